"""The API's request bodies are strict: an unknown key is refused, never ignored.

A typo (``{"seeed": 5}``) silently ignored runs something else than asked
(seed 0); so every body model of the workbench derives from :class:`StrictBody`,
which answers 422 naming the key and the keys known, and the routes that take
no fields (Pause, Step...) refuse a body that has some (:func:`no_fields`).

>>> class Start(StrictBody):
...     seed: int = 0
>>> Start.model_validate({"seeed": 5})
Traceback (most recent call last):
...
pydantic_core._pydantic_core.ValidationError: 1 validation error for Start
  seeed: unknown field (expected seed) [type=unknown_field, ...]
"""

from __future__ import annotations

import json
from typing import Any

from fastapi import HTTPException, Request
from pydantic import BaseModel, ConfigDict, model_validator
from pydantic_core import PydanticCustomError


class StrictBody(BaseModel):
    """A request body whose unknown keys are refused (the error type ``unknown_field``)."""

    model_config = ConfigDict(extra="forbid")

    @model_validator(mode="before")
    @classmethod
    def _known_keys_only(cls, data: Any) -> Any:
        if isinstance(data, dict):
            unknown = [key for key in data if key not in cls.model_fields]
            if unknown:
                raise PydanticCustomError(
                    "unknown_field", "{key}: unknown field (expected {known})",
                    {"key": str(unknown[0])[:80], "known": ", ".join(cls.model_fields)})
        return data


async def no_fields(request: Request) -> None:
    """A dependency of the routes that take no body: none, ``{}`` or ``null`` is fine,
    anything else 422 (a field sent there is a mistake the caller should hear of)."""
    body = await request.body()
    if not body.strip():
        return
    try:
        data = json.loads(body)
    except ValueError:
        raise HTTPException(422, "body: expected none (this action takes no fields)") from None
    if data is None or data == {}:
        return
    if isinstance(data, dict):
        key = str(next(iter(data)))[:80]
        raise HTTPException(422, f"{key}: unknown field (this action takes no fields)")
    raise HTTPException(422, f"body: expected none (this action takes no fields), got "
                             f"{type(data).__name__}")
