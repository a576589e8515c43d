"""Sensor noise checked statistically against a type's settings (SPEC section 3).

Many draws through a real simulation, with fixed seeds (so the outcome is
deterministic: the tests cannot flake), compared with the configured
zero-mean Gaussians: mean within 4 standard errors, standard deviation
within 5%, and a Kolmogorov-Smirnov test (scipy) against the exact normal.
The truth is the same simulation's ground truth (or its noise-free twin).
"""

import math
from dataclasses import replace

import numpy as np
from scipy import stats

from mimics.engine.simulation import Simulation
from mimics.world.maps import Map
from mimics.world.robot_types import (
    OdometryNoise,
    PositioningNoise,
    RangerSpec,
    RobotType,
)
from mimics.world.scenario import Scenario

BASE = RobotType("noisy", width=0.2, length=0.2, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)


def assert_gaussian(samples: np.ndarray, sigma: float) -> None:
    """``samples`` look drawn from N(0, sigma): mean, spread and shape."""
    n = samples.size
    assert n >= 2000
    assert abs(samples.mean()) < 4 * sigma / math.sqrt(n)
    assert abs(samples.std(ddof=1) / sigma - 1) < 0.05
    assert stats.kstest(samples, "norm", args=(0.0, sigma)).pvalue > 1e-3


def grid(robot_type: RobotType, count: int, spacing: float, v: float = 0.0,
         yaw: float = 0.0) -> Scenario:
    """``count`` robots in a row along y, far apart, no walls, no goals."""
    rows = [[0.0, spacing * i, yaw, v, np.nan, np.nan] for i in range(count)]
    bounds = (-100.0, -spacing, 100.0, spacing * count)
    return Scenario.from_matrix(rows, Map.empty(bounds), robot_type)


def test_positioning_noise_has_the_types_sigmas() -> None:
    sigmas = PositioningNoise(sigma_position=0.05, sigma_velocity=0.02, sigma_acceleration=0.3)
    sim = Simulation(grid(replace(BASE, positioning=sigmas), 200, 1.0),
                     lambda robot: (0.0, 0.0), seed=11, time_limit=2.0)
    errors: dict[str, list[np.ndarray]] = {"position": [], "velocity": [], "acceleration": []}
    sim.start()
    while True:
        state = sim.state
        errors["position"].append((state.measured_pose[:, :2] - state.pose[:, :2]).ravel())
        errors["velocity"].append((state.measured_velocity - state.velocity).ravel())
        errors["acceleration"].append((state.measured_acceleration - state.acceleration).ravel())
        assert np.array_equal(state.measured_pose[:, 2], state.pose[:, 2])  # heading exact
        if not sim.step():
            break
    assert_gaussian(np.concatenate(errors["position"]), 0.05)
    assert_gaussian(np.concatenate(errors["velocity"]), 0.02)
    assert_gaussian(np.concatenate(errors["acceleration"]), 0.3)


def test_odometry_noise_accumulates_with_distance_travelled() -> None:
    """Straight at constant references: the odometer's along-track error is the sum of the
    steps' draws, N(0, sigma_t * sqrt(sum d_k^2)) with d_k the true step lengths; the
    heading does not turn, so the rotation noise adds nothing."""
    sigma_t = 0.04
    noisy = replace(BASE, odometry=OdometryNoise(sigma_translation=sigma_t, sigma_rotation=0.1))
    sim = Simulation(grid(noisy, 2500, 0.5), lambda robot: (0.5, 0.0), seed=5, time_limit=3.0)
    sim.start()
    x = [sim.state.pose[:, 0].copy()]
    while sim.step():
        x.append(sim.state.pose[:, 0].copy())
    steps = np.diff(np.array(x), axis=0)
    assert np.all(sim.state.pose[:, 2] == 0.0) and np.all(steps > 0)
    spread = sigma_t * np.sqrt(np.sum(steps ** 2, axis=0))
    np.testing.assert_allclose(spread, spread[0])  # every robot drove the same steps
    error = sim.state.odometry[:, 0] - sim.state.pose[:, 0]
    assert_gaussian(error, float(spread[0]))
    np.testing.assert_allclose(sim.state.odometry[:, 1], sim.state.pose[:, 1], atol=1e-12)


def test_odometry_rotation_noise_accumulates_with_the_angle_turned() -> None:
    sigma_r = 0.05
    noisy = replace(BASE, odometry=OdometryNoise(sigma_translation=0.2, sigma_rotation=sigma_r))
    sim = Simulation(grid(noisy, 2500, 0.5), lambda robot: (0.0, 1.0), seed=9, time_limit=2.0)
    sim.start()
    heading = [sim.state.pose[:, 2].copy()]
    while sim.step():
        heading.append(sim.state.pose[:, 2].copy())
    turns = np.diff(np.array(heading), axis=0)  # below pi per step: no wrap
    spread = sigma_r * np.sqrt(np.sum(turns ** 2, axis=0))
    np.testing.assert_allclose(spread, spread[0])
    error = sim.state.odometry[:, 2] - sim.state.pose[:, 2]
    assert_gaussian(error, float(spread[0]))
    # turning in place: no translation, so no translation noise either
    np.testing.assert_array_equal(sim.state.odometry[:, :2], sim.state.pose[:, :2])


def test_ranger_noise_has_the_types_sigma_and_is_clipped_to_the_range() -> None:
    """Robots in a ring of walls 1.0 m away (a 40-gon), range 1.5 m and a beam fan that
    also looks through gaps: hits get N(0, sigma) noise; misses (no return) read the range
    exactly, as a real lidar reports no return, never a phantom obstacle short of it."""
    sigma = 0.02
    ranger = RangerSpec(name="test", fov=2 * math.pi, beams=90, range=1.5, sigma=sigma)
    corners = [(math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 41)]
    walls = [(*corners[i], *corners[i + 1]) for i in range(40) if (i // 5) % 2 == 0]
    world = Map(np.array(walls), (-2.0, -2.0, 2.0, 2.0))

    def scans(spec: RangerSpec, seed: int) -> np.ndarray:
        rows = [[0.0, 0.0, 0.0, 0.0, np.nan, np.nan]]
        sim = Simulation(Scenario.from_matrix(rows, world, replace(BASE, ranger=spec)),
                         lambda robot: (0.0, 0.0), seed=seed, time_limit=8.0)
        sim.start()
        out = [sim.state.scan[0].copy()]
        while sim.step():
            out.append(sim.state.scan[0].copy())
        return np.array(out)

    truth = scans(replace(ranger, sigma=0.0), 0)
    noisy = scans(ranger, 3)
    hit = truth < 1.5
    assert np.all(truth[hit] > 0.9)  # far from both clip bounds: the noise is not clipped
    assert hit.sum() >= 2000 and (~hit).sum() >= 2000
    assert_gaussian((noisy - truth)[hit], sigma)
    assert (noisy[~hit] == 1.5).all()
