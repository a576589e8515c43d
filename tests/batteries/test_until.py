"""The stopping rule: rounds recomputed from finished runs, cells that never stop on a
sample without spread nor on a rare value seen once or twice, and a kill mid-round.
(Whether its final intervals keep their 95% promise: test_until_coverage.py.)"""

from __future__ import annotations

import math
import sqlite3
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.batteries import resume_battery, run_battery, runs_table
from mimics.batteries.spec import spec_from_dict
from mimics.batteries.stats import proportion_interval, skew_corrected_interval
from mimics.batteries.until import (
    MIN_DEPARTURES,
    UntilRule,
    _round_width,
    cell_progress,
    next_round,
)
from mimics.world.errors import MimicsError
from tests.batteries.helpers import fault, kill_midway, write_battery
from tests.batteries.test_resume import executions
from tests.batteries.test_skew_corrected_interval import hall_by_root_finding


def values_of(draws: list[float]) -> dict[int, float]:
    return {seed: value for seed, value in enumerate(draws, start=1)}


def test_a_cell_without_spread_never_meets_its_target_and_a_noisy_one_goes_on() -> None:
    rule = UntilRule("time_to_goal", 0.2, min_seeds=10, max_seeds=500)
    # a zero-width interval is no evidence: twenty runs without a collision say little
    # about a 10% collision rate, so the cell goes on, to max_seeds, flagged unmet
    steady = [4.4] * 500
    assert cell_progress(values_of(steady[:10]), rule).scheduled == 20
    end = cell_progress(values_of(steady), rule)
    assert end.complete and not end.target_met and end.scheduled == 500
    assert end.half_width == 0.0
    rng = np.random.default_rng(7)
    noisy = rng.normal(8.0, 2.0, 500).tolist()
    first = cell_progress(values_of(noisy[:10]), rule)
    assert not first.complete and first.finished == 10 and first.scheduled == 20  # doubled
    # fed every draw, the cell stops where the interval is first narrow enough: the
    # 95% half-width, about t * s / sqrt(n) for normal draws, <= 0.2 needs about
    # (1.96 * 2 / 0.2)^2 = 384 seeds
    last = cell_progress(values_of(noisy), rule)
    assert last.complete and last.target_met and last.half_width <= 0.2
    assert 250 <= last.scheduled <= 500
    data = np.array(noisy[:last.scheduled])
    from scipy.stats import t

    low, high = hall_by_root_finding(data)  # the reported interval, from its definition
    assert last.half_width == pytest.approx((high - low) / 2, rel=1e-9)
    assert last.half_width == pytest.approx(  # and a normal sample's skewness is small
        t.ppf(0.975, len(data) - 1) * data.std(ddof=1) / math.sqrt(len(data)), rel=0.02)


def test_undefined_values_count_as_seeds_but_not_as_values() -> None:
    rule = UntilRule("time_to_goal", 0.5, min_seeds=4, max_seeds=16)
    never = cell_progress(values_of([math.nan] * 16), rule)  # no robot ever arrives
    assert never.complete and never.scheduled == 16 and never.half_width == math.inf
    assert not never.target_met
    assert next_round([math.nan, 1.0, math.nan, 1.0], rule) == 8  # nil spread: doubled
    assert next_round([math.nan] * 4, rule) == 8


def test_a_proportion_uses_the_wilson_half_width() -> None:
    rule = UntilRule("success", 0.2, min_seeds=10, max_seeds=200)
    progress = cell_progress(values_of([1.0] * 200), rule)
    # every run succeeds: Wilson's half-width (1 - low) / 2 falls under 0.2 from 10 seeds;
    # unlike a t interval it is no zero-width one, so the rule may stop there
    assert progress.complete and progress.target_met and progress.scheduled == 10
    assert progress.half_width == pytest.approx((1 - 10 / (10 + 1.959964**2)) / 2)
    assert progress.half_width < 0.2


def test_a_rare_value_seen_twice_does_not_end_a_mean() -> None:
    rule = UntilRule("collisions", 0.35, min_seeds=20, max_seeds=500)
    # rate 0.1: half-width 0.330 (skewness 2.89 stretches the upper end to 0.659; the
    # t interval's half-width is 0.144), under the target
    draws = [1.0, 1.0] + [0.0] * 18
    first = cell_progress(values_of(draws), rule)
    low, high = hall_by_root_finding(draws)
    assert first.half_width == pytest.approx((high - low) / 2, rel=1e-9)
    assert first.half_width == pytest.approx(0.3303, abs=1e-4)
    assert first.half_width < 0.35 and not first.complete
    # 5 departures at the rate seen need 5 * 20 / 2 = 50 seeds: doubled to 40 at most
    assert first.scheduled == 40
    more = draws + [1.0, 0.0, 0.0, 1.0, 0.0, 1.0] + [0.0] * 14  # 5 ones in 40
    second = cell_progress(values_of(more), rule)
    assert second.complete and second.target_met and second.scheduled == 40
    assert MIN_DEPARTURES == 5


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from([0.0, 1.0, 2.5, 7.0]) | st.floats(-1e6, 1e6), min_size=0,
                max_size=60))
def test_the_rules_cached_widths_are_the_reported_ones_to_the_bit(draws: list[float]) -> None:
    data = np.array(draws)
    assert _round_width(data, False) == skew_corrected_interval(data).half_width
    zero_one = (data > 0.5).astype(float)
    assert _round_width(zero_one, True) == proportion_interval(zero_one).half_width


