"""`mimics run` without --out never replaces an earlier run: two scenarios with one name, or
one scenario run twice, leave two folders, and the command says which one it wrote."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

import mimics
from mimics.interfaces.cli import program as cli

runner = CliRunner()
SCENARIO = """\
name = "line"
map = {{ segments = [[0,0,8,0], [8,0,8,4], [8,4,0,4], [0,4,0,0]], bounds = [0, 0, 8, 4] }}
robots = [{{ type = "Pioneer2DX", x = {x}, y = 2.0, yaw = 0.0, goal = [6.0, 2.0] }}]
"""


def test_a_second_run_of_the_same_name_gets_a_new_folder(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    for name, x in (("a.toml", 2.0), ("b.toml", 3.0)):
        (tmp_path / name).write_text(SCENARIO.format(x=x))
    monkeypatch.chdir(tmp_path)
    outputs = []
    for name in ("a.toml", "b.toml"):
        result = runner.invoke(cli.app, ["run", name, "go_to_goal", "--time", "0.5",
                                         "--seed", "2"])
        assert result.exit_code == 0, result.output
        outputs.append(result.output)
    assert "records in runs/line-go_to_goal-s2\n" in outputs[0]
    assert "records in runs/line-go_to_goal-s2-2\n" in outputs[1]
    starts = [mimics.load_run(tmp_path / "runs" / folder).trajectory.iloc[0]["x"]
              for folder in ("line-go_to_goal-s2", "line-go_to_goal-s2-2")]
    assert starts == [2.0, 3.0]  # each folder holds its own scenario's run
    again = runner.invoke(cli.app, ["run", "a.toml", "go_to_goal", "--time", "0.5", "--seed",
                                    "2", "--out", "runs/line-go_to_goal-s2"])
    assert again.exit_code == 0 and "records in runs/line-go_to_goal-s2\n" in again.output
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == [
        "line-go_to_goal-s2", "line-go_to_goal-s2-2"]  # --out names the folder to replace
