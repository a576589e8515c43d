"""The docs' notebooks: made from their Markdown pages, and run on a real Jupyter kernel.

Each notebook is executed by nbclient with the python3 kernel (ipykernel of
this environment) in a temporary folder, as a reader would run it, and its
outputs are checked against what the page says and what the run folders hold:
a figure of the right size, a replay with the frame count of its run's length,
a DataFrame with one row per arrival.
"""

from __future__ import annotations

import base64
import importlib.util
import json
import math
import os
import re
import shutil
import sys
from pathlib import Path

import imageio.v3 as imageio
import nbclient
import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[3]
DOCS = ROOT / "docs"


def load_generator():
    spec = importlib.util.spec_from_file_location("gen_notebooks", DOCS / "gen_notebooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gen = load_generator()


def test_committed_notebooks_are_those_their_pages_make():
    assert gen.main(["--check"]) == 0, "run: python docs/gen_notebooks.py"
    assert len(gen.PAGES) >= 3 and sum(p.startswith("how-to/") for p in gen.PAGES) >= 2


def test_check_fails_once_a_page_changes(tmp_path, monkeypatch, capsys):
    copy = tmp_path / "docs"
    shutil.copytree(DOCS, copy, ignore=shutil.ignore_patterns("images", "profiles"))
    monkeypatch.setattr(gen, "DOCS", copy)
    monkeypatch.setattr(gen, "SNIPPETS", copy / "snippets")
    assert gen.main(["--check"]) == 0
    page = copy / "tutorials/first-algorithm.md"
    page.write_text(page.read_text().replace("10 minutes", "ten minutes"))
    assert gen.main(["--check"]) == 1
    assert "first-algorithm-notebook.ipynb" in capsys.readouterr().out
    assert gen.main([]) == 0 and gen.main(["--check"]) == 0  # one command brings it back
    text = (copy / "tutorials/first-algorithm-notebook.ipynb").read_text()
    assert "ten minutes" in text


def execute(page: str, folder: Path) -> nbformat.NotebookNode:
    """Run ``page``'s committed notebook in ``folder`` on a python3 kernel."""
    notebook = nbformat.read(gen.notebook_path(page), as_version=4)
    nbformat.validate(notebook)
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(folder)}})
    client.execute()
    return notebook


@pytest.fixture
def kernel_env(monkeypatch):
    # the notebooks' `!mimics ...` cells find this environment's command, as in a
    # Jupyter started from an activated venv
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")


def outputs_of(notebook: nbformat.NotebookNode, source_start: str) -> list[dict]:
    cells = [c for c in notebook.cells if c.cell_type == "code"
             and c.source.startswith(source_start)]
    assert len(cells) == 1, source_start
    return cells[0].outputs


def png_of(outputs: list[dict]):
    data = [o["data"]["image/png"] for o in outputs if "image/png" in o.get("data", {})]
    assert len(data) == 1
    return imageio.imread(base64.b64decode(data[0]))


def replay_frames(outputs: list[dict]) -> tuple[int, int]:
    """The replay's declared frame count and the frames decoded from its video."""
    html = next(o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {}))
    declared = int(re.search(r'data-frames="(\d+)"', html).group(1))
    video = base64.b64decode(re.search(r'base64,([^"]+)"', html).group(1))
    return declared, imageio.imread(video, index=None, extension=".mp4").shape[0]


def frames_for(sim_time: float, fps: float, speed: float) -> int:
    step = speed / fps
    whole = math.floor(sim_time / step + 1e-9)
    return whole + 1 + (sim_time - whole * step > 1e-9)


def test_first_algorithm_notebook_runs_and_shows_runs_plots_and_replays(tmp_path, kernel_env):
    notebook = execute("tutorials/first-algorithm.md", tmp_path)
    # the CLI cells wrote what the page says
    assert (tmp_path / "my_algo.py").is_file() and (tmp_path / "runs/two/summary.json").is_file()
    # the run in the cell: its summary table and its figure
    shown = outputs_of(notebook, "import mimics\n\nrun = mimics.simulate")[0]["data"]
    assert "mimics-summary" in shown["text/html"] and "data:image/png" in shown["text/html"]
    # the arrivals: one row per robot, all ten reached their goal (as the page says)
    events = outputs_of(notebook, 'run.events[run.events["kind"]')[0]["data"]["text/html"]
    body = events.split("<tbody>")[1].split("</tbody>")[0]
    assert body.count("<tr>") == 10 and body.count("reached_goal") == 10
    # mimics plot's figure, 1000 x 800
    assert png_of(outputs_of(notebook, "import mimics\n\nmine = ")).shape[:2] == (800, 1000)
    # the replay: frames every 0.4 s of the run, from its summary.json
    mine = json.loads((tmp_path / "runs/mine/summary.json").read_text())
    declared, decoded = replay_frames(outputs_of(notebook, "mine.animate("))
    assert declared == decoded == frames_for(mine["sim_time"], fps=10, speed=4)


