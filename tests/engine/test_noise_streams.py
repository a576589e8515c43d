"""The sensors' noise streams: independence, common random numbers, determinism.

Truth: the same runs without noise (the noise is the difference), the same
runs with a robot, a sensor or a read added, SciPy's normality test, the
ziggurat's equal-area layers in closed form, and a pure-Python rendering of
the ranger's counter-based generator (ranger_noise.py's docstring).
"""

import itertools
import math
from collections.abc import Iterator
from dataclasses import replace

import numpy as np
from scipy import stats

from mimics.engine.noise_streams import RangerNoise
from mimics.engine.ranging.ranger_noise import LAYER_AREA, NO_RETURN, TAIL, ziggurat_tables
from mimics.engine.simulation import Simulation
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, PositioningNoise, RangerSpec, RobotType
from mimics.world.scenario import Scenario
from mimics.world.streams import stream_seed
from tests.threads import thread_count

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


def draws(seed: int, step: int, robots: list[int], width: int,
          no_return: tuple[int, int] | None = None) -> np.ndarray:
    """The standard normals of ``robots``' beams (unit sigma, far from either clip), NaN
    where a beam has no return."""
    ranges = np.full((len(robots), width), 50.0)
    owners = np.full(ranges.shape, -1, dtype=np.int64)
    if no_return is not None:
        owners[no_return] = NO_RETURN
    RangerNoise(seed).add(ranges, owners, np.full(len(robots), 100.0), np.ones(len(robots)),
                          step, np.array(robots))
    ranges[owners == NO_RETURN] = np.nan
    return ranges - 50.0


def test_a_robot_that_stops_scanning_leaves_the_others_noise_unchanged() -> None:
    everyone = draws(3, 12, [0, 1, 2, 3], 5)
    assert np.array_equal(draws(3, 12, [1, 3], 5), everyone[[1, 3]])
    # a wider type in the team changes nobody's first beams; robot 0 alone draws the same
    wide = draws(3, 12, [0, 1, 2, 3], 8)
    assert np.array_equal(wide[:, :5], everyone)
    assert np.array_equal(draws(3, 12, [0], 5)[0], everyone[0])
    # a beam without return draws nothing, and shifts no other beam's draw
    holed = draws(3, 12, [0, 1, 2, 3], 5, no_return=(2, 1))
    assert np.isnan(holed[2, 1]) and np.isnan(holed).sum() == 1
    assert np.array_equal(np.nan_to_num(holed, nan=everyone[2, 1]), everyone)
    assert not np.array_equal(draws(3, 13, [0], 5), everyone[:1])  # another step
    assert not np.array_equal(draws(4, 12, [0], 5), everyone[:1])  # another seed


_WORD = 2 ** 64 - 1
_GOLDEN = 0x9E3779B97F4A7C15


def _mix(z: int) -> int:
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _WORD
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _WORD
    return z ^ (z >> 31)


INNER, WIDTH, HEIGHT = (table.tolist() for table in ziggurat_tables())


def reference_normal(seed: int, step: int, robot: int, beam: int) -> float:
    """The documented generator's draw (:func:`reference_draw`)."""
    return reference_draw(seed, step, robot, beam)[0]


def reference_draw(seed: int, step: int, robot: int, beam: int) -> tuple[float, str]:
    """The documented generator in plain Python integers: the first word a hash of
    ``(key, step, robot, beam)``, further words SplitMix64 started at it, through the
    256-layer ziggurat; also which part of the ziggurat gave the draw."""
    key = int(stream_seed(seed, "ranger").generate_state(1, np.uint64)[0])
    state = _mix((key + (step + 1) * _GOLDEN) & _WORD)
    state = _mix((state + (robot + 1) * _GOLDEN) & _WORD)
    first = _mix((state + (beam + 1) * _GOLDEN) & _WORD)

    def beam_words() -> Iterator[int]:
        yield first  # w0, then mix(w0 + j G) for j = 1, 2...
        for j in itertools.count(1):
            yield _mix((first + j * _GOLDEN) & _WORD)

    words = beam_words()

    def word() -> int:
        return next(words)

    def unit() -> float:
        return (word() >> 11) / 2.0 ** 53

    while True:  # (a name of its own: rebinding ``first`` would move beam_words' start)
        drawn = word()
        layer, negative, bits = drawn & 0xFF, (drawn >> 8) & 1, (drawn >> 9) & (2 ** 52 - 1)
        x = bits * WIDTH[layer]
        if bits < INNER[layer]:
            return (-x if negative else x), "rectangle"
        if layer == 0:
            while True:
                xx = -math.log1p(-unit()) / TAIL
                yy = -math.log1p(-unit())
                if yy + yy > xx * xx:
                    return (-(TAIL + xx) if negative else TAIL + xx), "tail"
        low, high = HEIGHT[layer], HEIGHT[layer - 1]
        if low + unit() * (high - low) < math.exp(-0.5 * x * x):
            return (-x if negative else x), "wedge"


