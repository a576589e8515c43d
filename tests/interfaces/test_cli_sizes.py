"""Finite but enormous sizes and times on the command line meet the limits of
``mimics.world.limits`` at once (exit 2, one line), before any image is allocated or any
run starts."""

from __future__ import annotations

from pathlib import Path

import pytest

from mimics.interfaces.cli import main
from tests.fuzzing import map_files


@pytest.mark.parametrize("argv", [
    ["map", "show", "{maps}/room.toml", "--out", "{tmp}/m.png", "--width", "8000"],
    ["map", "show", "{maps}/room.toml", "--out", "{tmp}/m.png", "--width", "1e300"],
    ["run", "line", "go_to_goal", "--robots", "2", "--time", "1e300"],
    ["run", "line", "go_to_goal", "--robots", "2", "--time", "1e12"],
    ["run", "line", "go_to_goal", "--robots", "2", "--time", "0.3", "--wall-limit", "1e300"],
    ["plot", "{tmp}/run", "--width", "100000"],
    ["battery", "new", "-a", "go_to_goal", "-s", "line", "--timeout", "1e12", "--no-input",
     "-o", "{tmp}/b.toml"],
], ids=lambda argv: " ".join(argv[:2] + argv[-2:]))
def test_enormous_sizes_and_times_are_refused_in_one_line(
        argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    map_files(tmp_path / "maps")
    line = [a.format(maps=tmp_path / "maps", tmp=tmp_path) for a in argv]
    assert main(line) == 2
    errors = [e for e in capsys.readouterr().err.splitlines() if e.strip()]
    assert len(errors) == 1 and errors[0].startswith("mimics: error: "), errors
    option = next(a for a in reversed(argv) if a.startswith("--") and a != "--no-input")
    assert option in errors[0], errors[0]
    assert not (tmp_path / "m.png").exists() and not (tmp_path / "b.toml").exists()
    assert not (tmp_path / "runs").exists()  # no run started


def test_a_map_at_its_largest_width_is_still_drawn(tmp_path: Path) -> None:
    map_files(tmp_path / "maps")
    assert main(["map", "show", str(tmp_path / "maps" / "room.toml"), "--out",
                 str(tmp_path / "m.png"), "--width", "20"]) == 0
    assert (tmp_path / "m.png").stat().st_size > 0
