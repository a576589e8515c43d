"""The fuzzer's second round on the Python API: ``simulate``, ``load_run``, ``save``,
``run_battery`` and ``show`` given values of every wrong type and finite but enormous
numbers, damaged run folders, and folders that alias what is saved.

The property, for every example: a result or one ``MimicsError`` line naming the
argument, never another exception; and nothing an example did not create changes.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mimics
from mimics.world.errors import MimicsError
from tests.fuzzing import (
    RUN_ALIASES,
    WRONG_TYPES,
    foreign_run_folder,
    make_run_folder,
    snapshot,
)

SIMULATE_ARGUMENTS = ["robots", "time", "seed", "policy", "out", "wall_limit", "params",
                      "observers", "record_scans", "allow_overlap"]
SHOW_ARGUMENTS = ["robots", "time", "seed", "params", "policy", "speed", "fps", "width_px",
                  "trail", "beams_of", "autoplay", "no_such_option"]
BATTERY_ARGUMENTS = ["out", "workers", "dask", "progress"]
ENORMOUS_NUMBERS = st.sampled_from([1e300, 1e308, -1e300, 1.7976931348623157e308, 2**63,
                                    10**400])
VALUES = st.sampled_from(WRONG_TYPES) | ENORMOUS_NUMBERS


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_run_folder(tmp_path_factory.mktemp("fuzz-api") / "run")


def one_line(exc: MimicsError, names: list[str]) -> None:
    message = str(exc)
    assert "\n" not in message and message.strip()
    assert any(name in message for name in names), message


@settings(max_examples=40, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(SIMULATE_ARGUMENTS), value=VALUES)
def test_simulate_takes_a_value_or_names_the_argument(name: str, value: Any) -> None:
    options: dict[str, Any] = {"robots": 2, "time": 0.3, name: value}
    with tempfile.TemporaryDirectory() as tmp:
        if name == "out" and isinstance(value, str) and value:
            options["out"] = Path(tmp) / value
        try:
            mimics.simulate("line", "go_to_goal", **options)
        except MimicsError as exc:
            one_line(exc, [name, "time", "robots", "scenario parameter"])


@settings(max_examples=25, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(SHOW_ARGUMENTS), value=VALUES)
def test_show_takes_a_value_or_names_the_argument(name: str, value: Any) -> None:
    try:
        mimics.show("line", "go_to_goal", widget=False, **{"robots": 2, "time": 0.3, name: value})
    except MimicsError as exc:
        one_line(exc, [name, "robot_beams", "time", "robots", "scenario parameter", "replay"])


@settings(max_examples=15, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(BATTERY_ARGUMENTS), value=st.sampled_from(WRONG_TYPES),
       key=st.sampled_from(["time", "timeout", "seeds", "record_every", "policy", "name"]),
       bad=VALUES)
def test_run_battery_refuses_before_creating_anything(
        name: str, value: Any, key: str, bad: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        monkeypatch.chdir(tmp)
        spec = {"battery": {"algorithms": ["go_to_goal"], "seeds": 1, "time": 0.3, key: bad},
                "scenarios": [{"name": "line", "robots": 2}]}
        with pytest.raises(MimicsError) as error:  # the bad key or the bad argument
            mimics.run_battery(spec, **{name: value})
        one_line(error.value, [name, key])
        assert list(Path(tmp).iterdir()) == []


@settings(max_examples=12, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(alias=st.sampled_from(RUN_ALIASES), memory=st.booleans())
def test_save_into_what_it_saves_or_a_run_s_records_is_refused(
        run_folder: Path, alias: str, memory: bool) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = shutil.copytree(run_folder, Path(tmp) / "run")
        view = mimics.simulate("line", "go_to_goal", robots=2, time=0.3) if memory else \
            mimics.load_run(folder)
        target = Path(alias.format(run=folder, name="run"))
        before = snapshot(folder)
        if memory and target == folder:
            view.save(target)  # an earlier run's folder: replaced, as documented
            return
        with pytest.raises(MimicsError):
            view.save(target)
        assert snapshot(folder) == before


@settings(max_examples=10, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(value=st.sampled_from(WRONG_TYPES), damaged=st.booleans())
def test_load_run_names_the_path_or_the_damaged_file(run_folder: Path, value: Any,
                                                    damaged: bool) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        if damaged:
            folder = foreign_run_folder(run_folder, Path(tmp) / "foreign")
            with pytest.raises(MimicsError, match=r"trajectory\.parquet: not the table"):
                mimics.load_run(folder)
        with pytest.raises(MimicsError, match=r"^load_run: path: expected a path"):
            mimics.load_run(value)