def test_the_kernels_draws_are_the_documented_generators() -> None:
    """Bit for bit against the pure-Python rendering, on beams that take every part of the
    ziggurat: its rectangles, wedges and (about one draw in 4,000) its tail."""
    parts = set()
    rows = ((0, 0, 0, 20000), (7, 3, 5, 64), (123456789, 10 ** 6, 1999, 64))
    for seed, step, robot, beams in rows:
        ranges = np.full((1, beams), 4.0)
        owners = np.full((1, beams), -1, dtype=np.int64)
        RangerNoise(seed).add(ranges, owners, np.array([8.0]), np.array([0.25]), step,
                              np.array([robot]))
        # the first 1,000 beams, and those past the tail's start (only the tail goes there)
        checked = sorted(set(range(min(beams, 1000))) | set(np.flatnonzero(
            np.abs(ranges[0] - 4.0) > 0.25 * TAIL).tolist()))
        for beam in checked:
            z, part = reference_draw(seed, step, robot, beam)
            assert ranges[0, beam] == min(max(4.0 + 0.25 * z, 0.0), 8.0), (seed, beam, part)
            parts.add(part)
    assert parts == {"rectangle", "wedge", "tail"}


def test_the_noise_is_the_clipped_sum_and_spares_pads_no_returns_and_noise_free_rows() -> None:
    """``clip(r + sigma z, 0, range)`` with the reference's ``z``, to the bit: readings pushed
    past either bound are clipped to it; NaN pads and no-return beams keep their value, as
    does a robot of a noise-free type (sigma 0)."""
    ranges = np.random.default_rng(7).uniform(0.0, 2.0, (5, 9))
    ranges[0, :3] = 0.0  # at the lower bound: half the noise pushes below it
    ranges[1, 6:] = np.nan  # a robot with fewer beams: its pads have no return
    ranges[2, :] = 1.0  # hits at its range
    ranges[4, ::2] = 3.0  # no return
    owners = np.full(ranges.shape, -1, dtype=np.int64)
    owners[1, 6:] = owners[4, ::2] = NO_RETURN
    max_range, sigma = np.array([2.0, 2.0, 1.0, 2.0, 3.0]), np.array([0.5, 0.1, 0.3, 0.0, 0.05])
    robots, before = [4, 0, 9, 2, 7], ranges.copy()
    RangerNoise(5).add(ranges, owners, max_range, sigma, 6, np.array(robots))
    expected = before.copy()
    for row, robot in enumerate(robots):
        for beam in range(9):
            if owners[row, beam] != NO_RETURN and sigma[row] > 0:
                noisy = before[row, beam] + sigma[row] * reference_normal(5, 6, robot, beam)
                expected[row, beam] = min(max(noisy, 0.0), max_range[row])
    assert ranges.tobytes() == expected.tobytes()
    assert (ranges[0, :3] == 0.0).any() and (ranges[2] == 1.0).any() and (ranges[2] < 1.0).any()
    assert np.isnan(ranges[1, 6:]).all() and (ranges[4, ::2] == 3.0).all()


def reference_noise(seed: int, step: int, robots: np.ndarray, ranges: np.ndarray,
                    owners: np.ndarray, max_range: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """The documented generator over whole arrays: every beam's first word and its
    rectangle draw in NumPy's wrapping uint64 arithmetic, the beams outside the
    rectangles by :func:`reference_draw`, then ``clip(r + sigma z, 0, range)`` on the
    beams that hit of the rows with noise."""
    key = int(stream_seed(seed, "ranger").generate_state(1, np.uint64)[0])

    def mix(z: np.ndarray) -> np.ndarray:
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))

    golden = np.uint64(_GOLDEN)
    step_state = np.uint64(_mix((key + (step + 1) * _GOLDEN) & _WORD))
    with np.errstate(over="ignore"):
        robot_state = mix(step_state + (robots.astype(np.uint64) + np.uint64(1)) * golden)
        beam = np.arange(1, ranges.shape[1] + 1, dtype=np.uint64)
        word = mix(robot_state[:, None] + beam[None, :] * golden)
    layer = (word & np.uint64(0xFF)).astype(np.int64)
    bits = ((word >> np.uint64(9)) & np.uint64(2 ** 52 - 1)).astype(np.int64)
    x = bits.astype(np.float64) * np.asarray(WIDTH)[layer]
    z = np.where((word >> np.uint64(8)) & np.uint64(1), -x, x)
    for row, beam_index in zip(*np.nonzero(bits >= np.asarray(INNER)[layer]), strict=True):
        z[row, beam_index] = reference_normal(seed, step, int(robots[row]), int(beam_index))
    noisy = np.minimum(np.maximum(ranges + sigma[:, None] * z, 0.0), max_range[:, None])
    return np.where((owners != NO_RETURN) & (sigma[:, None] != 0.0), noisy, ranges)


