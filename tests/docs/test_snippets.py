"""Every code block of the tutorials is a file in docs/snippets/, and every one of them runs.

Shell snippets are run line by line through the CLI's entry function in a
temporary folder (as a reader would, from the folder holding the files the
tutorial asks them to write); Python snippets are executed there too.
"""

import json
import os
import re
import runpy
import shlex
import signal
import sqlite3
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import matplotlib.pyplot as plt
from PIL import Image

from mimics.interfaces.cli import main
from mimics.interfaces.plots import plot_run

ROOT = Path(__file__).resolve().parents[2]
SNIPPETS = ROOT / "docs" / "snippets"
TUTORIALS = sorted((ROOT / "docs" / "tutorials").glob("*.md"))
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```", re.S | re.M)
INCLUDE = re.compile(r'^--8<-- "([^"]+)"$')


def included(page: Path) -> list[str]:
    """The snippet paths the page's code blocks include, failing on any inline code block."""
    paths = []
    for body in FENCE.findall(page.read_text()):
        line = body.strip()
        found = INCLUDE.match(line)
        assert found and "\n" not in line, f"{page.name}: not a snippet include:\n{body}"
        paths.append(found.group(1))
    return paths


def run_shell(snippet: str) -> None:
    for line in (SNIPPETS / snippet).read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        words = shlex.split(line)
        assert words[0] == "mimics", f"{snippet}: not a mimics command: {line}"
        assert main(words[1:]) == 0, line


def test_tutorial_code_blocks_are_all_snippet_files():
    assert len(TUTORIALS) == 2
    for page in TUTORIALS:
        paths = included(page)
        assert paths, page.name
        for path in paths:
            assert (SNIPPETS / path).is_file(), f"{page.name}: missing snippet {path}"


def test_install_snippet_names_this_project():
    lines = (SNIPPETS / "first_algorithm/install.sh").read_text().splitlines()
    assert lines[0] == "python3 -m venv .venv"
    assert lines[1] == "source .venv/bin/activate"
    install = shlex.split(lines[2])
    assert install[:3] == ["pip", "install", "-e"]
    target = install[3]
    name, _, extras = target.partition("[")
    assert name == "."
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    for extra in filter(None, extras.rstrip("]").split(",")):
        assert extra in project["optional-dependencies"]
    assert "mimics" in project["scripts"]


def test_first_algorithm_tutorial_runs(tmp_path, monkeypatch, capsys):
    page = ROOT / "docs/tutorials/first-algorithm.md"
    monkeypatch.chdir(tmp_path)
    for name in ("my_algo.py", "two_robots.toml"):
        (tmp_path / name).write_text((SNIPPETS / "first_algorithm" / name).read_text())
    for snippet in included(page):
        if snippet.endswith(".sh") and not snippet.endswith("install.sh"):
            run_shell(snippet)
        elif snippet.endswith("read_run.py"):
            runpy.run_path(str(SNIPPETS / snippet), run_name="__main__")
    assert (tmp_path / "mine.png").stat().st_size > 10_000
    assert "reached their goal" in capsys.readouterr().out
    first = json.loads((tmp_path / "runs/first/summary.json").read_text())
    assert (first["robots"], first["reached_goal"]) == (10, 10)  # what the page says
    prose = " ".join(page.read_text().split())  # the numbers §2 quotes from the summary
    assert f"*time to goal* is the robots' mean, {first['time_to_goal']['mean']:.2f} s" in prose
    assert f"*simulated time* the moment the last one arrived and the run ended, " \
           f"{first['sim_time']:.2f} s" in prose
    assert first["sim_time"] == first["time_to_goal"]["max"]  # "the last one arrived"
    mine = json.loads((tmp_path / "runs/mine/summary.json").read_text())
    assert (mine["robots"], mine["robot_collisions"]) == (6, 6)  # the page: all six collide
    # the page's figure is this run's: docs/make_figures.py stamps the plot's title in it
    figure = plot_run(tmp_path / "runs/mine", None, width_px=720, height_px=560)
    with Image.open(ROOT / "docs/images/tutorial_my_algo.png") as image:
        stamped = image.text.get("Title")
    assert stamped == figure.axes[0].get_title(), "run python docs/make_figures.py --only tutorial"
    plt.close(figure)
    two = json.loads((tmp_path / "runs/two/summary.json").read_text())
    assert (two["robots"], two["reached_goal"]) == (2, 2)
    wide = json.loads((tmp_path / "runs/wide/summary.json").read_text())
    assert wide["robots"] == 6 and wide["parameters"]["width"] == 4.0


def done_runs(db: Path) -> dict[int, int]:
    """Run id -> attempts, of the runs a battery database lists as done."""
    if not db.is_file():
        return {}
    with sqlite3.connect(db) as connection:
        try:
            rows = connection.execute("SELECT id, attempts FROM runs WHERE state = 'done'")
            return dict(rows.fetchall())
        except sqlite3.OperationalError:  # the table is not there yet
            return {}


def run_then_kill(snippet: str, db: Path) -> dict[int, int]:
    """Start the snippet's battery, kill it (and its workers) once a run is done."""
    (line,) = [ln for ln in (SNIPPETS / snippet).read_text().splitlines() if ln.strip()]
    words = shlex.split(line)
    assert words[0] == "mimics"
    battery = subprocess.Popen([sys.executable, "-m", "mimics", *words[1:], "--no-progress"],
                               start_new_session=True, stdout=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while not done_runs(db) and battery.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)
    finally:
        if battery.poll() is None:
            os.killpg(battery.pid, signal.SIGKILL)
        battery.wait()
    return done_runs(db)


def test_first_battery_tutorial_runs(tmp_path, monkeypatch, capsys):
    page = ROOT / "docs/tutorials/first-battery.md"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "battery.toml").write_text((SNIPPETS / "first_battery/battery.toml").read_text())
    before_kill: dict[int, int] = {}
    for snippet in included(page):
        if snippet.endswith("run.sh"):
            before_kill = run_then_kill(snippet, tmp_path / "night/battery.db")
        elif snippet.endswith(".sh"):
            run_shell(snippet)
        elif snippet.endswith("read_table.py"):
            namespace = runpy.run_path(str(SNIPPETS / snippet), run_name="__main__")
    table = namespace["table"]
    assert len(table) == 12 and set(table["state"]) == {"done"}
    # the kill came with at least one run done; resume did not repeat those
    assert before_kill and len(before_kill) < 12
    attempts = dict(zip(table["id"], table["attempts"], strict=True))
    assert all(attempts[i] == n for i, n in before_kill.items())
    means = namespace["means"]
    assert means["go_to_goal"].tolist() == [4.0, 6.0]  # everyone collides driving straight
    assert means["wall_aware"].tolist() == [0.0, 0.0]
    reached = namespace["reached"]  # the page: wall_aware brings every robot home
    assert reached["go_to_goal"].tolist() == [0.0, 0.0]
    assert reached["wall_aware"].tolist() == [4.0, 6.0]
    for run in table[table.algorithm == "wall_aware"].itertuples():  # "about 38 s and 45 s"
        folder = Path(run.folder)  # relative to the folder the battery ran from
        goal = json.loads((folder / "summary.json").read_text())["time_to_goal"]
        assert abs(goal["mean"] - {4: 38, 6: 45}[run.param_robots]) <= 2
    # each seed is a run of its own (start jitter, laser noise): no two share a digest
    digests = [json.loads((Path(f) / "summary.json").read_text())["trajectory_digest"]
               for f in table["folder"]]
    assert len(set(digests)) == len(digests)
    assert (tmp_path / "night-plots/outcomes.png").is_file()
    assert (tmp_path / "night-plots/time_to_goal.png").is_file()
    assert (tmp_path / "night-plots/arrivals.png").is_file()
    capsys.readouterr()

