"""Objects made before a run are frozen for it and handed back after: nothing stays frozen,
garbage made before the run is still collected, a process's own freeze is left alone."""

from __future__ import annotations

import gc
import weakref

from mimics.algorithms import go_to_goal
from mimics.engine.compiling import heap_frozen
from mimics.engine.simulation import Simulation
from mimics.scenarios.line import scenario


class Node:
    def __init__(self) -> None:
        self.other: Node | None = None


def cycle() -> weakref.ref[Node]:
    """An unreachable cycle (only the collector frees it); a weak reference to watch it."""
    a, b = Node(), Node()
    a.other, b.other = b, a
    return weakref.ref(a)


def test_frozen_during_the_block_and_collected_after() -> None:
    gc.collect()
    before = cycle()
    with heap_frozen():
        assert gc.get_freeze_count() > 0
        gc.collect()
        assert before() is not None  # frozen: the collector passes it by
        during = cycle()
        gc.collect()
        assert during() is None  # made during the block: collected as ever
    assert gc.get_freeze_count() == 0
    gc.collect()
    assert before() is None


def test_a_process_that_froze_its_own_objects_is_left_alone() -> None:
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        with heap_frozen():
            assert gc.get_freeze_count() == frozen
        assert gc.get_freeze_count() == frozen
    finally:
        gc.unfreeze()


def test_a_run_leaves_nothing_frozen() -> None:
    seen = []

    class Watch:
        def on_step(self, sim: Simulation) -> None:
            seen.append(gc.get_freeze_count())

    Simulation(scenario(robots=2), go_to_goal, seed=1, time_limit=0.3,
               observers=[Watch()]).run()
    assert seen and min(seen) > 0 and gc.get_freeze_count() == 0


def test_the_set_up_leaves_nothing_frozen() -> None:
    from mimics.records.runner import prepare

    sim = prepare("line", "go_to_goal", robots=2, seed=1)
    assert sim.state.n == 2 and gc.get_freeze_count() == 0