def test_replay_how_to_notebook_runs(tmp_path, kernel_env):
    notebook = execute("how-to/replay-video.md", tmp_path)
    assert (tmp_path / "mine.mp4").stat().st_size > 0 and (tmp_path / "mine.gif").is_file()
    declared, decoded = replay_frames(outputs_of(notebook, "run.animate("))
    assert declared == decoded == frames_for(40.0, fps=10, speed=4) == 101
    assert png_of(outputs_of(notebook, "run.plot()")).shape[:2] == (800, 1000)


def test_team_form_how_to_notebook_runs(tmp_path, kernel_env):
    notebook = execute("how-to/team-form.md", tmp_path)
    printed = "".join(o.get("text", "") for o in outputs_of(notebook, "import mimics\n\nper_robot"))
    assert "identical trajectories: True" in printed
    assert png_of(outputs_of(notebook, "team.plot()")).shape[:2] == (800, 1000)


def load_examples_generator():
    spec = importlib.util.spec_from_file_location("examples_gen",
                                                  ROOT / "examples" / "gen_notebooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_gallery_example_links_its_up_to_date_notebook():
    examples = load_examples_generator()
    assert examples.main(["--check"]) == 0, "run: python examples/gen_notebooks.py"
    for name in examples.EXAMPLES:
        assert "](notebook.ipynb)" in (ROOT / "examples" / name / "README.md").read_text()
        nbformat.validate(nbformat.read(ROOT / "examples" / name / "notebook.ipynb", 4))


def test_go_to_goal_example_notebook_runs_in_its_folder(kernel_env):
    folder = ROOT / "examples" / "go_to_goal"
    before = sorted(p.name for p in folder.iterdir())
    notebook = nbformat.read(folder / "notebook.ipynb", as_version=4)
    nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(folder)}}).execute()
    assert sorted(p.name for p in folder.iterdir()) == before  # a run in memory writes nothing
    html = outputs_of(notebook, "import mimics")[0]["data"]["text/html"]
    steps = int(re.search(r"simulated time</th><td[^>]*>[\d.]+ s \((\d+) steps", html).group(1))
    sim_time = round(steps * 0.1, 9)  # the line's steps are 0.1 s
    # the README: all 10 robots reach their goals, well before the 40 s limit
    assert "reached goal</th><td style=\"text-align:left\">10<" in html and sim_time < 40
    declared, decoded = replay_frames(outputs_of(notebook, "run.animate()"))
    # by default at most 201 frames: real time if it fits, else 2x (enough below 40 s)
    speed = 1 if frames_for(sim_time, 10, 1) <= 201 else 2
    assert declared == decoded == frames_for(sim_time, fps=10, speed=speed)
    counts = outputs_of(notebook, "run.events")[0]["data"]["text/html"]
    assert re.search(r"<th>reached_goal</th>\s*<td>10</td>", counts)


def test_run_battery_draws_its_progress_bar_in_the_cell(tmp_path, kernel_env):
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(
        "import mimics\n"
        "spec = {'battery': {'algorithms': ['go_to_goal'], 'seeds': 2, 'time': 1.0},\n"
        "        'scenarios': [{'name': 'line', 'robots': 2}]}\n"
        "battery = mimics.run_battery(spec, 'night', workers=1)\nbattery")]
    nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}},
                            store_widget_state=True).execute()
    outputs = notebook.cells[0].outputs
    views = [o["data"]["application/vnd.jupyter.widget-view+json"]["model_id"] for o in outputs
             if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(views) == 1  # tqdm's bar: one widget in the cell, moved in place
    state = notebook.metadata["widgets"]["application/vnd.jupyter.widget-state+json"]["state"]
    bars = [m["state"] for m in state.values() if m["model_name"] == "FloatProgressModel"]
    assert len(bars) == 1 and bars[0]["value"] == bars[0]["max"] == 2  # both runs, at the end
    texts = [m["state"]["value"] for m in state.values() if m["model_name"] == "HTMLModel"]
    assert any("2/2" in text for text in texts) and any("failed=0" in text for text in texts)
    assert "night: 2 runs (2 done)" in outputs[-1]["data"]["text/html"]
    assert (tmp_path / "night" / "battery.db").is_file()
