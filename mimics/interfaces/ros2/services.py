"""``/mimics/pause``, ``resume``, ``step`` and ``reset`` as ROS 2 services over DDS.

What each does is the ROS 1 bridge's (:mod:`mimics.interfaces.ros.services`,
:class:`~mimics.interfaces.ros.run_control.RunControl`). A ROS 2 service is a
pair of topics: requests on ``rq/mimics/pauseRequest``
(``std_srvs::srv::dds_::Trigger_Request_``), replies on
``rr/mimics/pauseReply`` (``Trigger_Response_``), each sample starting with
``rmw_cyclonedds_cpp``'s request header ``{uint64 guid; int64 seq}``, which a
reply repeats (:mod:`.messages`): ``ros2 service call /mimics/pause
std_srvs/srv/Trigger`` works from a node on ``rmw_cyclonedds_cpp``. Fast DDS's
middleware frames requests differently (the request's identity travels
beside the sample), so its clients get no answer. Under the ``stage`` names,
stage_ros' ``reset_positions`` (``std_srvs/srv/Empty``) does what reset does.

Requests are answered on a thread of their own: a pause waits for the run to
hold, which may wait for commands, which Cyclone's receiving thread
delivers; answering there would stall them.
"""

from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable
from typing import Any

from cyclonedds.pub import DataWriter

from mimics.interfaces.ros.run_control import SERVICES, RunControl
from mimics.interfaces.ros2 import messages as msg
from mimics.interfaces.ros2 import qos
from mimics.interfaces.ros2.transport import DdsGraph, matched_readers, service_topics

READER_WAIT = 1.0  # s a reply waits for the client's reply reader to be matched


class DdsServices:
    """Serves the run's services on ``graph`` for ``control`` (with stage_ros'
    ``reset_positions`` when ``reset_positions``)."""

    def __init__(self, graph: DdsGraph, control: RunControl,
                 reset_positions: bool = False) -> None:
        self._requests: queue.Queue[tuple[Callable[[], Any], DataWriter, Any] | None] = (
            queue.Queue())
        offered = [(f"/mimics/{name}", getattr(control, name), msg.TriggerRequest,
                    msg.TriggerResponse) for name in SERVICES]
        if reset_positions:
            offered.append(("/reset_positions", control.reset, msg.EmptyRequest,
                            msg.EmptyResponse))
        for name, action, request, response in offered:
            requests, replies = service_topics(name)
            writer = graph.writer(name, response, qos.SERVICES, dds_name=replies)
            graph.reader(name, request, qos.SERVICE_REQUESTS,
                         self._queued(action, writer), dds_name=requests)
        self._thread = threading.Thread(target=self._serve, name="mimics-ros2-services",
                                        daemon=True)
        self._thread.start()

    def _queued(self, action: Callable[[], Any], writer: DataWriter) -> Callable[[Any], None]:
        def take(request: Any) -> None:  # on Cyclone's receiving thread: only queued
            self._requests.put((action, writer, request))
        return take

    def _serve(self) -> None:
        while (item := self._requests.get()) is not None:
            action, writer, request = item
            outcome = action()
            deadline = time.monotonic() + READER_WAIT
            # the client's reply reader may not be matched yet (rmw_cyclonedds_cpp waits too)
            while matched_readers(writer) == 0 and time.monotonic() < deadline:
                time.sleep(0.01)
            if isinstance(request, msg.TriggerRequest):
                success, message = outcome
                writer.write(msg.TriggerResponse(request.guid, request.seq, success, message))
            else:
                writer.write(msg.EmptyResponse(request.guid, request.seq))

    def close(self) -> None:
        """Stop answering (the graph withdraws the topics)."""
        self._requests.put(None)
        self._thread.join(timeout=5.0)
