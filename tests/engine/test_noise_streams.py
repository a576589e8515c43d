"""The sensors' noise streams: independence, common random numbers, determinism.

Truth: the same runs without noise (the noise is the difference), the same
runs with a robot, a sensor or a read added, and SciPy's normality test.
"""

from dataclasses import replace

import numpy as np
from scipy import stats

from mimics.engine.noise_streams import RangerNoise
from mimics.engine.simulation import Simulation
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, PositioningNoise, RangerSpec, RobotType
from mimics.world.scenario import Scenario

SIGMA = 0.02
EYE = RobotType("eye", width=0.2, length=0.2, kv=0.5, kw=1.0, tau_v=0.5, tau_w=0.2,
                ranger=RangerSpec("eye", fov=0.5, beams=5, range=3.0, sigma=SIGMA))


def under_a_wall(robot_type: RobotType, count: int, noise: str = "on") -> Scenario:
    """``count`` robots 10 m apart on y = 0 facing a wall 1 m away (every beam hits it, far
    from the clipping at 0 and at the range), standing still."""
    rows = [[10.0 * i, 0.0, np.pi / 2, 0.0, np.nan, np.nan] for i in range(count)]
    wall = Map(np.array([[-5.0, 1.0, 10.0 * count + 5, 1.0]]), (-5.0, -5.0, 10.0 * count + 5, 5.0))
    scenario = Scenario.from_matrix(rows, wall, robot_type)
    return scenario.with_settings(noise=noise)


def scans(scenario: Scenario, seed: int, steps: int, read: set[int] | None = None
          ) -> dict[int, np.ndarray]:
    """The scans read at each step of ``read`` (default every step) of a still team."""
    sim = Simulation(scenario, lambda robot: (0.0, 0.0), seed=seed, time_limit=10.0)
    sim.start()
    seen = {}
    for step in range(steps):
        if read is None or step in read:
            seen[step] = sim.state.scan.copy()
        sim.step()
    return seen


def noise_of(robot_type: RobotType, count: int, seed: int, steps: int,
             read: set[int] | None = None) -> dict[int, np.ndarray]:
    noisy = scans(under_a_wall(robot_type, count), seed, steps, read)
    exact = scans(under_a_wall(robot_type, count, noise="off"), seed, steps, read)
    return {k: noisy[k] - exact[k] for k in noisy}


def test_adding_a_robot_leaves_the_others_ranger_noise_unchanged() -> None:
    three = noise_of(EYE, 3, seed=5, steps=4)
    four = noise_of(EYE, 4, seed=5, steps=4)
    for step in three:
        np.testing.assert_allclose(four[step][:3], three[step], rtol=0, atol=1e-12)
        assert np.all(np.abs(three[step]) > 0)


def test_a_scans_noise_does_not_depend_on_which_earlier_scans_were_read() -> None:
    every = scans(under_a_wall(EYE, 3), seed=9, steps=8)
    some = scans(under_a_wall(EYE, 3), seed=9, steps=8, read={7})
    assert np.array_equal(every[7], some[7])
    assert not np.array_equal(every[7], every[6])  # each step has noise of its own


def test_a_robot_that_stops_scanning_leaves_the_others_noise_unchanged() -> None:
    noise = RangerNoise(3, np.array([5, 5, 5, 5]), 5)
    everyone = noise.draws(12, None)
    assert np.array_equal(noise.draws(12, np.array([1, 3])), everyone[[1, 3]])
    mixed = RangerNoise(3, np.array([5, 8, 5]), 8)  # robot 1 of a wider type
    rows = mixed.draws(2, None)
    assert np.array_equal(mixed.draws(2, np.array([2])), rows[[2]])
    # robot 0's draws are those of a team of robot 0 alone
    alone = RangerNoise(3, np.array([5]), 5).draws(2, None)
    assert np.array_equal(rows[0, :5], alone[0])


def test_adding_a_sensor_leaves_the_other_sensors_noise_unchanged() -> None:
    positioning = PositioningNoise(sigma_position=0.05)
    with_ranger = replace(EYE, positioning=positioning)
    without = replace(EYE, positioning=positioning, ranger=RangerSpec())
    poses = []
    for robot_type in (with_ranger, without):
        sim = Simulation(under_a_wall(robot_type, 3), lambda robot: (0.0, 0.0), seed=4,
                         time_limit=1.0)
        sim.start()
        _ = sim.state.scan
        sim.step()
        poses.append(sim.state.measured_pose.copy())
    assert np.array_equal(*poses)


