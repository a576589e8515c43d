"""Fixtures of the learning-environment tests: small scenarios, and numba on one thread.

Results do not depend on the thread count (the engine's kernels are
deterministic per robot); one thread keeps these many short steps quick when
the machine is busy, where two threads wait on each other at every kernel call.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

import numba
import numpy as np
import pytest

from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, OdometryNoise, PositioningNoise
from mimics.world.scenario import Scenario, Settings


@pytest.fixture(autouse=True)
def one_numba_thread() -> Iterator[None]:
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


def open_field(rows: list[list[float]], *, noisy: bool = False, time_limit: float = 30.0,
               bounds: tuple[float, float, float, float] = (-10.0, -10.0, 10.0, 10.0),
               ) -> Scenario:
    """Pioneer2DX robots at ``rows`` ``[x, y, yaw, v, gx, gy]`` on a map with one wall."""
    kind = PIONEER_2DX
    if noisy:
        kind = replace(kind, ranger=replace(kind.ranger, sigma=0.01),
                       positioning=PositioningNoise(sigma_position=0.02, sigma_velocity=0.01),
                       odometry=OdometryNoise(sigma_translation=0.01, sigma_rotation=0.01))
    walls = Map(np.array([[-9.0, -9.0, -9.0, 9.0]]), bounds, "one wall")
    # not noisy: exact sensors (the built-in type carries its datasheet noise)
    settings = Settings(time_limit=time_limit, noise="on" if noisy else "off")
    return Scenario.from_matrix(rows, walls, kind, settings=settings, name="open_field")


@pytest.fixture
def four_robots() -> Scenario:
    """Four robots 2 m apart in a row, each with a goal 3 m ahead."""
    return open_field([[0.0, 2.0 * i, 0.0, 0.0, 3.0, 2.0 * i] for i in range(4)])


@pytest.fixture
def noisy_four_robots() -> Scenario:
    """``four_robots`` with ranger, positioning and odometry noise."""
    return open_field([[0.0, 2.0 * i, 0.0, 0.0, 3.0, 2.0 * i] for i in range(4)], noisy=True)
