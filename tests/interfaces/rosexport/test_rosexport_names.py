"""`mimics export --names mimics|stage`: the live bridge's topics, frames and odometer, read
back with rosbags.

The truth for the odometer is the engine's own, taken by an observer during
the run (a run folder does not record it): the ``odom`` pose must be
``T(start)^-1 * T(odometer)``, worked out here by hand, and its twist the
engine's measured velocity. Names are checked against the bridge's
``RosNames`` and against stage_ros' literal names.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from mimics.algorithms import go_to_goal
from mimics.engine.simulation import Simulation
from mimics.interfaces.cli import main
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.odometry_frame import OdometerFrames
from mimics.interfaces.rosexport.odometer import odometer_gap
from mimics.interfaces.rosexport.source import Trajectory
from mimics.records.run_folder import load_run
from mimics.records.runner import run_to_folder
from mimics.scenarios.line import scenario as line
from mimics.world.edits import edit_from_dict
from mimics.world.robot_types import PositioningNoise
from mimics.world.scenario import Scenario

NAME_SETS = ("mimics", "stage")
FILES = ("bag", "mcap")


class EngineReadings:
    """An observer keeping the engine's odometer and measured velocity at every step."""

    def __init__(self) -> None:
        self.odometry: dict[int, np.ndarray] = {}
        self.velocity: dict[int, np.ndarray] = {}

    def on_start(self, sim: Simulation) -> None:
        self.on_step(sim)

    def on_step(self, sim: Simulation) -> None:
        self.odometry[sim.state.step] = sim.state.odometry.copy()
        self.velocity[sim.state.step] = sim.state.measured_velocity.copy()


def noisy(scenario: Scenario) -> Scenario:
    """``scenario`` with a noisy positioning sensor too (the odometer is noisy already)."""
    positioning = PositioningNoise(sigma_position=0.02, sigma_velocity=0.05)
    return replace(scenario, types=tuple(replace(t, positioning=positioning)
                                         for t in scenario.types))


def read(path: Path) -> dict[str, list[Any]]:
    found: dict[str, list[Any]] = defaultdict(list)
    with AnyReader([path]) as reader:
        for connection, _, raw in reader.messages():
            found[connection.topic].append(reader.deserialize(raw, connection.msgtype))
    return found


def yaw(q: Any) -> float:
    return 2.0 * math.atan2(q.z, q.w)


def gap(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2.0 * math.pi))


def xyt(pose: Any) -> tuple[float, float, float]:
    return pose.position.x, pose.position.y, yaw(pose.orientation)


