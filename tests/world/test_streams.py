"""The run's named streams (mimics.world.streams) and the scenarios' seeded randomness.

Truth: SplitMix64 written out in plain Python integers (its published
definition), SciPy's uniformity and normality tests, and the layouts of the
same scenario built with more robots.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from mimics.catalog import load_scenario
from mimics.world.scenario_files import scenario_from_toml_text
from mimics.world.streams import keyed_normal, keyed_uniform, stream, stream_seed

MASK = (1 << 64) - 1


def splitmix64(state: int) -> int:
    """SplitMix64's output for a state (Steele, Lea and Flood 2014), in Python integers."""
    z = state & MASK
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def test_keyed_uniform_is_splitmix64_of_the_streams_key() -> None:
    key = int(stream_seed(11, "jitter").generate_state(1, np.uint64)[0])
    expected = [(splitmix64(key + (i + 1) * 0x9E3779B97F4A7C15) >> 11) / 2 ** 53
                for i in range(6)]
    assert keyed_uniform(11, "jitter", 6).tolist() == expected


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2 ** 63 - 1), count=st.integers(1, 50), more=st.integers(1, 50))
def test_a_robots_draw_does_not_depend_on_how_many_robots_there_are(seed: int, count: int,
                                                                     more: int) -> None:
    few = keyed_uniform(seed, "start", count, -1.0, 1.0)
    many = keyed_uniform(seed, "start", count + more, -1.0, 1.0)
    assert np.array_equal(few, many[:count])
    assert np.all((few >= -1.0) & (few < 1.0))


def test_keyed_draws_are_uniform_and_normal() -> None:
    uniform = keyed_uniform(3, "check", 20_000)
    assert stats.kstest(uniform, "uniform").pvalue > 1e-3
    normal = keyed_normal(3, "check", 20_000)
    assert stats.kstest(normal, "norm").pvalue > 1e-3
    # different purposes are independent streams: no correlation beyond chance
    other = keyed_uniform(3, "check2", 20_000)
    assert abs(stats.pearsonr(uniform, other).statistic) < 4 / math.sqrt(20_000)


def test_streams_of_different_seeds_purposes_and_ids_differ() -> None:
    draws = {(s, p, i): stream(s, p, i).integers(0, 2 ** 62, 4).tolist()
             for s in (0, 1) for p in ("a", "b") for i in (0, 1)}
    assert len({tuple(v) for v in draws.values()}) == len(draws)
    assert stream(1, "a", 0).integers(0, 2 ** 62, 4).tolist() == draws[(1, "a", 0)]


def test_line_headings_follow_the_runs_seed_and_adding_robots_keeps_them() -> None:
    one = load_scenario("line", robots=5, run_seed=1).stages[:, 2]
    again = load_scenario("line", robots=5, run_seed=1).stages[:, 2]
    two = load_scenario("line", robots=5, run_seed=2).stages[:, 2]
    more = load_scenario("line", robots=9, run_seed=1).stages[:, 2]
    assert np.array_equal(one, again)
    assert np.all(one != two)
    assert np.array_equal(more[:5], one)
    assert np.all((one >= -math.pi) & (one < math.pi))


@pytest.mark.parametrize("params", [{"random_yaw": False}, {"fixed": True}, {"seed": 4}])
def test_a_fixed_line_does_not_follow_the_runs_seed(params: dict) -> None:
    one = load_scenario("line", robots=4, run_seed=1, **params).stages
    two = load_scenario("line", robots=4, run_seed=2, **params).stages
    assert np.array_equal(one, two)


@pytest.mark.parametrize("name", ["circle_swap", "corridor", "obstacle_room", "swarm"])
def test_builtin_layouts_vary_with_the_seed_unless_fixed(name: str) -> None:
    one = load_scenario(name, run_seed=1)
    two = load_scenario(name, run_seed=2)
    assert not np.array_equal(one.stages, two.stages)
    assert np.array_equal(one.goals, two.goals, equal_nan=True)  # goals are the layout's
    fixed = [load_scenario(name, run_seed=s, fixed=True).stages for s in (1, 2)]
    assert np.array_equal(*fixed)


def test_jitter_stays_within_its_bounds() -> None:
    nominal = load_scenario("corridor", fixed=True).stages
    moved = load_scenario("corridor", run_seed=7).stages
    assert np.abs(moved[:, :2] - nominal[:, :2]).max() <= 0.1
    turned = np.angle(np.exp(1j * (moved[:, 2] - nominal[:, 2])))  # headings wrap at +-pi
    assert np.abs(turned).max() <= 0.1


ROOM = ('map = { segments = [[0.0, 0.0, 10.0, 0.0]], bounds = [-1.0, -1.0, 11.0, 9.0] }\n'
        '[[robots]]\ngenerator = "random"\ntype = "Pioneer2DX"\ncount = 4\n'
        '[[robots]]\ngenerator = "line"\ntype = "Pioneer2DX"\ncount = 3\nstart = [1.0, 7.0]\n'
        'step = [1.0, 0.0]\nyaw = "random"\n')


def test_a_scenario_files_generators_follow_the_runs_seed_unless_fixed() -> None:
    one = scenario_from_toml_text(ROOM, "room.toml", run_seed=1).stages
    two = scenario_from_toml_text(ROOM, "room.toml", run_seed=2).stages
    assert not np.any(one[:, 2] == two[:, 2])  # random headings of both generators
    assert np.array_equal(one[4:, :2], two[4:, :2])  # the line's places are not random
    fixed = "fixed = true\n" + ROOM
    assert np.array_equal(scenario_from_toml_text(fixed, "room.toml", run_seed=1).stages,
                          scenario_from_toml_text(fixed, "room.toml", run_seed=2).stages)
    assert np.array_equal(scenario_from_toml_text(ROOM, "room.toml", run_seed=1, seed=3).stages,
                          scenario_from_toml_text(ROOM, "room.toml", run_seed=2, seed=3).stages)
