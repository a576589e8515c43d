"""Compiling once, finding the build again while the file is unchanged, and bad files."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from mimics.native.adapter import native_controller
from mimics.native.build import CompileError, load_native
from mimics.world.errors import AlgorithmError
from tests.native.conftest import ALGORITHMS, EXAMPLES

_LOAD = ("import sys; from mimics.native.build import load_native; "
         "print(load_native(sys.argv[1]).compiled)")


def _fresh_copy(tmp_path: Path, name: str, tag: str) -> Path:
    """The C go_to_goal under a new name, with a comment that makes its content new."""
    path = tmp_path / name
    path.write_text(f"/* {tag} */\n" + (EXAMPLES / "c" / "go_to_goal.c").read_text())
    return path


def _load_in_child(path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", _LOAD, str(path)], capture_output=True,
                          text=True, check=False, env=os.environ.copy())


def test_a_file_compiles_once_and_is_reloaded_from_the_cache(tmp_path: Path,
                                                             native_cache: Path) -> None:
    source = _fresh_copy(tmp_path, "mine.c", f"cache test {tmp_path}")
    first = load_native(source)
    assert first.compiled
    assert first.folder.parent == native_cache / "native"
    (library,) = [p for p in first.folder.iterdir() if p.suffix == ".so"]
    stamp = library.stat().st_mtime_ns
    # another process (as a battery worker) finds the build and does not compile
    again = _load_in_child(source)
    assert again.returncode == 0, again.stderr
    assert again.stdout.strip() == "False"
    assert library.stat().st_mtime_ns == stamp
    # a change of content is a new build
    source.write_text(source.read_text() + "\n/* changed */\n")
    changed = load_native(source)
    assert changed.compiled and changed.folder != first.folder
    assert not [p for p in (native_cache / "native").iterdir() if p.name.startswith(".build")]


def test_workers_building_the_same_file_at_once_share_one_build(tmp_path: Path,
                                                                native_cache: Path) -> None:
    source = _fresh_copy(tmp_path, "raced.c", f"race test {tmp_path}")
    children = [subprocess.Popen([sys.executable, "-c", _LOAD, str(source)],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                for _ in range(2)]
    outputs = [child.communicate() for child in children]
    assert [child.returncode for child in children] == [0, 0], outputs
    assert "True" in [out.strip() for out, _ in outputs]  # somebody compiled it
    assert load_native(source).compiled is False  # one finished build, found by all
    assert not [p for p in (native_cache / "native").iterdir() if p.name.startswith(".build")]


def test_a_compile_error_is_the_compilers_first_error_with_file_and_line() -> None:
    with pytest.raises(CompileError) as caught:
        load_native(ALGORITHMS / "syntax_error.c")
    message = str(caught.value)
    assert message.startswith(f"{ALGORITHMS / 'syntax_error.c'}:7:5: error: ")
    assert "undeclared_name" in message and "\n" not in message


def test_a_file_without_the_header_or_an_entry_point_is_refused() -> None:
    with pytest.raises(AlgorithmError, match=r"no_header\.c: it does not include mimics\.h"):
        load_native(ALGORITHMS / "no_header.c")
    with pytest.raises(AlgorithmError, match=r"no_entry_point\.c: define int mimics_step"):
        native_controller(ALGORITHMS / "no_entry_point.c")


def test_a_missing_file_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(AlgorithmError, match="does not exist"):
        load_native(tmp_path / "nothing.c")
