"""summary.json: the machine-readable outcome of one run."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from mimics.engine.outcome import RunResult


def write_json_atomic(path: Path, data: Any) -> None:
    """Write JSON through a temporary file and a rename, so readers never see half a file."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=2, default=_jsonable) + "\n")
    os.replace(tmp, path)


def _jsonable(value: Any) -> Any:
    if hasattr(value, "item"):
        return value.item()
    if hasattr(value, "tolist"):
        return value.tolist()
    return str(value)


def write_summary(result: RunResult, folder: Path, extra: dict[str, Any] | None = None) -> Path:
    """Write ``summary.json`` for ``result`` into ``folder``; returns its path."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "summary.json"
    write_json_atomic(path, {**result.summary(), **(extra or {})})
    return path
