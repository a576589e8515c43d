"""The CLI's Numba-free look at the kernel cache agrees with Numba's own locators.

``mimics.interfaces.cli.kernel_cache`` mirrors ``numba.core.caching`` so that
``mimics run`` can start its compile processes before importing Numba. The
truth here is Numba itself: its locator classes, each kernel's cache folder
and index file name, and ``warm_up.missing_parts``.
"""

import importlib
import inspect
import os
import subprocess
import sys

import pytest
from numba.core import caching

from mimics.engine.compiling import warm_up
from mimics.interfaces.cli import kernel_cache

WITNESSES = [(module, name) for part in kernel_cache.PARTS
             for module, name in kernel_cache.WITNESSES[part]]


def kernel(module: str, name: str):
    return getattr(importlib.import_module(module), name)


def test_the_witnesses_are_warm_ups_own():
    """A witness added to, renamed in or moved out of ``warm_up._WITNESSES`` fails here."""
    assert kernel_cache.PARTS == warm_up.PARTS
    for part in warm_up.PARTS:
        named = tuple(kernel(module, name) for module, name in kernel_cache.WITNESSES[part])
        assert named == warm_up._WITNESSES[part], part
    for module, name in WITNESSES:
        assert kernel(module, name).py_func.__qualname__ == name
        assert inspect.getfile(kernel(module, name).py_func) == kernel_cache.source_file(module)


@pytest.mark.parametrize(("module", "name"), WITNESSES)
def test_each_witness_is_looked_for_where_and_as_numba_caches_it(module, name):
    """This process's Numba settings (NUMBA_CACHE_DIR when the suite sets it, or not)."""
    cache = kernel(module, name)._cache
    assert kernel_cache.cache_folder(module) == cache._cache_path
    assert kernel_cache.index_file_pattern(module, name).fullmatch(
        cache._cache_file._index_name)


@pytest.mark.parametrize(("module", "name"), WITNESSES)
def test_each_locator_numba_would_use_is_mirrored(module, name, tmp_path, monkeypatch):
    py_func = kernel(module, name).py_func
    py_file = inspect.getfile(py_func)
    # NUMBA_CACHE_DIR set: Numba's UserProvidedCacheLocator
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "user"))
    monkeypatch.setattr(caching.config, "CACHE_DIR", str(tmp_path / "user"))
    provided = caching.UserProvidedCacheLocator.from_function(py_func, py_file)
    assert kernel_cache.cache_folder(module) == provided.get_cache_path()
    # unset: __pycache__ beside the module when writable (InTreeCacheLocator)...
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(caching.config, "CACHE_DIR", "")
    in_tree = caching.InTreeCacheLocator.from_function(py_func, py_file)
    if in_tree is not None:
        assert kernel_cache.cache_folder(module) == in_tree.get_cache_path()
    # ... else the user's cache folder (UserWideCacheLocator)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    in_tree_folder = os.path.join(os.path.dirname(py_file), "__pycache__")
    writable = kernel_cache._writable
    monkeypatch.setattr(kernel_cache, "_writable",
                        lambda folder: folder != in_tree_folder and writable(folder))
    user_wide = caching.UserWideCacheLocator.from_function(py_func, py_file)
    assert kernel_cache.cache_folder(module) == user_wide.get_cache_path()
    assert user_wide.get_cache_path().startswith(str(tmp_path / "xdg"))


def test_settings_it_does_not_mirror_leave_the_answer_to_numba(monkeypatch, tmp_path):
    monkeypatch.setenv("NUMBA_CACHE_LOCATOR_CLASSES", "UserWideCacheLocator")
    assert kernel_cache.missing_parts() is None
    monkeypatch.delenv("NUMBA_CACHE_LOCATOR_CLASSES")
    monkeypatch.chdir(tmp_path)
    (tmp_path / ".numba_config.yaml").write_text("CACHE_DIR: elsewhere\n")
    assert kernel_cache.missing_parts() is None


def test_an_empty_cache_lacks_every_part_and_a_filled_one_none(tmp_path, monkeypatch):
    """Against Numba's own answer, in a process whose NUMBA_CACHE_DIR is an empty folder
    and after that process compiled one part; and in this process once all are compiled."""
    for part in warm_up.PARTS:
        warm_up.compile_part(part)
    assert kernel_cache.missing_parts() == warm_up.missing_parts() == []
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert kernel_cache.missing_parts() == list(kernel_cache.PARTS)
    script = ("from mimics.engine.compiling import warm_up; "
              "print(' '.join(warm_up.missing_parts())); "
              "warm_up.compile_part('index'); print(' '.join(warm_up.missing_parts()))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=dict(os.environ), timeout=300, check=True)
    before, after = (line.split() for line in done.stdout.splitlines())
    assert before == list(warm_up.PARTS)
    assert after == [part for part in warm_up.PARTS if part != "index"]
    assert kernel_cache.missing_parts() == after  # now this process reads the same cache


def test_the_check_imports_neither_numpy_nor_numba():
    script = ("import sys; from mimics.interfaces.cli import kernel_cache; "
              "kernel_cache.missing_parts(); "
              "print(sorted(m for m in ('numpy', 'numba', 'mimics.engine') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=120, check=True)
    assert done.stdout.strip() == "[]"
