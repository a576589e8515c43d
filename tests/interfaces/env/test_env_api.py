"""The environments pass PettingZoo's and Gymnasium's own checkers."""

from __future__ import annotations

import subprocess
import sys
import warnings

import gymnasium
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test, parallel_seed_test

import mimics.env
from mimics.interfaces.env.single import GYM_ID


def _strict_warnings() -> None:
    warnings.simplefilter("error")
    # our action box is in physical units (m/s, rad) on purpose; RescaleAction normalises it
    warnings.filterwarnings("ignore", message=".*symmetric and normalized")


@pytest.mark.parametrize("observation", ["dict", "flat"])
def test_parallel_api_test_passes(observation: str) -> None:
    # 8 robots swapping places on a circle: random actions crash some, the rest truncate
    env = mimics.env.parallel_env("circle_swap", robots=6, observation=observation, time=8.0)
    with warnings.catch_warnings():
        _strict_warnings()
        parallel_api_test(env, num_cycles=200)
    assert env.agents == []


def test_parallel_seed_test_passes() -> None:
    with warnings.catch_warnings():
        _strict_warnings()
        parallel_seed_test(lambda: mimics.env.parallel_env("circle_swap", robots=4, time=3.0))


@pytest.mark.parametrize("observation", ["dict", "flat"])
def test_single_robot_env_passes_gymnasium_check_env(observation: str) -> None:
    env = gymnasium.make(GYM_ID, scenario="circle_swap", robots=4, robot=2,
                         others="go_to_goal", observation=observation)
    with warnings.catch_warnings():
        _strict_warnings()
        check_env(env.unwrapped)


def test_importing_mimics_does_not_import_the_rl_libraries() -> None:
    code = ("import sys, mimics, mimics.env; "
            "mimics.env.parallel_env; "
            "print(sorted(m for m in ('pettingzoo', 'gymnasium') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
