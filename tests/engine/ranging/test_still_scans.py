"""Robots standing still: when their lists are made and dropped, and runs unchanged by them."""

import hashlib

import numpy as np
import pytest

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.ranging import still_scans
from mimics.engine.ranging.ranger import NO_SIGHT_LISTS
from mimics.engine.ranging.still_scans import SETTLE_STEPS, StillScans
from mimics.engine.ranging.wall_index import build_wall_index
from mimics.engine.robot_index import build_robot_index
from mimics.engine.simulation import Simulation
from tests.stage import needs_stage_scenario

WALLS = build_wall_index(np.array([[-10.0, -10.0, 40.0, -10.0], [-10.0, 10.0, 40.0, 10.0]]),
                         (-11, -11, 41, 11), reach=8.0)


def pinned_after(scans, centers, solid=None, steps=1):
    solid = np.ones(len(centers), bool) if solid is None else solid
    for _ in range(steps):
        robots = build_robot_index(centers, np.zeros(len(centers)), 0.3, 0.2, solid, cell=4.0)
        lists = scans.update(robots.centers, WALLS, robots)
    return lists.pinned.nonzero()[0].tolist()


def test_lists_come_after_standing_still_and_go_when_a_neighbour_in_range_moves():
    scans = StillScans(np.full(3, 8.0), np.full(3, 180), np.full(3, 0.2))
    centers = np.array([[0.0, 0.0], [3.0, 0.0], [30.0, 0.0]])
    # the first call has nothing to compare with: still for SETTLE_STEPS steps after it
    assert pinned_after(scans, centers, steps=SETTLE_STEPS) == []
    assert pinned_after(scans, centers) == [0, 1, 2]
    centers[2, 0] += 0.01  # 27 m from robot 1: out of its range
    assert pinned_after(scans, centers) == [0, 1]
    centers[1, 1] = 1e-12  # the least move counts
    assert pinned_after(scans, centers) == []
    assert pinned_after(scans, centers, steps=SETTLE_STEPS) == [0, 1, 2]


def test_a_robot_moving_out_of_range_unpins_those_it_left():
    scans = StillScans(np.full(2, 8.0), np.full(2, 180), np.full(2, 0.2))
    centers = np.array([[0.0, 0.0], [8.0, 0.0]])
    assert pinned_after(scans, centers, steps=SETTLE_STEPS + 1) == [0, 1]
    centers[1, 0] = 20.0  # its new place is out of robot 0's range, its old one was not
    assert pinned_after(scans, centers) == []


def test_robots_with_few_beams_are_never_pinned():
    scans = StillScans(np.full(2, 8.0), np.array([180, 8]), np.full(2, 0.2))
    assert pinned_after(scans, np.array([[0.0, 0.0], [3.0, 0.0]]), steps=20) == [0]


def test_a_robot_hidden_or_shown_unpins_everyone():
    scans = StillScans(np.full(2, 8.0), np.full(2, 180), np.full(2, 0.2))
    centers = np.array([[0.0, 0.0], [30.0, 0.0]])
    assert pinned_after(scans, centers, steps=SETTLE_STEPS + 1) == [0, 1]
    assert pinned_after(scans, centers, solid=np.array([True, False])) == []


def run_digest(name, algorithm, seconds):
    """A digest of every step's scans and poses, and how many robots were pinned."""
    sim = Simulation(load_scenario(name), find_algorithm(algorithm)[1], seed=3,
                     time_limit=seconds)
    sim.start()
    digest, pinned = hashlib.sha256(), 0
    while sim.step():
        digest.update(sim.state.scan.tobytes())
        digest.update(sim.state.scan_hit.tobytes())
        digest.update(sim.state.pose.tobytes())
        pinned = max(pinned, int(sim._scanner._still.lists.pinned.sum()))
    return digest.hexdigest(), pinned


@pytest.mark.parametrize("name, algorithm, seconds", [("hospital", "deployment_team", 2.0),
                                                      ("obstacle_room", "dispersion", 20.0)])
def test_runs_are_the_same_with_the_lists_and_without(monkeypatch, name, algorithm, seconds):
    needs_stage_scenario(name)
    with_lists, pinned = run_digest(name, algorithm, seconds)
    assert pinned > 0  # robots did stand still, and were scanned from their lists
    monkeypatch.setattr(still_scans.StillScans, "update", lambda *_: NO_SIGHT_LISTS)
    assert run_digest(name, algorithm, seconds) == (with_lists, 0)