def test_the_threaded_kernel_gives_the_reference_numbers_at_the_hospitals_size() -> None:
    """2,000 rows of 181 beams (a width that is no whole number of the kernel's flag words),
    on one thread and with a helper, bit for bit the reference's: about 3,600 draws outside
    the rectangles, rows of sigma 0, pads, no-return beams, readings clipped at both ends."""
    rng = np.random.default_rng(17)
    rows, width = 2000, 181
    robots = rng.permutation(3000)[:rows]
    max_range = rng.choice([2.0, 8.0, 30.0], rows)
    sigma = rng.choice([0.0, 0.01, 0.3], rows, p=[0.1, 0.6, 0.3])
    ranges = rng.uniform(0.0, 1.0, (rows, width)) * max_range[:, None]
    ranges[:, :4] = 0.0  # at the lower clip
    ranges[:, 4:8] = max_range[:, None]  # at the upper clip
    owners = rng.integers(-1, 50, (rows, width))
    owners[rng.random((rows, width)) < 0.15] = NO_RETURN
    pads = rng.random(rows) < 0.2  # robots of a type with fewer beams
    ranges[pads, 170:], owners[pads, 170:] = np.nan, NO_RETURN
    expected = reference_noise(6, 41, robots, ranges, owners, max_range, sigma)
    for threads in (1, 2):
        noisy = ranges.copy()
        with thread_count(threads):
            RangerNoise(6).add(noisy, owners, max_range, sigma, 41, robots)
        assert noisy.tobytes() == expected.tobytes(), threads
    assert (expected[:, :4] == 0.0).any() and (expected[:, 4:8] == max_range[:, None]).any()


def test_the_ziggurats_layers_have_equal_areas() -> None:
    """Closed form: every layer holds LAYER_AREA under exp(-x**2 / 2), the base its
    rectangle plus the tail's integral sqrt(pi / 2) erfc(r / sqrt 2)."""
    inner, width, height = ziggurat_tables()
    edges = width * 2.0 ** 52
    edges[0] = TAIL
    base = TAIL * math.exp(-TAIL ** 2 / 2) + math.sqrt(math.pi / 2) * math.erfc(TAIL / math.sqrt(2))
    assert abs(base / LAYER_AREA - 1) < 1e-6
    for layer in range(1, 256):
        top = 1.0 if layer == 1 else math.exp(-edges[layer - 1] ** 2 / 2)
        area = edges[layer] * (top - math.exp(-edges[layer] ** 2 / 2))
        assert abs(area / LAYER_AREA - 1) < 1e-6, layer
        assert height[layer] == math.exp(-edges[layer] ** 2 / 2)
    assert inner[1] == 0 and all(inner[i] < 2 ** 52 for i in range(256))


def test_the_counter_based_draws_are_standard_normal() -> None:
    """300,000 draws (a Hospital step) against N(0, 1): KS, mean, spread and the mass
    beyond the ziggurat's tail start."""
    z = draws(11, 5, list(range(2000)), 150).ravel()
    assert stats.kstest(z, "norm").pvalue > 1e-3
    assert abs(z.mean()) < 4 / math.sqrt(z.size) and abs(z.std() - 1) < 0.005
    tail = np.mean(np.abs(z) > TAIL)
    expected = 2 * stats.norm.sf(TAIL)
    assert abs(tail - expected) < 4 * math.sqrt(expected / z.size)


def test_a_beam_with_no_return_reads_exactly_the_range_with_noise_on() -> None:
    """A robot in the open with its datasheet noise: every beam reads its maximum range to
    the bit, and its hit mask says no return, at every step."""
    rows = [[0.0, 0.0, 0.0, 0.0, np.nan, np.nan]]
    far = Map(np.array([[40.0, -1.0, 40.0, 1.0]]), (-50.0, -50.0, 50.0, 50.0))
    scenario = Scenario.from_matrix(rows, far, PIONEER_2DX).with_settings(noise="on")
    sim = Simulation(scenario, lambda robot: (0.0, 0.0), seed=3, time_limit=1.0)
    sim.start()
    assert "sigma_range" in sim.types.noisy
    for _ in range(5):
        assert (sim.state.scan == PIONEER_2DX.ranger.range).all()
        assert (sim.state.scan_hit == NO_RETURN).all()
        sim.step()


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
