"""Events: collisions with whom, escapes, exceptions with tracebacks, deadlocks and livelocks
with their start, messages; and how each ends a robot's log."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import mimics
from mimics.algorithms import go_to_goal
from mimics.engine.simulation import Simulation
from mimics.engine.user_code import shown_path
from mimics.records.events import EVENTS_SCHEMA, EventBuffer, _messages
from mimics.records.parts import PartWriter
from mimics.records.robot_logs import read_robot_log

from .helpers import box_scenario, circle, fail_robot_1, head_on, record, stay


def endings(folder: Path, robots: int) -> list[str]:
    return [read_robot_log(folder / "robots" / f"robot_{i:04d}.log").deactivation
            for i in range(robots)]


def test_collisions_say_with_whom(tmp_path: Path) -> None:
    record(head_on(), go_to_goal, tmp_path)
    run = mimics.load_run(tmp_path)
    hits = run.read_events(kinds=["collision"]).set_index("robot")
    assert hits.loc[0, "other"] == 1 and hits.loc[1, "other"] == 0 and hits.loc[2, "other"] == -1
    assert hits.loc[0, "detail"] == "Collision with robot 1"
    assert endings(tmp_path, 4) == ["Collision with robot 1", "Collision with robot 0",
                                    "Collision with wall", "Reached goal"]
    summary = run.summary
    assert (summary["collisions"], summary["robot_collisions"], summary["wall_collisions"]) \
        == (3, 2, 1)


def test_escaping_the_map_ends_the_log(tmp_path: Path) -> None:
    record(box_scenario([[5, 5, 0, 0, 12, 5]], walls=False), go_to_goal, tmp_path)
    assert endings(tmp_path, 1) == ["Escaped map"]
    assert mimics.load_run(tmp_path).summary["escaped"] == 1


@pytest.mark.parametrize("policy", ["abort", "deactivate"])
def test_exceptions_keep_their_traceback(tmp_path: Path, policy: str) -> None:
    record(head_on(), fail_robot_1, tmp_path, policy=policy)
    run = mimics.load_run(tmp_path)
    failure = run.read_events(kinds=["exception"]).iloc[0]
    assert failure["robot"] == 1 and failure["time"] == 0.5
    assert "ZeroDivisionError" in failure["traceback"] and "fail_robot_1" in failure["traceback"]
    # the log's last line names the user's line that raised
    where = f"{shown_path(fail_robot_1.__code__.co_filename)}:56"
    message = f"Exception: ZeroDivisionError: division by zero ({where})"
    assert endings(tmp_path, 4)[1] == message
    assert run.summary["exceptions"] == 1
    assert run.summary["status"] == ("error" if policy == "abort" else "time_limit")


def test_deadlocks_are_events_with_their_start(tmp_path: Path) -> None:
    record(head_on(), stay, tmp_path)
    run = mimics.load_run(tmp_path)
    stalls = run.read_events(kinds=["deadlock"])
    assert stalls["robot"].tolist() == [0, 1, 2, 3]
    assert set(stalls["time"]) == {1.0} and set(stalls["start"]) == {0.0}
    assert endings(tmp_path, 4) == ["Deadlock"] * 4
    assert run.summary["deadlocks"] == 4 and run.summary["deadlock_episodes"] == 4


def test_deadlocks_that_do_not_deactivate_are_counted(tmp_path: Path) -> None:
    record(head_on().with_settings(deactivate_on_deadlock=False, time_limit=2.0), stay, tmp_path)
    run = mimics.load_run(tmp_path)
    assert len(run.read_events(kinds=["deadlock"])) == 4
    assert run.summary["deadlock_episodes"] == 4 and run.summary["deadlocks"] == 4
    assert run.summary["status"] == "time_limit" and run.summary["active_at_end"] == 4
    assert endings(tmp_path, 4) == ["None (active when the run ended)"] * 4


def test_livelocks_and_user_messages(tmp_path: Path) -> None:
    record(head_on().with_settings(time_limit=4.0), circle, tmp_path)
    run = mimics.load_run(tmp_path)
    stalls = run.read_events(kinds=["livelock"])
    assert len(stalls) >= 1
    assert np.all(stalls["start"] <= stalls["time"] - 2.0 + 1e-9)
    assert run.summary["livelocks"] == stalls["robot"].nunique()
    assert run.summary["livelock_episodes"] == len(stalls)
    messages = run.read_events(kinds=["user_message"])
    robot_steps = int((run.trajectory["step"] > 0).sum())
    assert len(messages) == robot_steps == run.summary["user_messages"]
    assert set(messages["detail"]) == {"going; round"}
    log = read_robot_log(tmp_path / "robots" / "robot_0000.log")
    assert set(log.table["user_msg"].iloc[1:]) == {"going; round"}
    assert log.table["user_msg"].iloc[0] == ""
    stall_row = log.table[log.table["time"] == stalls.set_index("robot").loc[0, "time"]]
    assert stall_row["sys_msg"].tolist() == ["Livelock"]


def test_a_system_message_unlike_the_events_is_kept(tmp_path: Path) -> None:
    sim = Simulation(head_on(), go_to_goal, seed=1)
    sim.start()
    buffer = EventBuffer(PartWriter(tmp_path / "parts", EVENTS_SCHEMA))
    sim.state.system_message[2] = "battery low"
    sim.state.system_message[3] = "stale, robot not active"
    buffer.collect(sim.events, sim.state, np.array([0, 1, 2]))
    assert buffer.rows == [(0.0, 0, 2, "system_message", "battery low", -2, buffer.rows[0][6],
                            "")]
    assert buffer.counts == {"system_message": 1}


def awkward(robot: object) -> tuple[float, float]:
    """Log a message with quotes, a separator and a line break."""
    robot.log('say "hi";\nthen go')  # type: ignore[attr-defined]
    return 0.0, 0.0


def test_messages_with_separators_and_line_breaks_parse_back(tmp_path: Path) -> None:
    record(head_on().with_settings(time_limit=0.3), awkward, tmp_path)
    log = read_robot_log(tmp_path / "robots" / "robot_0002.log")
    assert log.table["user_msg"].tolist() == ["", *['say "hi";\nthen go'] * 3]
    assert len(log.table) == 4 and log.deactivation == "None (active when the run ended)"
    events = mimics.load_run(tmp_path).read_events(kinds=["user_message"])
    assert set(events["detail"]) == {'say "hi";\nthen go'}


@given(st.lists(st.sampled_from(["", "", "hello"]), max_size=12), st.data())
def test_messages_are_those_of_the_given_robots_in_order(messages: list[str],
                                                       data: st.DataObject) -> None:
    """The robots whose messages a step records: exactly those among ``ids`` (the robots
    active at the start of the step) with a non-empty message, in ascending order."""
    ids = sorted(data.draw(st.sets(st.integers(0, max(len(messages) - 1, 0)))
                           if messages else st.just(set())))
    expected = [i for i in ids if messages[i]]
    assert _messages(messages, np.array(ids, dtype=np.int64)) == expected