def compose(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, ...]:
    """T(a) * T(b), by hand."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2]


@pytest.fixture(scope="module")
def exports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """A 3-robot (noisy positioning, turning) and a 1-robot line run, each exported under
    both name sets as a bag and an MCAP."""
    folder = tmp_path_factory.mktemp("names")
    found: dict[str, Any] = {"folder": folder}
    for robots, seconds in ((3, 3.0), (1, 1.0)):
        readings = EngineReadings()
        sim = Simulation(noisy(line(robots=robots)), go_to_goal, seed=4, time_limit=seconds,
                         observers=[readings])
        run = folder / f"run{robots}"
        run_to_folder(sim, run, record_scans=True, robot_logs="off")
        found[robots] = {"run": load_run(run), "engine": readings}
        for names in NAME_SETS:
            paths = {kind: folder / f"run{robots}-{names}.{kind}" for kind in FILES}
            assert main(["export", str(run), "--bag", str(paths["bag"]), "--mcap",
                         str(paths["mcap"]), "--names", names]) == 0
            found[robots][names] = paths
    return found


@pytest.mark.parametrize("robots", [3, 1])
@pytest.mark.parametrize("names", NAME_SETS)
@pytest.mark.parametrize("kind", FILES)
def test_topics_and_frames_are_the_live_bridges(exports: dict[str, Any], robots: int,
                                                names: str, kind: str) -> None:
    run = exports[robots]["run"]
    topics = read(exports[robots][names][kind])
    bridge = RosNames(names, robots)
    expected = {"/map", "/tf", "/tf_static", "/markers"}
    for i in range(robots):
        expected |= {bridge.odom(i), bridge.ground_truth(i), bridge.scan(i)}
        expected |= {bridge.pose(i)} - {None}
    assert set(topics) == expected
    # stage_ros' own names, spelt out
    literal = {(3, "stage"): ["/robot_2/odom", "/robot_2/base_pose_ground_truth",
                              "/robot_2/base_scan"],
               (1, "stage"): ["/odom", "/base_pose_ground_truth", "/base_scan"],
               (3, "mimics"): ["/robot_2/odom", "/robot_2/pose", "/robot_2/ground_truth",
                               "/robot_2/scan"],
               (1, "mimics"): ["/robot_0/odom", "/robot_0/ground_truth", "/robot_0/scan"]}
    assert set(literal[robots, names]) <= set(topics)
    if (robots, names) == (1, "stage"):
        assert bridge.body_frame(0) == "base_footprint" and bridge.laser_frame(0) == \
            "base_laser_link"
    trajectory = run.trajectory.sort_values(["step", "robot"], kind="stable")
    for i in range(robots):
        rows = len(trajectory[trajectory["robot"] == i])
        odom, truth = topics[bridge.odom(i)], topics[bridge.ground_truth(i)]
        assert len(odom) == len(truth) == rows
        assert {(m.header.frame_id, m.child_frame_id) for m in odom} == {
            (bridge.odom_frame(i), bridge.body_frame(i))}
        assert {(m.header.frame_id, m.child_frame_id) for m in truth} == {
            (MAP_FRAME, bridge.body_frame(i))}
        assert {m.header.frame_id for m in topics[bridge.scan(i)]} == {bridge.laser_frame(i)}
    (static,) = topics["/tf_static"]
    pairs = [(t.header.frame_id, t.child_frame_id) for t in static.transforms]
    expected_static = []
    for i in range(robots):
        if names == "stage":
            expected_static.append((bridge.footprint_frame(i), bridge.base_frame(i)))
        expected_static.append((bridge.base_frame(i), bridge.laser_frame(i)))
    assert pairs == expected_static
    steps = sorted(trajectory["step"].unique())
    assert len(topics["/tf"]) == len(steps)
    for message, step in zip(topics["/tf"], steps, strict=True):
        ids = trajectory[trajectory["step"] == step]["robot"].tolist()
        assert [(t.header.frame_id, t.child_frame_id) for t in message.transforms] == [
            pair for i in ids for pair in ((MAP_FRAME, bridge.odom_frame(i)),
                                           (bridge.odom_frame(i), bridge.body_frame(i)))]
    footprints = [m for m in topics["/markers"][0].markers if m.ns == "footprint"]
    assert [m.header.frame_id for m in footprints] == [bridge.base_frame(i)
                                                       for i in range(robots)]


@pytest.mark.parametrize("names", NAME_SETS)
@pytest.mark.parametrize("kind", FILES)
def test_odom_is_the_engines_odometer_seen_from_the_start_pose(exports: dict[str, Any],
                                                               names: str, kind: str) -> None:
    run, engine = exports[3]["run"], exports[3]["engine"]
    topics = read(exports[3][names][kind])
    bridge = RosNames(names, 3)
    trajectory = run.trajectory.sort_values(["step", "robot"], kind="stable")
    start = engine.odometry[0]
    # the live bridge's covariance, fed the engine's odometer
    frames = OdometerFrames(start, np.full(3, 0.03), np.full(3, 0.05))
    covariance = {0: frames.covariance.copy()}
    for step in range(1, max(engine.odometry) + 1):
        frames.update(engine.odometry[step])
        covariance[step] = frames.covariance.copy()
    drift = 0.0
    for i in range(3):
        rows = trajectory[trajectory["robot"] == i]
        sx, sy, st = start[i]
        for message, row in zip(topics[bridge.odom(i)], rows.itertuples(), strict=True):
            ox, oy, ot = engine.odometry[row.step][i]
            # T(start)^-1 * T(odometer), by hand
            c, s = math.cos(st), math.sin(st)
            want = (c * (ox - sx) + s * (oy - sy), -s * (ox - sx) + c * (oy - sy), ot - st)
            got = xyt(message.pose.pose)
            if row.step == 0:
                assert got == (0.0, 0.0, 0.0)
            assert abs(got[0] - want[0]) < 1e-7 and abs(got[1] - want[1]) < 1e-7
            assert gap(got[2], want[2]) < 1e-7
            twist = message.twist.twist
            assert (twist.linear.x, twist.angular.z) == tuple(engine.velocity[row.step][i])
            assert message.twist.covariance[0] == message.twist.covariance[35] == 0.05 ** 2
            planar = np.asarray(message.pose.covariance).reshape(6, 6)[np.ix_([0, 1, 5],
                                                                               [0, 1, 5])]
            assert np.allclose(planar, covariance[row.step][i], rtol=1e-6, atol=1e-15)
            # the odometer has drifted from the truth seen from the start pose
            tc, ts = math.cos(rows.iloc[0].theta), math.sin(rows.iloc[0].theta)
            dx, dy = row.x - rows.iloc[0].x, row.y - rows.iloc[0].y
            drift = max(drift, abs(tc * dx + ts * dy - got[0]))
    assert drift > 1e-4  # the odometer's noise is in the messages, not the truth


@pytest.mark.parametrize("names", NAME_SETS)
def test_tf_puts_the_body_at_the_measured_pose(exports: dict[str, Any], names: str) -> None:
    """``map -> odom -> body`` composes to the positioning sensor's pose, ``odom -> body``
    is the ``odom`` message's pose (as the live bridge's tree)."""
    run = exports[3]["run"]
    topics = read(exports[3][names]["mcap"])
    bridge = RosNames(names, 3)
    trajectory = run.trajectory.sort_values(["step", "robot"], kind="stable")
    odom = {i: iter(topics[bridge.odom(i)]) for i in range(3)}
    for message, (_, rows) in zip(topics["/tf"], trajectory.groupby("step"), strict=True):
        pairs = iter(message.transforms)
        for row in rows.itertuples():
            to_odom, to_body = next(pairs), next(pairs)
            a = (to_odom.transform.translation.x, to_odom.transform.translation.y,
                 yaw(to_odom.transform.rotation))
            b = (to_body.transform.translation.x, to_body.transform.translation.y,
                 yaw(to_body.transform.rotation))
            x, y, theta = compose(a, b)
            assert abs(x - row.x_meas) < 1e-9 and abs(y - row.y_meas) < 1e-9
            assert gap(theta, row.theta_meas) < 1e-9
            assert b == xyt(next(odom[row.robot]).pose.pose)


def test_stage_scans_put_range_max_where_mimics_puts_inf(exports: dict[str, Any]) -> None:
    mimics = read(exports[3]["mimics"]["bag"])
    stage = read(exports[3]["stage"]["bag"])
    misses = 0
    for i in range(3):
        for a, b in zip(mimics[f"/robot_{i}/scan"], stage[f"/robot_{i}/base_scan"],
                        strict=True):
            ranges, staged = np.asarray(a.ranges), np.asarray(b.ranges)
            assert np.isfinite(staged).all()
            assert np.array_equal(staged[np.isinf(ranges)],
                                  np.full(np.isinf(ranges).sum(), np.float32(b.range_max)))
            assert np.array_equal(staged[np.isfinite(ranges)], ranges[np.isfinite(ranges)])
            misses += int(np.isinf(ranges).sum())
    assert misses > 0  # the line scenario has open space: some beams hit nothing


def test_a_run_recorded_every_other_step_has_no_odom_and_says_so(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sim = Simulation(line(robots=2), go_to_goal, seed=1, time_limit=1.0)
    run_to_folder(sim, tmp_path / "run", every=2, robot_logs="off")
    target = tmp_path / "run.mcap"
    assert main(["export", str(tmp_path / "run"), "--mcap", str(target), "--names",
                 "stage"]) == 0
    out = capsys.readouterr().out
    assert "note: no odom topics" in out and "record_every > 1" in out
    topics = read(target)
    assert "/robot_0/odom" not in topics and "/robot_0/base_pose_ground_truth" in topics
    trajectory = load_run(tmp_path / "run").trajectory.sort_values(["step", "robot"])
    first = trajectory[trajectory["step"] == 0]
    transforms = topics["/tf"][0].transforms
    assert [(t.header.frame_id, t.child_frame_id) for t in transforms] == [
        ("map", "robot_0/base_footprint"), ("map", "robot_1/base_footprint")]
    assert [t.transform.translation.x for t in transforms] == first["x_meas"].tolist()


def test_an_unknown_name_set_is_one_error_line(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    run_to_folder(Simulation(line(robots=1), go_to_goal, seed=1, time_limit=0.2),
                  tmp_path / "run", robot_logs="off")
    assert main(["export", str(tmp_path / "run"), "--bag", str(tmp_path / "r.bag"),
                 "--names", "gazebo"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "mimics: error: --names: expected one of mimics, stage, got 'gazebo'"
    assert not (tmp_path / "r.bag").exists()


def test_a_moved_robot_or_an_unknown_seed_leaves_the_odometer_out(
        exports: dict[str, Any]) -> None:
    """A ``move_robot`` edit restarts the robot's odometer at a pose no row shows."""
    run = exports[3]["run"]
    trajectory = Trajectory.of(run)
    assert odometer_gap(trajectory, run.scenario, 4) is None
    edited = replace(run.scenario, edits=(edit_from_dict(
        {"kind": "move_robot", "step": 7, "robot": 0, "x": 1.0, "y": 1.0}),))
    assert odometer_gap(trajectory, edited, 4) == "a robot was moved by an edit at step 7"
    assert "seed" in str(odometer_gap(trajectory, run.scenario, None))
