"""The code blocks of docs/how-to/learning-environments.md run, in order, as one script."""

from __future__ import annotations

import re
from pathlib import Path

PAGE = Path(__file__).parents[3] / "docs" / "how-to" / "learning-environments.md"


def test_the_pages_python_blocks_run(capsys: object) -> None:
    blocks = re.findall(r"```python\n(.*?)```", PAGE.read_text(encoding="utf-8"), re.DOTALL)
    assert len(blocks) >= 5
    namespace: dict[str, object] = {"__name__": "docs_page"}
    exec(compile("\n".join(blocks), str(PAGE), "exec"), namespace)
    out = capsys.readouterr().out.splitlines()  # type: ignore[attr-defined]
    assert out[0] == "['robot_0', 'robot_1', 'robot_2'] 8"
    assert out[1] == "(277,)"
    assert out[2] == "[20.  0.]"