@settings(max_examples=80, deadline=None)
@given(st.lists(st.floats(0, 20, allow_nan=False), min_size=40, max_size=40),
       st.integers(2, 8), st.floats(0.1, 3.0))
def test_the_schedule_depends_only_on_the_rounds_it_decided(draws: list[float], low: int,
                                                           width: float) -> None:
    rule = UntilRule("path_length", width, min_seeds=low, max_seeds=40)
    final = cell_progress(values_of(draws), rule)
    # any prefix of the results (a battery killed anywhere) schedules no seed beyond the
    # final schedule, and rounds only grow: resuming from any point ends the same way
    previous = 0
    for seen in range(len(draws) + 1):
        partial = cell_progress(values_of(draws[:seen]), rule)
        assert previous <= partial.scheduled <= final.scheduled
        previous = partial.scheduled
    assert final.scheduled <= 40 and low <= final.scheduled


@pytest.mark.parametrize(("table", "field"), [
    ({"metric": "speed", "half_width": 0.2}, "[battery.until] metric"),
    ({"metric": "time_to_goal", "half_width": 0}, "[battery.until] half_width"),
    ({"metric": "time_to_goal", "half_width": -1.0}, "[battery.until] half_width"),
    ({"metric": "time_to_goal", "half_width": "small"}, "[battery.until] half_width"),
    ({"metric": "time_to_goal", "half_width": 0.2, "min_seeds": 20, "max_seeds": 10},
     "[battery.until] min_seeds"),
    ({"metric": "time_to_goal", "half_width": 0.2, "max_seeds": 2.5}, "[battery.until] max_seeds"),
    ({"metric": "time_to_goal", "half_width": 0.2, "patience": 3}, "unknown key 'patience'"),
    ({"metric": ["success"], "half_width": 0.2}, "[battery.until] metric: expected one of"),
    ({"metric": {"name": "success"}, "half_width": 0.2}, "[battery.until] metric: expected"),
    ({"metric": 3, "half_width": 0.2}, "[battery.until] metric: expected one of"),
    ({"metric": True, "half_width": 0.2}, "[battery.until] metric: expected one of"),
    ({"metric": "success", "half_width": 0.5}, "[battery.until] half_width: expected a "
                                                "number in (0, 0.5) for the proportion"),
    ({"metric": "success", "half_width": 2}, "[battery.until] half_width: expected a number "
                                              "in (0, 0.5)"),
])
def test_bad_until_tables_name_the_field(table: dict, field: str) -> None:
    with pytest.raises(MimicsError, match=r"^b.toml: ") as caught:
        spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "until": table},
                        "scenarios": [{"name": "line"}]}, source="b.toml")
    assert field in str(caught.value) and "\n" not in str(caught.value)


def test_until_and_seeds_together_are_refused() -> None:
    with pytest.raises(MimicsError, match=r"\[battery\] seeds: not with \[battery.until\]"):
        spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": 5,
                                    "until": {"metric": "collisions", "half_width": 1.0}},
                        "scenarios": [{"name": "line"}]})


def until_battery(path: Path, algorithms: list[str], **rule: object) -> Path:
    """Path length over 4 s: nil for a robot standing still (from fixed start poses), from
    1 to 4 m for one driving at a random speed."""
    until = {"metric": "path_length", "half_width": 0.05, "min_seeds": 4, "max_seeds": 8,
             **rule}
    write_battery(path, algorithms, time=4.0, timeout=30.0, until=until,
                  scenarios=[{"name": "line", "robots": 1, "random_yaw": False}])
    text = path.read_text().replace("seeds = 1\n", "")
    path.write_text(text)
    return path


def seeds_run(folder: Path) -> dict[str, list[int]]:
    table = runs_table(folder)
    return {a: sorted(int(s) for s in group["seed"]) for a, group in table.groupby("algorithm")}


def test_a_killed_stopping_rule_battery_resumes_to_the_same_seeds(tmp_path: Path) -> None:
    if sys.platform == "win32":
        pytest.skip("SIGKILL is POSIX")
    path = until_battery(tmp_path / "b.toml", [fault("stand_still"), fault("slow_random")])
    killed = tmp_path / "killed"
    db = killed / "battery.db"
    # killed in slow_random's second round (seeds 5..8)
    kill_midway(path, killed, 1, "algorithm = 'slow_random' AND seed > 4", seconds=120)
    with sqlite3.connect(db) as connection:
        left = connection.execute("SELECT count(*) FROM runs WHERE state IN ('pending', "
                                  "'running')").fetchone()[0]
    assert left > 0  # killed mid-round
    finished_before = {int(i) for i in runs_table(killed).query("state == 'done'")["id"]}

    result = resume_battery(killed, workers=2, progress=False)
    assert set(result.counts) == {"done"}
    reference = run_battery(path, tmp_path / "reference", workers=2, progress=False)
    assert seeds_run(killed) == seeds_run(tmp_path / "reference")
    assert seeds_run(killed)["stand_still"] == list(range(1, 9))  # no spread: never met
    assert seeds_run(killed)["slow_random"] == list(range(1, 9))  # to max_seeds
    assert reference.counts == result.counts
    started = executions(killed)
    assert all(started[i] == 1 for i in finished_before)  # no finished seed ran again
    assert set(started) == set(runs_table(killed)["id"])  # none lost

