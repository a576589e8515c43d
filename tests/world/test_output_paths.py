"""``check_outputs`` against the operating system's own answer (``os.path.realpath``,
``os.path.commonpath``, ``os.stat``) over generated paths, links and ``..``; ``as_path``."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.world.errors import MimicsError
from mimics.world.output_paths import Folder, as_path, check_outputs

#: A small tree: a run folder with records, a file beside it, links to both.
NAMES = ["run", "run/summary.json", "run/robots", "run/robots/r.log", "run/new.png",
         "beside.txt", "new.txt", "other", "other/x.txt", "soft_run", "soft_summary",
         "hard_summary", "run/..", "run/../beside.txt", "./new.txt", "soft_run/summary.json"]


def tree(root: Path) -> None:
    (root / "run" / "robots").mkdir(parents=True)
    (root / "run" / "summary.json").write_text("{}")
    (root / "run" / "robots" / "r.log").write_text("log")
    (root / "beside.txt").write_text("b")
    (root / "other").mkdir()
    (root / "other" / "x.txt").write_text("x")
    os.symlink(root / "run", root / "soft_run")
    os.symlink(root / "run" / "summary.json", root / "soft_summary")
    os.link(root / "run" / "summary.json", root / "hard_summary")


def expected_refusal(root: Path, output: str, inputs: list[str], records: tuple[str, ...],
                     outputs: list[str]) -> bool:
    """The truth, from the OS: same inode or real path, inside the folder's records, or
    holding an input; or two outputs that are one file."""
    real = os.path.realpath(root / output)
    for name in inputs:
        source = os.path.realpath(root / name)
        if real == source or (os.path.exists(real) and os.path.exists(source)
                              and os.stat(real).st_ino == os.stat(source).st_ino):
            return True
        if os.path.isdir(source) and real != source and \
                os.path.commonpath([real, source]) == source:
            first = Path(os.path.relpath(real, source)).parts[0]
            if not records or first in records:
                return True
        if os.path.isdir(source) and os.path.exists(real) and os.path.isfile(real):
            inode = os.stat(real).st_ino
            places = [os.path.join(source, r) for r in records] if records else [source]
            for place in places:
                for folder, _, files in os.walk(place):
                    if any(os.stat(os.path.join(folder, f)).st_ino == inode for f in files):
                        return True
                if os.path.isfile(place) and os.stat(place).st_ino == inode:
                    return True
        if source != real and os.path.commonpath([real, source]) == real:
            return True
    if len(outputs) < 2:
        return False
    first, second = (os.path.realpath(root / o) for o in outputs)
    return first == second or (os.path.exists(first) and os.path.exists(second)
                               and os.stat(first).st_ino == os.stat(second).st_ino)


@settings(max_examples=150, deadline=None, derandomize=True)
@given(output=st.sampled_from(NAMES), second=st.none() | st.sampled_from(NAMES),
       source=st.sampled_from(["run", "beside.txt", "other/x.txt"]),
       records=st.sampled_from([(), ("summary.json", "robots")]))
def test_refused_exactly_when_the_os_says_the_paths_alias(
        output: str, second: str | None, source: str, records: tuple[str, ...]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        tree(root)
        outputs = [output] if second is None else [output, second]
        given_inputs = {"the input": Folder(root / source, records)}
        truth = expected_refusal(root, output, [source], records, outputs) or (
            second is not None and expected_refusal(root, second, [source], records, outputs))
        try:
            check_outputs({f"--o{k}": root / o for k, o in enumerate(outputs)}, given_inputs)
        except MimicsError as exc:
            assert truth, f"refused without cause: {exc}"
            assert "--o" in str(exc) and "\n" not in str(exc)
        else:
            assert not truth, f"{outputs} alias {source} (records {records}) but passed"


def test_outputs_not_given_and_new_paths_elsewhere_pass(tmp_path: Path) -> None:
    tree(tmp_path)
    check_outputs({"--mcap": None, "--bag": tmp_path / "new.bag", "--csv": ""},
                  {"the run folder": tmp_path / "run", "the map": None})


@pytest.mark.parametrize("value", [5, None, [], ["a"], b"run", "", "  ", 1.5, {"a": 1}, "a\0b"])
def test_as_path_names_the_argument_for_anything_but_a_path(value: object) -> None:
    with pytest.raises(MimicsError, match=r"^out: expected a path"):
        as_path("out", value)


def test_as_path_takes_texts_and_paths() -> None:
    assert as_path("out", "a/b") == Path("a/b") == as_path("out", Path("a/b"))
