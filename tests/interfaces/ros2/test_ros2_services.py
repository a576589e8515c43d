"""The run's services over DDS, called as rmw_cyclonedds_cpp's clients call them: a request
on ``rq/mimics/<name>Request`` with the header ``{guid, seq}``, the answer on
``rr/mimics/<name>Reply`` carrying the same header (the test's own types)."""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from mimics.records.run_folder import load_run
from tests.interfaces.ros2.controller import end_all, wait_until_under_way
from tests.interfaces.ros2.loopback import dds_environment, loopback_here, next_domain
from tests.interfaces.ros2.ros2_types import TriggerAnswer, TriggerCall

SERVICE_QOS = Qos(Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
                  Policy.History.KeepLast(10),
                  Policy.DataRepresentation(use_cdrv0_representation=True))
CLIENT_GUID = 0x0102030405060708
LIMIT = 60.0


class Client:
    """A std_srvs/Trigger client of ``/mimics/<service>`` on ``participant``."""

    def __init__(self, participant: DomainParticipant, service: str) -> None:
        self.requests = DataWriter(participant, Topic(
            participant, f"rq/mimics/{service}Request", TriggerCall), qos=SERVICE_QOS)
        self.replies = DataReader(participant, Topic(
            participant, f"rr/mimics/{service}Reply", TriggerAnswer), qos=SERVICE_QOS)
        self.sequence = 0

    def call(self) -> TriggerAnswer:
        deadline = time.monotonic() + LIMIT
        while not (self.requests.get_matched_subscriptions()
                   and self.replies.get_matched_publications()):  # rclcpp's wait_for_service
            assert time.monotonic() < deadline, "the service never appeared"
            time.sleep(0.01)
        self.sequence += 1
        self.requests.write(TriggerCall(CLIENT_GUID, self.sequence))
        while time.monotonic() < deadline:
            for answer in self.replies.take(10):
                if (answer.guid, answer.seq) == (CLIENT_GUID, self.sequence):
                    return answer
            time.sleep(0.01)
        raise AssertionError("no answer")


def test_pause_step_reset_and_resume(tmp_path: Path) -> None:
    domain, folder, mark = next_domain(), tmp_path / "run", tmp_path / "under-way"
    environment = dds_environment(domain)
    controller = subprocess.Popen([sys.executable, "-m", "tests.interfaces.ros2.controller",
                                   "2", str(mark)], env=environment,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    run = subprocess.Popen([sys.executable, "-m", "mimics", "ros2", "line", "--robots", "2",
                            "--out", str(folder), "--strict-lockstep", "--startup-grace",
                            "0.5", "--timeout", "30"], env=environment,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        with loopback_here():
            participant = DomainParticipant(domain)
            pause, step, reset, resume = (Client(participant, name)
                                          for name in ("pause", "step", "reset", "resume"))
            wait_until_under_way(mark, run, LIMIT)
            paused = pause.call()
            assert paused.success, paused.message
            held = re.fullmatch(r"paused at step (\d+) \(t=([\d.]+) s published last\)",
                                paused.message)
            assert held is not None, paused.message
            stepped = step.call()
            assert stepped.success
            assert stepped.message.startswith(f"stepped at step {int(held[1]) + 1} ")
            again = reset.call()
            assert again.success
            assert again.message == (f"reset: the run started again from t=0 in "
                                     f"{folder.with_name('run-reset-1')}")
            assert resume.call().message == "resumed"
            participant.__del__()
        out, errors = run.communicate(timeout=LIMIT * 2)
    finally:
        end_all(controller, run)
    assert run.returncode == 0, errors
    assert f"reset: the run in {folder} ended (status stopped)" in out
    first, second = load_run(folder), load_run(folder.with_name("run-reset-1"))
    assert first.summary["status"] == "stopped"
    # paused at k, one step published (k + 1); the step computed from its commands (k + 2)
    # is recorded, held before publishing, and the reset ends the run there
    assert first.trajectory.step.max() == int(held[1]) + 2
    assert second.summary["reached_goal"] == 2
