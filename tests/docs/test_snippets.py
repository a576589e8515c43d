"""Every code block of the tutorials is a file in docs/snippets/, and every one of them runs.

Shell snippets are run line by line through the CLI's entry function in a
temporary folder (as a reader would, from the folder holding the files the
tutorial asks them to write); Python snippets are executed there too.
"""

import json
import re
import runpy
import shlex
import tomllib
from pathlib import Path

from mimics.interfaces.cli import main

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
    two = json.loads((tmp_path / "runs/two/summary.json").read_text())
    assert (two["robots"], two["reached_goal"]) == (2, 2)
    wide = json.loads((tmp_path / "runs/wide/summary.json").read_text())
    assert wide["robots"] == 6 and wide["parameters"]["width"] == 4.0


def test_first_battery_tutorial_runs(tmp_path, monkeypatch, capsys):
    page = ROOT / "docs/tutorials/first-battery.md"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "battery.toml").write_text((SNIPPETS / "first_battery/battery.toml").read_text())
    for snippet in included(page):
        if snippet.endswith(".sh"):
            run_shell(snippet)
        elif snippet.endswith("read_table.py"):
            namespace = runpy.run_path(str(SNIPPETS / snippet), run_name="__main__")
    table = namespace["table"]
    assert len(table) == 12 and set(table["state"]) == {"done"}
    means = namespace["means"]
    assert means["go_to_goal"].tolist() == [4.0, 6.0]  # everyone collides driving straight
    assert means["wall_aware"].tolist() == [0.0, 0.0]
    assert (tmp_path / "night-plots/outcomes.png").is_file()
    capsys.readouterr()