def test_two_algorithms_meet_the_same_start_and_the_same_noise() -> None:
    """Common random numbers: at the start both algorithms see the same scans, bit for bit,
    and their robots' own generators draw the same numbers."""
    seen = []
    for algorithm in ((lambda robot: (0.0, 0.0)), (lambda robot: (0.3, 0.5))):
        sim = Simulation(under_a_wall(EYE, 3), algorithm, seed=21, time_limit=1.0)
        sim.start()
        seen.append((sim.state.pose.copy(), sim.state.scan.copy(),
                     sim.user_rng(1).integers(0, 2 ** 62, 3)))
    (pose_a, scan_a, rng_a), (pose_b, scan_b, rng_b) = seen
    assert np.array_equal(pose_a, pose_b) and np.array_equal(scan_a, scan_b)
    assert np.array_equal(rng_a, rng_b)


def test_a_robots_own_generator_does_not_depend_on_another_robots_draws() -> None:
    sim = Simulation(under_a_wall(EYE, 3), lambda robot: (0.0, 0.0), seed=2, time_limit=1.0)
    first = sim.user_rng(2).random(3)
    other = Simulation(under_a_wall(EYE, 3), lambda robot: (0.0, 0.0), seed=2, time_limit=1.0)
    other.user_rng(0).random(1000)
    other.user_rng().random(10)
    assert np.array_equal(other.user_rng(2).random(3), first)


def test_the_lms200s_noise_has_its_datasheet_sigma() -> None:
    """Pioneer2DX's built-in ranger noise: N(0, 0.015 m), by KS test and its spread."""
    noisy = scans(under_a_wall(PIONEER_2DX, 4), 13, 12)
    exact = scans(under_a_wall(PIONEER_2DX, 4, noise="off"), 13, 12)
    sigma = PIONEER_2DX.ranger.sigma
    assert sigma == 0.015
    # the beams that hit the wall, far from the clips at 0 and at the 8 m range
    samples = np.concatenate([(noisy[k] - exact[k])[exact[k] < 7.0] for k in noisy])
    assert samples.size > 5000
    assert abs(samples.std(ddof=1) / sigma - 1) < 0.05
    assert stats.kstest(samples, "norm", args=(0.0, sigma)).pvalue > 1e-3


def test_same_seed_same_digest_other_seed_other_digest_noise_off_the_same() -> None:
    def digest(seed: int, noise: str = "on") -> str:
        sim = Simulation(under_a_wall(EYE, 3, noise),
                         lambda robot: (0.2 * robot.scan.ranges[0], 0.3), seed=seed,
                         time_limit=2.0)
        result = sim.run()
        assert result.status == "time_limit"
        return result.trajectory_digest
    assert digest(1) == digest(1)
    assert digest(1) != digest(2)
    assert digest(1, "off") == digest(2, "off")  # nothing random left: seeds change nothing
    assert len(digest(1)) == 32 and int(digest(1), 16) >= 0


def test_the_digest_is_that_of_the_poses_an_observer_saw_and_the_outcomes() -> None:
    """The documented definition, recomputed from what an observer sees at every step."""
    import hashlib
    import zlib

    class Poses:
        crc = 0

        def on_start(self, sim: Simulation) -> None:
            self.crc = zlib.crc32(sim.state.pose.tobytes())

        def on_step(self, sim: Simulation) -> None:
            self.crc = zlib.crc32(sim.state.pose.tobytes(), self.crc)

    watch = Poses()
    sim = Simulation(under_a_wall(EYE, 3), lambda robot: (0.3, 0.2), seed=8, time_limit=3.0,
                     observers=[watch])
    result = sim.run()
    expected = hashlib.blake2b(watch.crc.to_bytes(4, "little"), digest_size=16)
    for array in (sim.state.status, sim.state.goal_time, sim.state.collided_with):
        expected.update(array.tobytes())
    expected.update(f"{result.status}:{result.steps}".encode())
    assert result.trajectory_digest == expected.hexdigest()
    assert result.summary()["trajectory_digest"] == result.trajectory_digest
