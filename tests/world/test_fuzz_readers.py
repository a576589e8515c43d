"""A fuzzer over every reader of the world layer and of battery files.

Each reader gets valid files damaged at random (truncated, bytes flipped or
replaced, emptied, garbage) and well-formed files with values of the wrong
type or at the edges (NaN, infinite, huge, negative, empty) or keys missing.
The property: the reader returns its object or raises one ``MimicsError``
line; no other exception, and no value that would break the engine later
(a non-finite coordinate, a count past the limits).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from mimics.batteries.spec import load_battery
from mimics.catalog import load_scenario
from mimics.world.errors import MimicsError
from mimics.world.limits import MAX_ROBOTS
from mimics.world.map_files import load_map
from mimics.world.maps import Map
from mimics.world.scenario import Scenario
from mimics.world.scenario_files import load_scenario_toml
from mimics.world.stage_worlds import read_stage_world
from tests.fuzzing import (
    BATTERY_TOML,
    EDGE_VALUES,
    SCENARIO_TOML,
    damaged_bytes,
    map_files,
    mutated_toml,
)

FUZZ = settings(max_examples=30, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])


def one_line_error(exc: MimicsError) -> None:
    message = str(exc)
    assert message and "\n" not in message, repr(message)


def sound_map(loaded: Map) -> None:
    assert np.all(np.isfinite(loaded.segments)) and np.all(np.isfinite(loaded.bounds))


def sound_scenario(scenario: Scenario) -> None:
    sound_map(scenario.map)
    assert 1 <= scenario.robot_count <= MAX_ROBOTS
    assert np.all(np.isfinite(scenario.stages))
    assert math.isfinite(scenario.settings.dt) and math.isfinite(scenario.settings.time_limit)


@FUZZ
@example(text=SCENARIO_TOML.replace('generator = "line"', "generator = [1.0]"))  # was TypeError
@given(text=st.one_of(mutated_toml(SCENARIO_TOML),
                      damaged_bytes(SCENARIO_TOML.encode()).map(
                          lambda b: b.decode("utf-8", "replace"))))
def test_scenario_toml_damaged_or_mistyped(tmp_path: Path, text: str) -> None:
    path = tmp_path / "scenario.toml"
    path.write_text(text, encoding="utf-8")
    try:
        sound_scenario(load_scenario_toml(path))
    except MimicsError as exc:
        one_line_error(exc)


@FUZZ
@given(data=damaged_bytes(SCENARIO_TOML.encode()))
def test_scenario_toml_raw_bytes(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "scenario.toml"
    path.write_bytes(data)  # possibly not UTF-8
    try:
        sound_scenario(load_scenario_toml(path))
    except MimicsError as exc:
        one_line_error(exc)


PYTHON_SCENARIOS = [
    "def scenario(robots=3):\n    raise RuntimeError('user bug')\n",
    "def scenario(robots=3:\n",
    "import numpy as np\ndef scenario(robots=3):\n    return np.zeros((10**7, 10**7))\n",
    "def scenario(robots=3):\n    return None\n",
    "scenario = 3\n",
    "raise SystemError('at import')\n",
    "def scenario(robots=3):\n    return [1, 2, 3]\n",
    "from mimics.world.maps import Map\nfrom mimics.world.scenario import Scenario\n"
    "from mimics.world.robot_types import PIONEER_2DX\n"
    "def scenario(robots=3, gap=1.0):\n"
    "    rows = [[gap * i, 0.0, 0.0, 0.0, gap * i, 5.0] for i in range(robots)]\n"
    "    return Scenario.from_matrix(rows, Map.empty((-5, -5, 50, 50)), PIONEER_2DX)\n",
]
PARAMETERS = st.dictionaries(st.sampled_from(["robots", "gap", "seed", "other"]),
                             st.one_of(st.sampled_from([0, -1, 2, 3, 2**64, 10**8]),
                                       st.floats(allow_nan=True, allow_infinity=True),
                                       st.text(max_size=3), st.booleans()),
                             max_size=2)


@FUZZ
@given(source=st.sampled_from(PYTHON_SCENARIOS), params=PARAMETERS)
def test_python_scenarios_that_fail_or_lie(tmp_path: Path, source: str,
                                           params: dict[str, object]) -> None:
    path = tmp_path / f"s{abs(hash((source, repr(params)))) % 10**8}.py"
    path.write_text(source)
    try:
        sound_scenario(load_scenario(path, **params))
    except MimicsError as exc:
        one_line_error(exc)


@pytest.fixture(scope="module")
def maps(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return map_files(tmp_path_factory.mktemp("maps"))


MAP_KINDS = ["plain", "toml", "json", "svg", "png", "pgm", "ros"]


@FUZZ
@given(kind=st.sampled_from(MAP_KINDS), data=st.data())
def test_map_files_of_every_kind_damaged(tmp_path: Path, maps: dict[str, Path], kind: str,
                                         data: st.DataObject) -> None:
    original = maps[kind]
    path = tmp_path / original.name
    path.write_bytes(data.draw(damaged_bytes(original.read_bytes()), label="bytes"))
    if kind == "ros":  # the image it names, next to it
        (tmp_path / "ros.pgm").write_bytes(
            data.draw(st.one_of(st.just((original.parent / "ros.pgm").read_bytes()),
                                damaged_bytes((original.parent / "ros.pgm").read_bytes())),
                      label="image"))
    try:
        sound_map(load_map(path))
    except MimicsError as exc:
        one_line_error(exc)


IMPORT_OPTIONS = st.fixed_dictionaries({}, optional={
    "resolution": st.floats(allow_nan=True, allow_infinity=True),
    "tolerance": st.floats(allow_nan=True, allow_infinity=True),
    "origin": st.tuples(st.floats(allow_nan=True), st.floats(allow_infinity=True)),
    "threshold": st.floats(allow_nan=True, allow_infinity=True),
})


@FUZZ
@given(kind=st.sampled_from(["png", "pgm", "svg", "stage"]), options=IMPORT_OPTIONS,
       size=st.tuples(st.floats(allow_nan=True, allow_infinity=True),
                      st.floats(min_value=-1e300, max_value=1e300)))
def test_map_import_options_at_the_edges(maps: dict[str, Path], kind: str,
                                         options: dict[str, object],
                                         size: tuple[float, float]) -> None:
    if kind == "svg":
        options = {k: v for k, v in options.items() if k == "tolerance"}
        options["scale"] = size[0]
    if kind == "stage":
        options = {k: v for k, v in options.items() if k == "tolerance"}
        options["size"] = size
    try:
        sound_map(load_map(maps["svg" if kind == "svg" else "png" if kind == "stage" else kind],
                           **options))
    except MimicsError as exc:
        one_line_error(exc)


@FUZZ
@given(data=st.data())
def test_stage_worlds_damaged(tmp_path: Path, maps: dict[str, Path], data: st.DataObject) -> None:
    path = tmp_path / "cave.world"
    path.write_bytes(data.draw(damaged_bytes(maps["world"].read_bytes())))
    try:
        world = read_stage_world(path)
    except MimicsError as exc:
        one_line_error(exc)
        return
    assert world is not None


@FUZZ
@given(text=st.one_of(mutated_toml(BATTERY_TOML),
                      damaged_bytes(BATTERY_TOML.encode()).map(
                          lambda b: b.decode("utf-8", "replace")),
                      EDGE_VALUES.map(lambda v: BATTERY_TOML.replace("seeds = 1",
                                                                     f"seeds = {v}"))))
def test_battery_files_damaged_or_mistyped(tmp_path: Path, text: str) -> None:
    path = tmp_path / "battery.toml"
    path.write_text(text, encoding="utf-8")
    try:
        spec = load_battery(path)
    except MimicsError as exc:
        one_line_error(exc)
        return
    assert 1 <= len(spec.seeds) <= 1_000_000
    assert all(0 <= seed < 2**63 for seed in spec.seeds)


@pytest.mark.parametrize(("generator", "expected"), [
    ('generator = "line"\ncount = 100000000000\nstart = [1.0, 1.0]\nstep = [0.0, 0.5]',
     r"robots\[0\]\.count: 100000000000 is over the limit of 10000000"),
    ('generator = "grid"\nrows = 100000\ncolumns = 100000\norigin = [1.0, 1.0]\nspacing = 0.5',
     r"robots\[0\]\.rows: 100000 x 100000 robots, over the limit"),
    ('generator = "random"\ncount = 9223372036854775807',
     r"robots\[0\]\.count: 9223372036854775807 is over the limit of 10000"),
])
def test_generator_counts_past_the_limits_are_refused_before_allocating(
        tmp_path: Path, generator: str, expected: str) -> None:
    path = tmp_path / "many.toml"
    path.write_text('map = { segments = [], bounds = [0.0, 0.0, 10.0, 6.0] }\n[[robots]]\n'
                    f'type = "Pioneer2DX"\n{generator}\n')
    with pytest.raises(MimicsError, match=expected):
        load_scenario_toml(path)
