"""Every test that needs the Stage data guards itself: without the data it skips, saying why.

A fresh clone has no ``../shared/data`` and no downloaded Stage files; there
the suite must pass, with the Stage tests skipped by ``tests.stage`` (which
fails them instead on CI, where the data is always beside the clone). This
file finds, by reading the test files, every test that names a Stage scenario
(``"cave"``, ``"hospital"``, or their modules ``mimics.scenarios.cave``...), a
Stage map (``"stage:..."``) or a Stage file, directly, through a module
constant or helper, or through a fixture of its module; then runs those tests
in a child pytest whose data folder is an empty folder, and requires each one
to pass or to skip with the way to get the data.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from mimics.catalog import load_scenario
from mimics.world.errors import MimicsError
from tests.stage import REAL_DATA_VAR, STAGE_SCENARIOS, stage_file

ROOT = Path(__file__).resolve().parents[2]
TESTS = ROOT / "tests"
STAGE_FILES = {file for files in STAGE_SCENARIOS.values() for file in files} | {
    "cave.png", "hospital_section.png"}
KNOWN_STAGE_TEST = "test_runs_are_the_same_with_the_lists_and_without[hospital"


def names_stage_data(text: str) -> bool:
    """Whether a string constant of a test names Stage data."""
    return text in STAGE_SCENARIOS or text in STAGE_FILES or text.startswith("stage:")


def _strings_and_names(nodes: list[ast.AST]) -> tuple[bool, set[str]]:
    """Whether the nodes hold a Stage string, and the names they use."""
    stage, names = False, set()
    for node in nodes:
        for sub in ast.walk(node):
            if isinstance(sub, ast.Constant) and isinstance(sub.value, str):
                stage = stage or names_stage_data(sub.value)
            elif isinstance(sub, ast.Name):
                names.add(sub.id)
                stage = stage or sub.id in STAGE_SCENARIOS  # mimics.scenarios.cave, imported
            elif isinstance(sub, ast.Attribute):
                stage = stage or sub.attr in STAGE_SCENARIOS
            elif isinstance(sub, ast.arg):
                names.add(sub.arg)  # a fixture, by its parameter name
    return stage, names


def stage_tests(path: Path) -> tuple[list[str], list[str]]:
    """The module's tests that touch Stage data: (whole tests, tests parametrized over it).

    The second list holds tests that name Stage data only in their decorators (a
    ``parametrize`` over scenarios): only their Stage cases need the data.
    """
    tree = ast.parse(path.read_text(encoding="utf-8"))
    parts: dict[str, tuple[list[ast.AST], list[ast.AST]]] = {}  # name: (body, decorators)
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            parts[node.name] = ([node.args, *node.body], list(node.decorator_list))
        elif isinstance(node, ast.Assign) and node in tree.body:
            for target in node.targets:
                if isinstance(target, ast.Name):
                    parts[target.id] = ([node.value], [])
    touching: set[str] = set()
    changed = True
    while changed:  # a name touches Stage data if it names it or uses a name that does
        changed = False
        for name, (body, decorators) in parts.items():
            if name in touching:
                continue
            stage, used = _strings_and_names(body + decorators)
            if stage or used & touching:
                touching.add(name)
                changed = True
    whole, parametrized = [], []
    for name in sorted(touching):
        if not name.startswith("test_") or name not in parts:
            continue
        stage, used = _strings_and_names(parts[name][0])
        (whole if stage or (used - {name}) & touching else parametrized).append(name)
    return whole, parametrized


def test_the_finder_sees_stage_names_in_bodies_constants_helpers_and_parametrize(
        tmp_path: Path) -> None:
    module = tmp_path / "test_sample.py"
    module.write_text(
        'import pytest\nBIG = ["hospital"]\n'
        'def helper():\n    return load_map("stage:cave")\n'
        'def test_direct():\n    load_scenario("cave")\n'
        'def test_constant():\n    run(BIG)\n'
        'def test_helper():\n    helper()\n'
        '@pytest.fixture\ndef world():\n    return "cave.world"\n'
        'def test_fixture(world):\n    pass\n'
        '@pytest.mark.parametrize("name", ["line", "hospital"])\n'
        'def test_some(name):\n    run(name)\n'
        'def test_module():\n    hospital.scenario(robots=3)\n'
        'def test_plain():\n    load_scenario("line")\n')
    assert stage_tests(module) == (["test_constant", "test_direct", "test_fixture",
                                    "test_helper", "test_module"], ["test_some"])


def test_every_stage_test_skips_with_the_reason_when_the_data_is_missing(
        tmp_path: Path) -> None:
    whole: list[str] = []
    parametrized: list[str] = []
    for path in sorted(TESTS.rglob("test_*.py")):
        if path.resolve() == Path(__file__).resolve():
            continue
        found = stage_tests(path)
        module = path.relative_to(ROOT).as_posix()
        whole += [f"{module}::{name}" for name in found[0]]
        parametrized += [f"{module}::{name}" for name in found[1]]
    assert any(KNOWN_STAGE_TEST.startswith(node.split("::")[1]) for node in parametrized)
    # only the Stage cases of the parametrized tests: ids naming a Stage scenario
    only = " or ".join(node.split("::")[1] for node in parametrized)
    keep = f"not ({only}) or " + " or ".join(STAGE_SCENARIOS)
    empty = tmp_path / "no-data"
    empty.mkdir()
    env = {key: value for key, value in os.environ.items() if key != "CI"}
    env["MIMICS_DATA"] = str(empty)  # before the user folder and ../shared/data
    env[REAL_DATA_VAR] = str(empty)  # what the guards give back: nothing either
    report = tmp_path / "report.xml"
    child = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:randomly",
         "-k", keep, f"--junitxml={report}", "--basetemp", str(tmp_path / "child"),
         *whole, *parametrized],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=900)
    assert report.is_file(), child.stdout[-3000:] + child.stderr[-3000:]
    unguarded, skipped = [], []
    for case in ET.parse(report).getroot().iter("testcase"):
        name = f"{case.get('classname')}::{case.get('name')}"
        for bad in (*case.findall("failure"), *case.findall("error")):
            unguarded.append(f"{name}: {(bad.get('message') or '')[:300]}")
        for skip in case.findall("skipped"):
            reason = skip.get("message") or ""
            if "mimics data get stage" not in reason:
                unguarded.append(f"{name}: skipped for another reason: {reason[:300]}")
            skipped.append(case.get("name") or "")
    assert not unguarded, ("tests that need the Stage data and do not skip without it "
                           "(guard them with tests.stage.stage_file or "
                           "needs_stage_scenario):\n" + "\n".join(unguarded))
    assert any(name.startswith(KNOWN_STAGE_TEST) for name in skipped), skipped
    assert child.returncode == 0, child.stdout[-3000:]


ESCAPE = """
from mimics.catalog import load_scenario
load_scenario("cave", robots=2)
"""


def test_a_test_that_reaches_the_data_without_its_guard_fails_here_as_on_a_fresh_clone(
        ) -> None:
    # in the test's own process...
    with pytest.raises(MimicsError, match="mimics data get stage"):
        load_scenario("cave", robots=2)
    # ...and in a process it starts, which inherits the hidden data folder
    child = subprocess.run([sys.executable, "-c", ESCAPE], cwd=ROOT, capture_output=True,
                           text=True, timeout=120, check=False)
    assert child.returncode != 0 and "mimics data get stage" in child.stderr


def test_the_guard_gives_the_data_back_to_its_test_and_its_children() -> None:
    stage_file("cave_filled.png")  # skips here when no data folder holds it
    assert load_scenario("cave", robots=2).robot_count == 2
    child = subprocess.run([sys.executable, "-c", ESCAPE], cwd=ROOT, capture_output=True,
                           text=True, timeout=120, check=False)
    assert child.returncode == 0, child.stderr[-2000:]
