"""This process as a ROS node: its name, the ROS command-line arguments, its private
parameters.

``mimics ros`` is the node ``/mimics`` (``/stageros`` under the stage names,
as stage_ros' launch files name it); the arguments a launch file adds
(``__name:=``, ``__ns:=``, remaps ``from:=to``, private parameters
``_name:=value``) are handed to rospy, which honours them as for any rospy
node.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from mimics.interfaces.ros.system_ros import require_master, require_ros
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.interfaces.ros.bridge_core import BridgeOptions

NODE_NAME = "mimics"
STAGE_NODE_NAME = "stageros"  # --names stage: the node stage_ros runs, as launch files expect


def private_parameters(options: BridgeOptions) -> BridgeOptions:
    """``options`` with the node's private parameters read as stage_ros reads them:
    ``~base_watchdog_timeout`` (simulated seconds) replaces ``watchdog``.

    Raises:
        MimicsError: naming the parameter when its value is not a positive number.
    """
    import rospy

    value = rospy.get_param("~base_watchdog_timeout", None)
    if value is None:
        return options
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise MimicsError(f"{rospy.resolve_name('~base_watchdog_timeout')}: expected a "
                          f"positive number of seconds, got {value!r}")
    return replace(options, watchdog=float(value))


def join_ros(name: str = NODE_NAME, argv: list[str] | None = None) -> None:
    """Make ROS importable and this process the node ``name`` (once per process).

    ``argv``: ROS command-line arguments (``base_scan:=scan``, ``__name:=sim``,
    ``__ns:=/lab``, ``_param:=value``), honoured as rospy honours them; None: none.

    Raises:
        MimicsError: when ROS is not installed, no master answers at
            ``ROS_MASTER_URI``, or this process's node has already been shut down.
    """
    require_ros()
    import rospy

    if rospy.core.is_shutdown_requested() or rospy.core.is_shutdown():
        raise MimicsError("this process's ROS node has been shut down; rospy cannot start "
                          "another one in the same process")
    if not rospy.core.is_initialized():
        require_master()
        arguments = ["mimics", *(argv or [])]
        namespace = next((a.split(":=", 1)[1] for a in arguments if a.startswith("__ns:=")),
                         None)
        if namespace is not None:  # rospy reads __ns from sys.argv at import only
            import rosgraph.names

            rospy.names._set_caller_id(rosgraph.names.ns_join(
                rosgraph.names.make_global_ns(namespace), "unnamed"))
        rospy.init_node(name, argv=arguments, disable_signals=True)
