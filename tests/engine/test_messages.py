"""The message columns know which texts are not empty, whatever is written to them, and
the step clears the active robots' messages only."""

from __future__ import annotations

import copy
import pickle

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from mimics.engine.messages import MessageColumn, clear_messages, filled

SIZE = 6
texts = st.sampled_from(["", "a", "Collision with wall", "x | y"])
writes = st.lists(st.one_of(
    st.tuples(st.just("item"), st.integers(-SIZE, SIZE - 1), texts),
    st.tuples(st.just("slice"), st.integers(0, SIZE), st.lists(texts, min_size=0, max_size=3)),
    st.tuples(st.just("list"), st.sampled_from(["append", "pop", "reverse", "sort"]), texts),
), max_size=30)


def non_empty(column: list[str]) -> list[int]:
    return [i for i, text in enumerate(column) if text]


@given(writes)
def test_filled_follows_every_write(operations) -> None:
    column, plain = MessageColumn([""] * SIZE), [""] * SIZE
    for kind, where, what in operations:
        for target in (column, plain):
            if kind == "item" and -len(target) <= where < len(target):
                target[where] = what
            elif kind == "slice":
                target[where:where + len(what)] = what
            elif kind == "list" and where == "append":
                target.append(what)
            elif kind == "list" and where == "pop" and target:
                target.pop()
            elif kind == "list" and where in ("reverse", "sort"):
                getattr(target, where)()
        assert list(column) == plain
        assert filled(column) == non_empty(plain)


def test_numpy_indices_and_copies_keep_it() -> None:
    column = MessageColumn([""] * 4)
    column[np.int64(2)] = "low battery"
    column[-1] = "stuck"
    assert filled(column) == [2, 3]
    for other in (pickle.loads(pickle.dumps(column)), copy.deepcopy(column)):
        assert isinstance(other, MessageColumn)
        assert filled(other) == [2, 3] and list(other) == list(column)


def test_clear_empties_the_active_robots_only() -> None:
    column = MessageColumn(["a", "", "b", "c"])
    clear_messages(column, np.array([True, True, False, True]))
    assert list(column) == ["", "", "b", ""]
    assert filled(column) == [2]
    plain = ["a", "", "b", "c"]  # a plain list works too (scanned)
    clear_messages(plain, np.array([False, True, True, True]))
    assert plain == ["a", "", "", ""]
