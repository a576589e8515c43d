"""The engine's side of the views user code gets (``robot_view``): mirrors and a link.

A view (``Robot``, ``Team``) never holds the simulation. The arrays they give are read-only views of
*mirrors*: copies of the world's arrays refreshed once per step (a few rows of
numbers: microseconds), so writing into them, even after turning ``writeable``
back on, never reaches the world. What cannot be copied ahead (a scan row is
traced when first read, messages, the log) goes through a generator
(:class:`ViewHub`'s link): no attribute, closure or ``__dict__`` of a view leads
to the simulation. In-process Python can still reach any object through ``gc``
or frames; battery workers close those ways with an audit hook
(:mod:`mimics.engine.user_code.guard`), and the worker process is the boundary
(docs/explanation/containment.md).

"""

from __future__ import annotations

from collections.abc import Generator
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.sensors import within_range

if TYPE_CHECKING:
    from mimics.engine.user_code.world_access import SimulationParts

#: The world's arrays mirrored for the views (attribute names of ``WorldState``).
MIRRORED = ("pose", "measured_pose", "velocity", "measured_velocity", "measured_acceleration",
            "odometry", "goal")

Link = Generator[Any, Any, None]


def _frozen(view: np.ndarray) -> np.ndarray:
    view.flags.writeable = False
    return view


class Mirror:
    """Copies of the world's arrays as of this step's sensing, shared by a run's views."""

    def __init__(self, sim: SimulationParts) -> None:
        state = sim.state
        for name in MIRRORED:
            setattr(self, name, np.array(getattr(state, name), copy=True))
        self.scan: np.ndarray | None = None  # made at the first scan read (n x beams)
        self.scan_hit: np.ndarray | None = None
        self.beam_count = tuple(int(b) for b in sim.types.beam_count)
        self.max_range = tuple(float(r) for r in sim.types.max_range)
        self.scan_step = [-1] * state.n  # the step at which each row was copied
        self.step = -1  # refreshes so far: a scan row copied before the last one is stale
        self.time = 0.0
        self.dt = float(sim.scenario.settings.dt)
        self.comm_range = float(sim.scenario.settings.comm_range)


class ViewHub:
    """The engine's side of the views of one simulation: refreshes the mirror and serves
    the link's requests. Kept on the simulation (``sim.view_hub``), never on a view."""

    def __init__(self, sim: SimulationParts) -> None:
        self._sim = sim
        self.mirror = Mirror(sim)
        self._comms: np.ndarray | None = None
        self._comms_step = -1
        link = self._serve()
        next(link)
        self.link: Link = link

    def refresh(self) -> None:
        """Copy the world's values into the mirror (before user code runs: a few rows of
        numbers per robot, microseconds a step)."""
        state = self._sim.state
        mirror = self.mirror
        for name in MIRRORED:
            np.copyto(getattr(mirror, name), getattr(state, name))
        mirror.step += 1
        mirror.time = state.time

    def _serve(self) -> Link:
        """The link: a generator answering ``(what, robot, ...)`` requests. Its frame is the
        only place a view's request reaches the simulation from."""
        answer: Any = None
        while True:
            request = yield answer
            answer = self._answer(request)

    def _answer(self, request: tuple[Any, ...]) -> Any:
        sim, what, robot = self._sim, request[0], request[1]
        if what == "scan_row":
            self._scan_row(robot)
            return None
        if what == "angles":
            count = self.mirror.beam_count[robot]
            return _frozen(np.array(sim.types.beam_offsets[robot, :count], copy=True))
        if what == "team_angles":
            return np.array(sim.types.beam_offsets[robot], copy=True)
        if what == "memory":
            return sim.state.memory[robot]
        if what == "stalled":  # asked, not mirrored: a copy each step would cost every run
            flags = sim.state.stalled
            return bool(flags[robot]) if np.ndim(robot) == 0 else flags[robot]
        if what == "comms":
            table = self._comms_table()
            if robot is None:
                return table
            x, y = self.mirror.measured_pose[robot, :2]
            return within_range(table, x, y, self.mirror.comm_range)
        if what == "inbox":
            return list(sim.messages.inbox(robot))
        if what == "send":
            sim.messages.send(robot, request[2], request[3])
            return None
        if what == "log":
            current = sim.state.user_message[robot]
            text = f"{current} | {request[2]}" if current else str(request[2])
            sim.state.user_message[robot] = text
            return None
        if what == "rng":
            return sim.user_rng(robot)
        if what == "map":
            return sim.world_map
        if what == "type":
            return sim.scenario.robot_type(robot)
        if what == "team_scan":  # (k, B) copies: the whole trace, read once per team step
            rows = robot
            return {"ranges": sim.state.scan[rows], "hits": sim.state.scan_hit[rows] != -2}
        if what == "team_memory":
            return sim.team_memory
        if what == "team_types":
            types = sim.types
            return {"kv": types.plant.kv[robot], "half_length": types.half_length[robot],
                    "half_width": types.half_width[robot], "max_range": types.max_range[robot]}
        raise ValueError(f"unknown view request {what!r}")

    def _scan_row(self, robot: int) -> None:
        """Trace ``robot``'s row if pending and copy it into the mirror."""
        state, mirror = self._sim.state, self.mirror
        if mirror.scan is None or mirror.scan_hit is None:
            mirror.scan = np.array(state.scan_buffer, copy=True)
            mirror.scan_hit = np.array(state.scan_hit_buffer, copy=True)
        if state.pending_scan is not None:
            state.scan_row(robot)
        mirror.scan[robot] = state.scan_buffer[robot]
        mirror.scan_hit[robot] = state.scan_hit_buffer[robot]
        mirror.scan_step[robot] = mirror.step

    def _comms_table(self) -> np.ndarray:
        """This step's comms table, copied once per step and read-only."""
        if self._comms is None or self._comms_step != self.mirror.step:
            self._comms = _frozen(np.array(self._sim.comms_table(), copy=True))
            self._comms_step = self.mirror.step
        return self._comms


def hub_of(sim: SimulationParts) -> ViewHub:
    """The simulation's :class:`ViewHub` (made and refreshed on first use)."""
    hub: ViewHub | None = getattr(sim, "view_hub", None)
    if hub is None:
        hub = ViewHub(sim)
        hub.refresh()
        sim.view_hub = hub  # type: ignore[attr-defined]
    return hub
