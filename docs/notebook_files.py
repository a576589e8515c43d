"""What the two notebook generators share (``docs/gen_notebooks.py`` for the docs' pages,
``examples/gen_notebooks.py`` for the gallery): a cell, the notebook's text, and writing
the notebooks or, with ``--check``, listing those out of date."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from pathlib import Path


def cell(kind: str, source: str) -> dict[str, object]:
    """A Markdown or code cell without outputs."""
    made: dict[str, object] = {"cell_type": kind, "metadata": {}, "source": source.strip("\n")}
    if kind == "code":
        made.update(execution_count=None, outputs=[])
    return made


def notebook_text(cells: list[dict[str, object]], source: str, generator: str) -> str:
    """The notebook as written (nbformat 4, cells numbered), naming where it comes from."""
    for number, each in enumerate(cells):
        each["id"] = f"cell-{number}"
    notebook = {
        "cells": cells,
        "metadata": {
            "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
            "mimics": {"source": source, "generator": generator},
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }
    return json.dumps(notebook, indent=1, ensure_ascii=False) + "\n"


def write_or_check(notebooks: Iterable[tuple[Path, str]], check: bool, generator: str,
                   root: Path, also_stale: Callable[[Path], bool] = lambda path: False) -> int:
    """Write each ``(path, text)``, or with ``check`` write nothing and list the notebooks
    (relative to ``root``) whose file differs or for which ``also_stale`` says so: status
    1 when any does."""
    stale = []
    for path, text in notebooks:
        if check:
            if not path.is_file() or path.read_text() != text or also_stale(path):
                stale.append(str(path.relative_to(root)))
        else:
            path.write_text(text)
    if stale:
        print(f"out of date (run python {generator}):", *stale, sep="\n  ")
        return 1
    return 0
