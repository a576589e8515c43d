"""Message passing between robots: sent in one step, delivered at the next.

A message reaches its recipient only if it is active and, when the scenario
sets a communication range, within that range of the sender at delivery.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class MessageBus:
    """Holds messages in flight and each robot's inbox for the current step."""

    def __init__(self, comm_range: float) -> None:
        self.comm_range = comm_range
        self._outgoing: list[tuple[int, int | None, Any]] = []
        self._inboxes: dict[int, list[tuple[int, Any]]] = {}

    def send(self, sender: int, message: Any, to: int | None) -> None:
        """Queue ``message`` from ``sender`` to robot ``to`` (None: everyone in range)."""
        self._outgoing.append((sender, to, message))

    def inbox(self, robot: int) -> list[tuple[int, Any]]:
        """Messages delivered to ``robot`` at the start of this step."""
        return self._inboxes.get(robot, [])

    def deliver(self, positions: np.ndarray, active: np.ndarray) -> None:
        """Move queued messages into inboxes; called once per step before user code."""
        self._inboxes = {}
        if not self._outgoing:
            return
        in_range = np.isfinite(self.comm_range)
        everyone = np.flatnonzero(active)
        for sender, to, message in self._outgoing:
            if to is None:
                # a broadcast: all active robots but the sender, distances in one go
                targets = everyone[everyone != sender]
                if in_range and targets.size:
                    gap = np.hypot(positions[targets, 0] - positions[sender, 0],
                                   positions[targets, 1] - positions[sender, 1])
                    targets = targets[~(gap > self.comm_range)]
                for target in targets.tolist():
                    self._inboxes.setdefault(target, []).append((sender, message))
                continue
            (target,) = np.array([to]).tolist()  # a plain Python number, whatever ``to`` is
            if target == sender or not (0 <= target < len(active)) or not active[target]:
                continue
            if in_range:
                gap = np.hypot(*(positions[target] - positions[sender]))
                if gap > self.comm_range:
                    continue
            self._inboxes.setdefault(target, []).append((sender, message))
        self._outgoing = []


def clear_messages(messages: list[str], active: np.ndarray) -> None:
    """Empty the messages of active robots (inactive ones keep their last words).

    Most entries are already empty: scan in C and touch only the others.
    """
    if any(messages):
        for i in [i for i, text in enumerate(messages) if text]:
            if active[i]:
                messages[i] = ""
