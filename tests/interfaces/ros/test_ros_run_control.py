"""The run control behind ``/mimics/pause``, ``step``, ``resume`` and ``reset``, with the
run played by a thread (no master needed): what each service answers and lets through."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from tests.system_packages import require


@pytest.fixture
def control():
    require("ros")
    from mimics.interfaces.ros.system_ros import require_ros

    require_ros()
    from mimics.interfaces.ros.services import RunControl

    return RunControl(answer_within=3.0)


class FakeRun(threading.Thread):
    """Publishes steps 0, 1, 2... through the control's gate, as the bridge does."""

    def __init__(self, control, folder: str, steps: int) -> None:
        super().__init__(daemon=True)
        self.control, self.folder, self.steps = control, Path(folder), steps
        self.published: list[int] = []
        self.reset_at: int | None = None

    def run(self) -> None:
        self.control.run_started(self.folder)
        self._publish(0)
        for step in range(1, self.steps + 1):
            go_on, _ = self.control.gate()
            if not go_on:
                self.reset_at = step
                return
            self._publish(step)
        self.control.run_ended()

    def _publish(self, step: int) -> None:
        self.published.append(step)
        self.control.published(step, step * 0.1)


def test_step_is_refused_unless_paused_and_pause_holds_before_the_next_step(control):
    assert control.step() == (False, "not paused: call /mimics/pause first")
    run = FakeRun(control, "run", steps=10_000_000)
    run.start()
    ok, message = control.pause()
    held = len(run.published)
    assert ok and message == f"paused at step {held - 1} (t={(held - 1) * 0.1:g} s published last)"
    assert control.step() == (True, f"stepped at step {held} (t={held * 0.1:g} s published last)")
    assert run.published == list(range(held + 1))  # exactly one more
    assert control.resume() == (True, "resumed")
    assert control.resume() == (True, "was not paused")
    control.pause()
    # no second run comes here: after its wait the service says the reset is under way
    assert control.reset() == (True, "resetting: the run ends at its next step and starts "
                                     "again")
    run.join(10)
    assert run.reset_at is not None and run.published[-1] == run.reset_at - 1


def test_reset_while_paused_ends_the_run_and_the_next_one_starts_paused(control):
    first = FakeRun(control, "run", steps=10_000_000)
    first.start()
    control.pause()
    answers = []
    asking = threading.Thread(target=lambda: answers.append(control.reset()))
    asking.start()
    first.join(10)
    assert first.reset_at == first.published[-1] + 1  # that step was never published
    second = FakeRun(control, "run-reset-1", steps=100)
    second.start()
    asking.join(10)
    assert answers == [(True, "reset: the run started again from t=0 in run-reset-1")]
    ok, message = control.pause()  # still paused: held after its step 0
    assert ok and message.startswith("paused at step 0 ")
    assert second.published == [0]
    assert control.step()[0] and second.published == [0, 1]
    control.resume()
    second.join(10)
    assert second.published == list(range(101))


def test_next_reset_folder_never_takes_an_existing_one(control, tmp_path):
    (tmp_path / "run-reset-1").mkdir()
    assert control.next_reset_folder(tmp_path / "run") == tmp_path / "run-reset-2"
    assert control.next_reset_folder(tmp_path / "run") == tmp_path / "run-reset-3"
