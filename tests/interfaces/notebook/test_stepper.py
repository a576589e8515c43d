"""SimulationStepper: play, pause, step and stop over a simulation in a thread.

The truth is the same simulation run to its end by Simulation.run(): stepping it
in a thread, paused and resumed, must not change a single pose.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from mimics.interfaces.stepper import SimulationStepper
from mimics.records.runner import prepare
from mimics.world.errors import MimicsError


def new_sim():
    return prepare("circle_swap", "wall_aware", robots=4, time=4.0, seed=3)


def test_paused_stepped_and_resumed_run_ends_as_a_straight_run():
    straight = new_sim()
    straight.run()
    sim = new_sim()
    frames: list[tuple[int, float]] = []
    stepper = SimulationStepper(sim, lambda s: frames.append((s.state.step, s.state.time)),
                                speed=math.inf)
    assert stepper.state == "paused"
    for _ in range(3):
        stepper.step()
    assert stepper.wait_paused()
    assert sim.state.step == 3 and [f[0] for f in frames] == [0, 1, 2, 3]
    time.sleep(0.2)  # paused: nothing moves
    assert sim.state.step == 3
    stepper.play()
    assert stepper.wait_ended(timeout=120)
    assert sim.status == "time_limit" and stepper.state == "ended"
    assert frames[-1][0] == sim.state.step == straight.state.step == 40
    assert np.array_equal(sim.state.pose, straight.state.pose)


def test_stop_ends_the_run_with_status_stopped_and_a_last_frame():
    sim = new_sim()
    frames: list[int] = []
    stepper = SimulationStepper(sim, lambda s: frames.append(s.state.step), speed=math.inf)
    stepper.step()
    stepper.wait_paused()
    stepper.stop()
    assert stepper.wait_ended(timeout=60)
    # Stop while paused ends the run where it is, without another step, its end recorded
    assert sim.status == "stopped" and sim.state.step == 1 and frames[-1] == 1
    assert [(e.kind, e.step, e.status) for e in sim.scenario.edits] == [("end", 1, "stopped")]
    stepper.play()  # nothing happens after the end
    assert stepper.state == "ended"


def test_speed_paces_simulated_time_against_the_wall_clock():
    sim = prepare("line", "go_to_goal", robots=2, time=30.0, seed=1)
    stepper = SimulationStepper(sim, lambda s: None, speed=5.0)
    stepper.step()
    stepper.wait_paused()  # the first step pays the start-up, outside the measure
    began, at = time.monotonic(), sim.state.time
    stepper.play()
    time.sleep(1.0)
    stepper.pause()
    stepper.wait_paused()
    elapsed = time.monotonic() - began
    simulated = sim.state.time - at
    # never ahead of 5 simulated seconds per wall second, but for two steps: the first
    # of the play (pacing starts at its end) and the last, whose wait Pause cuts short
    assert simulated <= 5.0 * elapsed + 0.2 + 1e-9
    assert simulated > 0
    stepper.close()


def test_bad_arguments_are_refused_in_one_line():
    with pytest.raises(MimicsError, match="speed"):
        SimulationStepper(new_sim(), print, speed=0)
    sim = new_sim()
    sim.run()
    with pytest.raises(MimicsError, match="already run"):
        SimulationStepper(sim, print)
