"""A DDS domain of one run's own: the ROS 2 counterpart of ROS 1's private master.

A ``ros2:`` run puts its topics and its node on a ``ROS_DOMAIN_ID`` that no
other DDS participant on this machine uses at that moment, so that two
battery workers (or a user's own ROS 2 graph) never see each other's
``/robot_0/cmd_vel``.

DDS gives every domain ``d`` its own UDP ports (the RTPS port mapping, the
same in Cyclone DDS and Fast DDS): ``7400 + 250 d`` (multicast discovery),
``+ 1`` (multicast data), ``+ 10 + 2 p`` and ``+ 11 + 2 p`` (participant
``p``'s unicast discovery and data). :func:`reserve_domain` takes the
domains from 101 down to 1 (domain 0 is every ROS 2 node's default, and
above 101 the ports reach Linux's ephemeral range, as ROS 2's documentation
warns) and, skipping ``ROS_DOMAIN_ID`` of this process (the user's own
graph), keeps the first one where

1. it can bind ``7400 + 250 d + 249`` on 127.0.0.1 (a port no participant
   uses): that socket, held for the run, is the reservation, so two mimics
   processes choosing at the same moment never take the same domain (the
   kernel gives a port to one socket only, and frees it if mimics dies);
2. none of the domain's multicast ports nor the unicast ports of its
   participants 0 to 3 is bound by anyone (a test bind on 127.0.0.1, which
   fails on a port bound to 127.0.0.1 or to every address): a domain some
   DDS process already uses is left to it.
"""

from __future__ import annotations

import errno
import os
import socket
from collections.abc import Iterable, Mapping

from mimics.interfaces.ros2.transport import DOMAIN_VARIABLE
from mimics.world.errors import MimicsError

PORT_BASE, DOMAIN_GAIN = 7400, 250  # the RTPS port mapping's PB and DG
RESERVATION_OFFSET = 249  # participant 119's data port: unused short of 120 participants
PROBED_OFFSETS = (0, 1, *range(10, 18))  # multicast; participants 0 to 3's unicast
PRIVATE_DOMAINS = range(101, 0, -1)
LOOPBACK = "127.0.0.1"


def domain_ports(domain: int) -> list[int]:
    """The ports whose use tells that DDS participants are on ``domain``."""
    first = PORT_BASE + DOMAIN_GAIN * domain
    return [first + offset for offset in PROBED_OFFSETS]


def _bound(port: int) -> socket.socket | None:
    """A UDP socket bound to ``port`` on loopback, or None when the port is taken."""
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        probe.bind((LOOPBACK, port))
    except OSError as exc:
        probe.close()
        if exc.errno in (errno.EADDRINUSE, errno.EACCES):
            return None
        raise
    return probe


def _unused(port: int) -> bool:
    probe = _bound(port)
    if probe is None:
        return False
    probe.close()
    return True


class PrivateDomain:
    """A DDS domain reserved for one run until :meth:`release`."""

    def __init__(self, domain: int, reservation: socket.socket) -> None:
        self.domain = domain
        self._reservation: socket.socket | None = reservation

    def release(self) -> None:
        """Give the domain back (idempotent)."""
        if self._reservation is not None:
            self._reservation.close()
            self._reservation = None


def reserve_domain(candidates: Iterable[int] = PRIVATE_DOMAINS,
                   environ: Mapping[str, str] | None = None) -> PrivateDomain:
    """The first of ``candidates`` that nobody on this machine uses, reserved (see the
    module); ``environ`` (None: this process's) gives the ``ROS_DOMAIN_ID`` to skip.

    Raises:
        MimicsError: when every candidate is taken.
    """
    inherited = (os.environ if environ is None else environ).get(DOMAIN_VARIABLE, "").strip()
    tried = []
    for domain in candidates:
        if str(domain) == inherited:
            continue
        tried.append(domain)
        reservation = _bound(PORT_BASE + DOMAIN_GAIN * domain + RESERVATION_OFFSET)
        if reservation is None:  # another mimics run holds it
            continue
        if all(_unused(port) for port in domain_ports(domain)):
            return PrivateDomain(domain, reservation)
        reservation.close()
    span = f"{min(tried)} to {max(tried)}" if tried else "none"
    raise MimicsError(f"no free DDS domain for a ros2: run (tried {span}; each is in use by "
                      "another run or DDS program on this machine)")
