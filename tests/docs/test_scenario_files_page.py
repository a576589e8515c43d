"""The how-to "Write a scenario file": the error it quotes is the one mimics prints for the
file the page builds, with the mistake the page names (issue 54: the quote had fallen behind
the message)."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import pytest

from mimics.interfaces.cli import main

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "how-to" / "scenario-files.md"
TOML_BLOCK = re.compile(r"```toml\n(.*?)```", re.S)


def quoted_error(page: str) -> str:
    """The page's quoted ``mimics: error: ...`` line, its wrapping undone."""
    found = re.search(r"`(mimics: error: .*?)`", page, re.S)
    assert found is not None, "the page quotes no error"
    return " ".join(found[1].split())


def test_the_quoted_error_is_what_mimics_prints_for_the_pages_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    page = PAGE.read_text()
    # the first three blocks saved one after the other, as step 4 says, the second start
    # mistyped
    blocks = [textwrap.dedent(block) for block in TOML_BLOCK.findall(page)[:3]]
    text = "\n".join(blocks)
    assert text.count("start = [8.0, 1.5]") == 1
    (tmp_path / "doorway.toml").write_text(text.replace("start = [8.0, 1.5]",
                                                        "strat = [8.0, 1.5]"))
    monkeypatch.chdir(tmp_path)
    capsys.readouterr()
    assert main(["run", "doorway.toml", "wall_aware", "--time", "0.1"]) == 2
    printed = " ".join(capsys.readouterr().err.split())
    assert printed == quoted_error(page)
    assert "exit status 2" in page


def test_the_pages_file_without_the_mistake_runs(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    blocks = [textwrap.dedent(block) for block in TOML_BLOCK.findall(PAGE.read_text())[:3]]
    (tmp_path / "doorway.toml").write_text("\n".join(blocks))
    monkeypatch.chdir(tmp_path)
    assert main(["run", "doorway.toml", "wall_aware", "--time", "0.5", "--out", "run",
                 "--robot-logs", "off"]) == 0
