"""`mimics run` on a fresh install: the kernels are compiled before the timed run."""

import json

from typer.testing import CliRunner

from mimics.engine import ranger
from mimics.interfaces.cli import program as cli

runner = CliRunner()


def test_first_run_compiles_before_the_timed_simulation(tmp_path, monkeypatch):
    warmed = []
    monkeypatch.setattr(ranger, "kernels_cached", lambda: False)
    monkeypatch.setattr(cli, "_compile_kernels", lambda: warmed.append(True))
    out = tmp_path / "run"
    result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "2", "--time",
                                     "0.5", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "compiling the simulation kernels" in result.output
    assert warmed == [True]
    assert json.loads((out / "summary.json").read_text())["robots"] == 2


def test_warm_cache_says_nothing_about_compiling(tmp_path, monkeypatch):
    monkeypatch.setattr(ranger, "kernels_cached", lambda: True)
    result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "2", "--time",
                                     "0.5", "--out", str(tmp_path / "run")])
    assert result.exit_code == 0, result.output
    assert "compiling" not in result.output


def test_compile_kernels_runs_a_tiny_simulation():
    cli._compile_kernels()  # compiled already in this process: quick, and must not raise


def test_first_run_compile_leaves_the_ray_kernel_in_numbas_cache():
    """The compile runs robots without a ranger here and the scanning run in a second
    process; the ray kernel must then be in the disk cache the next run reads."""
    cli._compile_kernels()
    assert ranger.kernels_cached()
