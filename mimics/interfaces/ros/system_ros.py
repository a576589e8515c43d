"""Finding the system's ROS 1 (Debian packages) from inside a virtual environment.

Debian installs ``rospy`` and the message packages into the system Python's
``/usr/lib/python3/dist-packages``, which a virtual environment does not see.
:func:`add_system_packages` appends that folder to ``sys.path`` when ``rospy``
is not importable otherwise: appended, after the venv's own packages, never
first, so the venv's copies of shared libraries (``cffi``, ``numpy``,
``yaml``...) keep precedence; putting the folder first breaks the venv's
``cffi``. Nothing is written to the venv: the change lasts for the process.

The bridge uses only pure-Python parts of ROS (``rospy``, ``rosgraph`` and
the generated message classes; ``/tf`` is published as plain
``tf2_msgs/TFMessage``), so any Python 3 of the venv can load them.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import socket
import sys
from pathlib import Path

from mimics.world.errors import MimicsError

SYSTEM_DIST_PACKAGES = Path("/usr/lib/python3/dist-packages")
DEBIAN_PACKAGES = ("python3-rospy", "python3-rosmaster", "python3-std-msgs",
                   "python3-geometry-msgs", "python3-nav-msgs", "python3-sensor-msgs",
                   "python3-tf2-msgs", "python3-rosgraph-msgs", "python3-std-srvs",
                   "python3-visualization-msgs")
# the Python modules the bridge imports, in the order a missing one is reported
_MODULES = ("rospy", "rosgraph", "std_msgs.msg", "geometry_msgs.msg", "nav_msgs.msg",
            "sensor_msgs.msg", "tf2_msgs.msg", "rosgraph_msgs.msg", "std_srvs.srv",
            "visualization_msgs.msg")
DEFAULT_MASTER_URI = "http://localhost:11311"


def add_system_packages(folder: Path = SYSTEM_DIST_PACKAGES) -> bool:
    """Append ``folder`` to ``sys.path`` if ``rospy`` cannot be imported without it.

    Returns True when ``rospy`` is importable afterwards.
    """
    if importlib.util.find_spec("rospy") is not None:
        return True
    if folder.is_dir() and str(folder) not in sys.path:
        sys.path.append(str(folder))  # last: the venv's own packages win
        importlib.invalidate_caches()
    return importlib.util.find_spec("rospy") is not None


def require_ros() -> None:
    """Make ROS importable, or raise one clear error naming the Debian packages.

    Raises:
        MimicsError: when a module of ROS 1 the bridge needs cannot be imported.
    """
    add_system_packages()
    for name in _MODULES:
        try:
            importlib.import_module(name)
        except ImportError as exc:
            raise MimicsError(
                f"ROS 1 is not installed ({name} cannot be imported: {exc}); install it with "
                f"`apt-get install {' '.join(DEBIAN_PACKAGES)}` (Debian 12 or later)") from None


def master_uri() -> str:
    """The ROS master's address as ROS resolves it (``ROS_MASTER_URI``, else the default)."""
    return os.environ.get("ROS_MASTER_URI") or DEFAULT_MASTER_URI


def require_master(timeout: float = 3.0) -> str:
    """Check that a ROS master answers; returns its address.

    Raises:
        MimicsError: naming ``ROS_MASTER_URI`` when no master answers within ``timeout``.
    """
    import rosgraph

    uri = master_uri()
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout)
    try:
        rosgraph.Master("/mimics_probe", master_uri=uri).getPid()
    except Exception as exc:  # refused, unreachable, not a master: all mean "no master"
        reason = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
        raise MimicsError(f"no ROS master at ROS_MASTER_URI={uri} ({reason}); start one "
                          "(`roscore` or `rosmaster --core`) or set ROS_MASTER_URI") from None
    finally:
        socket.setdefaulttimeout(previous)
    return uri
