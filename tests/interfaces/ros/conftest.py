"""A real ROS master per test (``ros_env``); helpers are in ``helpers.py``."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.interfaces.ros.helpers import running_master
from tests.system_packages import require


@pytest.fixture
def ros_env(tmp_path: Path) -> Iterator[dict[str, str]]:
    """The environment of a fresh ``rosmaster`` on a free port (stopped afterwards)."""
    require("ros")
    with running_master(tmp_path / "ros_home") as env:
        yield env
