"""Counts, seeds and times past what mimics can hold are refused in one line naming the limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation
from mimics.scenarios.line import scenario as line
from mimics.world.errors import MimicsError, ScenarioError
from mimics.world.limits import (
    MAX_BEAMS,
    MAX_ROBOTS,
    MAX_SEED,
    MAX_STEPS,
    check_finite,
    check_steps,
    check_whole,
)
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, RangerSpec, RobotType
from mimics.world.scenario import Settings


@pytest.mark.parametrize("value", [-1, MAX_SEED + 1, 2**128, 1.0, True, "3", None])
def test_whole_numbers_outside_the_range_name_the_range(value: object) -> None:
    with pytest.raises(MimicsError, match=rf"seed: expected a whole number from 0 to {MAX_SEED}"):
        check_whole("seed", value, 0, MAX_SEED)


def test_whole_numbers_inside_pass_numpy_ints_too() -> None:
    assert check_whole("seed", np.int64(7), 0, MAX_SEED) == 7
    assert check_whole("seed", MAX_SEED, 0, MAX_SEED) == MAX_SEED


def test_non_finite_values_are_found_inside_sweeps() -> None:
    with pytest.raises(MimicsError, match=r"spacing\[1\]: expected a finite number, got nan"):
        check_finite("spacing", [1.0, math.nan])
    assert check_finite("spacing", [1.0, 2]) == [1.0, 2]


def test_step_counts_stop_at_the_limit_with_the_longest_time_in_the_message() -> None:
    assert check_steps(MAX_STEPS * 1.0, 1.0) == MAX_STEPS
    with pytest.raises(MimicsError, match=rf"over the limit of {MAX_STEPS} .*at most"):
        check_steps((MAX_STEPS + 1) * 1.0, 1.0)
    for bad in (math.inf, math.nan):
        with pytest.raises(MimicsError, match="finite"):
            check_steps(bad, 0.1)


@pytest.mark.parametrize(("field", "value"), [("time_limit", math.inf), ("dt", math.nan),
                                              ("deadlock_window", math.inf),
                                              ("livelock_progress", math.inf)])
def test_settings_refuse_infinite_and_nan_values_naming_the_field(field: str,
                                                                  value: float) -> None:
    with pytest.raises(ScenarioError, match=rf"settings\.{field}"):
        Settings(**{field: value})


def test_settings_refuse_more_steps_than_the_limit() -> None:
    with pytest.raises(ScenarioError, match=rf"settings\.time_limit: .*{MAX_STEPS} steps"):
        Settings(time_limit=1e12, dt=0.1)
    assert Settings(comm_range=math.inf).comm_range == math.inf  # no limit: allowed


def test_robot_types_refuse_beam_counts_and_sensors_past_the_limits() -> None:
    base = PIONEER_2DX
    with pytest.raises(ScenarioError, match=rf"ranger beams: .*0 to {MAX_BEAMS}"):
        RobotType(**{**vars(base), "ranger": RangerSpec(fov=1.0, beams=MAX_BEAMS + 1,
                                                          range=2.0)})
    with pytest.raises(ScenarioError, match=r"ranger\.range: expected a finite number"):
        RobotType(**{**vars(base), "ranger": RangerSpec(fov=1.0, beams=3, range=math.nan)})


def test_maps_refuse_infinite_bounds() -> None:
    with pytest.raises(ScenarioError, match="bounds"):
        Map.empty((-math.inf, 0.0, 1.0, 1.0))


def test_scenario_parameters_are_checked_before_the_scenario_is_built() -> None:
    with pytest.raises(MimicsError, match=rf"robots: expected a whole number from 1 to "
                                          rf"{MAX_ROBOTS}"):
        load_scenario("line", robots=MAX_ROBOTS + 1)
    with pytest.raises(MimicsError, match="x_offset: expected a finite number, got inf"):
        load_scenario("line", x_offset=math.inf)


@pytest.mark.parametrize("seed", [-1, MAX_SEED + 1])
def test_the_engine_refuses_seeds_numpy_or_the_records_cannot_take(seed: int) -> None:
    with pytest.raises(MimicsError, match="seed"):
        Simulation(line(robots=1), lambda robot: (0.0, 0.0), seed=seed)


def test_the_largest_seed_runs() -> None:
    result = Simulation(line(robots=1), lambda robot: (0.0, 0.0), seed=MAX_SEED,
                        time_limit=0.2).run()
    assert result.seed == MAX_SEED and result.steps == 2


@pytest.mark.parametrize("spacing", [1e300, 1e8])
def test_scenario_starts_farther_than_any_map_are_refused_at_the_scenario(spacing: float
                                                                           ) -> None:
    from mimics.scenarios.line import scenario as line
    from mimics.world.errors import ScenarioError

    with pytest.raises(ScenarioError, match=r"robot 0's start \[0.0, .*\] is farther than "
                                            r"1e\+07 m from the origin"):
        line(robots=2, spacing=spacing)
    assert len(line(robots=2, spacing=1e3).stages) == 2  # far, but a map could hold it
