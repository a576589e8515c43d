"""A notebook on a real kernel (nbclient, ipykernel): a bug raises at its cell, with the cell
and line of the bug; ``run.scenario`` gives distances to goals; a battery of a function
defined in a cell runs again from a second call (issue 51)."""

from __future__ import annotations

import re

import nbclient
import nbformat
import pytest

CELLS = [
    # 1
    "import math\nimport numpy as np\nimport mimics",
    # 2: the bug is on line 3 of this cell
    "def bad_step(robot):\n    x, y, theta = robot.pose\n    return 1.0 / 0, theta",
    # 3
    "run = mimics.simulate('line', bad_step, robots=2, time=1.0, seed=1)",
    # 4: Run All stops at 3; run on its own, this cell catches and keeps the run
    "try:\n    mimics.simulate('line', bad_step, robots=2, time=1.0, seed=1)\n"
    "except mimics.UserCodeError as error:\n    caught = error\n"
    "print(caught.run.status, type(caught.__cause__).__name__)\nprint(caught)",
    # 5: the errored run shown: its error first
    "mimics.simulate('line', bad_step, robots=2, time=1.0, seed=1, on_error='record')",
    # 6: the first analysis, distance to goal
    "run = mimics.simulate('circle_swap', 'go_to_goal', time=2.0, seed=1)\n"
    "last = run.trajectory[run.trajectory.step == run.trajectory.step.max()]"
    ".sort_values('robot')\n"
    "goals = run.scenario.goals\n"
    "distance = np.hypot(last.x.to_numpy() - goals[:, 0], last.y.to_numpy() - goals[:, 1])\n"
    "print(type(run.scenario).__name__, len(distance), bool(np.all(distance >= 0)))",
    # 7: a battery of a function defined here, twice
    "def toward(robot):\n    x, y, theta = robot.pose\n    gx, gy = robot.goal\n"
    "    return 0.5, math.atan2(gy - y, gx - x)\n"
    "spec = {'battery': {'algorithms': [toward], 'seeds': 2, 'time': 1.0},\n"
    "        'scenarios': [{'name': 'line', 'robots': 2}]}\n"
    "first = mimics.run_battery(spec, 'b', workers=1, progress=False)\n"
    "print(first.counts, first.result.finished)",
    # 8
    "second = mimics.run_battery(spec, 'b', workers=1, progress=False)\n"
    "print(second.counts, second.result.finished, sorted(set(second.table.algorithm)))",
]

ANSI = re.compile(r"\x1b\[[0-9;]*m")


@pytest.fixture(scope="module")
def notebook(tmp_path_factory: pytest.TempPathFactory) -> nbformat.NotebookNode:
    folder = tmp_path_factory.mktemp("cells")
    book = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in CELLS])
    # every cell runs (the error of cell 3 is checked in its outputs, as Run All shows it)
    client = nbclient.NotebookClient(book, timeout=300, kernel_name="python3",
                                     allow_errors=True,
                                     resources={"metadata": {"path": str(folder)}})
    client.execute()
    return book


def text_of(cell: nbformat.NotebookNode) -> str:
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")


def test_a_bug_in_a_cell_raises_at_the_cell_that_runs_it_naming_the_bugs_cell_and_line(
        notebook: nbformat.NotebookNode) -> None:
    errors = [o for o in notebook.cells[2].outputs if o.output_type == "error"]
    assert len(errors) == 1 and errors[0].ename == "UserCodeError"
    shown = ANSI.sub("", "\n".join(errors[0].traceback))
    # the cause: ZeroDivisionError in cell 2 (In[2]), line 3; then the cell that ran it
    assert "ZeroDivisionError" in shown
    assert re.search(r"Cell In\[2\], line 3", shown), shown
    assert "return 1.0 / 0, theta" in shown
    assert re.search(r"Cell In\[3\], line 1", shown), shown
    # the message names the cell, not ipykernel's temporary file
    assert "Cell In[2], line 3: float division by zero" in errors[0].evalue
    assert "ipykernel_" not in errors[0].evalue
    for cell in notebook.cells[3:]:  # only the cell of the bug failed
        assert not [o for o in cell.outputs if o.output_type == "error"], cell.source


def test_the_error_keeps_the_run_and_its_cause(notebook: nbformat.NotebookNode) -> None:
    lines = text_of(notebook.cells[3]).splitlines()
    assert lines[0] == "error ZeroDivisionError"
    assert lines[1].startswith("ZeroDivisionError in robot 0 at t=0 s, Cell In[2], line 3")


def test_an_errored_run_shows_its_error_first_in_red(notebook: nbformat.NotebookNode) -> None:
    page = next(o for o in notebook.cells[4].outputs
                if o.output_type == "execute_result")["data"]["text/html"]
    error_at = page.index('class="mimics-error"')
    assert error_at < page.index("<table") and "color:#c00" in page
    assert "Cell In[2], line 3" in page[error_at:page.index("<table")]


def test_run_scenario_gives_the_distance_to_goal(notebook: nbformat.NotebookNode) -> None:
    assert text_of(notebook.cells[5]).strip() == "Scenario 8 True"


def test_a_battery_of_a_cells_function_runs_and_a_second_call_reloads_it(
        notebook: nbformat.NotebookNode) -> None:
    assert text_of(notebook.cells[6]).strip() == "{'done': 2} 2"
    assert text_of(notebook.cells[7]).strip() == "{'done': 2} 0 ['toward']"
