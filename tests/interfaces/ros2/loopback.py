"""DDS on this machine's loopback only, and a DDS domain of its own for each test.

:func:`cyclone_config` is the Cyclone DDS configuration (``CYCLONEDDS_URI``)
every participant of the ROS 2 tests uses: bound to 127.0.0.1, multicast off,
the only peer 127.0.0.1. :func:`next_domain` gives each test (in each xdist
worker) its own ``ROS_DOMAIN_ID`` in 1..200, so parallel tests never see
each other's topics.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator
from contextlib import contextmanager

CYCLONE_CONFIG = (
    "<CycloneDDS><Domain Id=\"any\">"
    "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General>"
    "<Discovery><Peers><Peer address=\"127.0.0.1\"/></Peers>"
    "<ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>50</MaxAutoParticipantIndex></Discovery>"
    "</Domain></CycloneDDS>"
)
_DOMAINS_PER_WORKER = 25
_counter = itertools.count()


def cyclone_config() -> str:
    """The loopback-only Cyclone DDS configuration, as ``CYCLONEDDS_URI`` takes it."""
    return CYCLONE_CONFIG


def next_domain() -> int:
    """A ``ROS_DOMAIN_ID`` in 1..200 no other test of this run uses at the same time
    (xdist worker ``gwN`` takes 25 domains from ``1 + 25 N``, in turn)."""
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw")
    slot = int(worker) % 8 if worker.isdigit() else 0
    return 1 + slot * _DOMAINS_PER_WORKER + next(_counter) % _DOMAINS_PER_WORKER


def dds_environment(domain: int) -> dict[str, str]:
    """The environment of a process on ``domain``, over loopback only."""
    return {**os.environ, "ROS_DOMAIN_ID": str(domain), "CYCLONEDDS_URI": cyclone_config(),
            "PYTHONUNBUFFERED": "1"}


@contextmanager
def loopback_here() -> Iterator[None]:
    """This process's Cyclone DDS on loopback while the block runs (Cyclone reads
    ``CYCLONEDDS_URI`` when a participant first joins a domain)."""
    previous = os.environ.get("CYCLONEDDS_URI")
    os.environ["CYCLONEDDS_URI"] = cyclone_config()
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop("CYCLONEDDS_URI", None)
        else:
            os.environ["CYCLONEDDS_URI"] = previous
