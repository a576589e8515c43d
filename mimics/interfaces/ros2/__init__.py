"""The live ROS 2 bridge: ``mimics ros2`` runs a simulation on the ROS 2 DDS graph.

No rclpy: ROS 2 nodes talk DDS, and this bridge speaks it with Eclipse
Cyclone DDS's Python binding (``cyclonedds``, the ``ros2`` extra), by ROS 2's
conventions: topic ``/a/b`` is the DDS topic ``rt/a/b``, message types are
``pkg::msg::dds_::Type_`` with ROS 2's field layout (:mod:`.messages`),
samples are plain XCDR1 and each topic has the QoS a ROS 2 node expects
(:mod:`.qos`); the DDS domain is ``ROS_DOMAIN_ID``. ``transport`` is the DDS
participant, ``conversion`` fills the messages, ``bridge`` ties them to a
run, ``services`` serves pause, resume, step and reset.

Only the transport is here: the bridge core (lockstep and pace,
:mod:`mimics.interfaces.ros.bridge_core`, resets included), the inbox of
commands, the references it returns to the engine, the names of topics and
frames, the odometry frame, the map's cells, what every message means
(:mod:`mimics.interfaces.ros.planar`, :mod:`mimics.interfaces.ros.readings`)
and what the services do (:mod:`mimics.interfaces.ros.run_control`) are the
ROS 1 bridge's, shared.
"""

from __future__ import annotations

from mimics.world.errors import MimicsError

INSTALL_HINT = "mimics ros2 needs the ros2 extra: pip install 'mimics-sim[ros2]'"


def require_cyclonedds() -> None:
    """Check that Cyclone DDS's Python binding can be imported.

    Raises:
        MimicsError: naming the extra to install (and why the import failed).
    """
    try:
        import cyclonedds.domain  # noqa: F401
    except ImportError as exc:
        raise MimicsError(f"{INSTALL_HINT} (cyclonedds cannot be imported: {exc})") from None
