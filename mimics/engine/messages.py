"""Message passing between robots: sent in one step, delivered at the next.

A message reaches its recipient only if it is active and, when the scenario
sets a communication range, within that range of the sender at delivery.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterable
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


class MessageColumn(list):
    """One text per robot (``WorldState.user_message`` and ``system_message``) that keeps
    the indices of the texts not empty, in ``filled``.

    Most texts are empty: the step clears and the recorder reads the others only,
    rather than scanning the column (10,000 robots: 250 us a scan, four a step).
    """

    def __init__(self, texts: Iterable[str] = ()) -> None:
        super().__init__(texts)
        self._refresh()

    def __setitem__(self, index: Any, value: Any) -> None:
        super().__setitem__(index, value)
        if isinstance(index, slice):  # (not SupportsIndex: a Protocol check costs 3 us)
            self._refresh()
            return
        robot = operator.index(index)
        robot += len(self) if robot < 0 else 0
        if value:
            self.filled.add(robot)
        else:
            self.filled.discard(robot)

    def _refresh(self) -> None:
        self.filled: set[int] = {i for i, text in enumerate(self) if text}


def _refreshing(name: str) -> Callable[..., Any]:
    method = getattr(list, name)

    def call(self: MessageColumn, *args: Any, **kwargs: Any) -> Any:
        result = method(self, *args, **kwargs)
        self._refresh()
        return result
    return call


# the column is one text per robot: these are not used on it, but keep ``filled`` right
for _name in ("__delitem__", "__iadd__", "__imul__", "append", "extend", "insert", "pop",
              "remove", "clear", "sort", "reverse"):
    setattr(MessageColumn, _name, _refreshing(_name))


def filled(messages: list[str]) -> list[int]:
    """The indices of the texts that are not empty, ascending."""
    if isinstance(messages, MessageColumn):
        return sorted(messages.filled)
    return [i for i, text in enumerate(messages) if text]


def clear_messages(messages: list[str], active: np.ndarray) -> None:
    """Empty the messages of active robots (inactive ones keep their last words)."""
    for i in filled(messages):
        if active[i]:
            messages[i] = ""
