"""``std_srvs/Trigger`` services that pause, resume, step and reset a ROS run.

================== ==========================================================================
service            what it does
================== ==========================================================================
``/mimics/pause``  holds the run before it publishes its next step; answers once it is held
                   (``message``: the last step published). Simulated time stops: no
                   ``/clock``, no observations, and in realtime the pace resumes from there.
``/mimics/resume`` lets a paused run go on.
``/mimics/step``   paused: publishes exactly one more step (the one computed from the
                   last commands), then holds again; answers with its step and time.
                   Refused (``success`` false) when not paused.
``/mimics/reset``  ends the run and starts it again from its start state with the same
                   scenario, parameters and seed, recorded into a new run folder beside the
                   first (``RUN-reset-1``, ``-reset-2``...). The ended run's summary has
                   status ``stopped``. ``/clock`` jumps back to 0 (nodes see time move
                   backwards, as after Gazebo's reset); a paused run restarts paused,
                   after publishing its step 0. Answers with the new folder.
================== ==========================================================================

Under the ``stage`` names, stage_ros' ``reset_positions`` (``std_srvs/Empty``)
is also advertised and does what ``/mimics/reset`` does.

:class:`~mimics.interfaces.ros.run_control.RunControl` (transport-free, shared
with ROS 2) is the state the services and the run's thread share; the
bridge calls its ``gate`` before publishing each step.
"""

from __future__ import annotations

import rospy
from std_srvs.srv import Empty, EmptyResponse, Trigger, TriggerResponse

from mimics.interfaces.ros.run_control import SERVICES, RunControl

__all__ = ["SERVICES", "RunControl", "RunServices"]  # RunControl: where callers import it


class RunServices:
    """Advertises ``/mimics/pause``, ``resume``, ``step`` and ``reset`` for ``control``;
    with ``reset_positions``, also stage_ros' ``reset_positions`` (``std_srvs/Empty``, in
    the node's namespace), which does what ``/mimics/reset`` does."""

    def __init__(self, control: RunControl, reset_positions: bool = False) -> None:
        self._services = [
            rospy.Service(f"/mimics/{name}", Trigger, _handler(getattr(control, name)))
            for name in SERVICES]
        if reset_positions:
            self._services.append(rospy.Service("reset_positions", Empty,
                                                _empty_handler(control.reset)))

    def close(self) -> None:
        """Withdraw the services."""
        for service in self._services:
            service.shutdown("the run has ended")


def _empty_handler(action):  # type: ignore[no-untyped-def]
    def handle(_request: object) -> EmptyResponse:
        _success, message = action()
        rospy.loginfo(f"reset_positions: {message}")
        return EmptyResponse()
    return handle


def _handler(action):  # type: ignore[no-untyped-def]
    def handle(_request: object) -> TriggerResponse:
        success, message = action()
        return TriggerResponse(success=success, message=message)
    return handle
