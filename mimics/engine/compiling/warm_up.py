"""Compile the engine's kernels ahead of a run, in parts that processes can share.

Numba compiles a kernel at its first call and caches it on disk
(``cache=True``): on a fresh install the first run would spend its first steps
compiling. ``mimics run`` compiles ahead instead, one part per process, on
the machine's cores at once:

- ``"index"``: the walls' walking grid, the robots' index and the stall screen;
- ``"motion"``: the checks after the robots move (``motion_checks``: collisions,
  goals and bounds) and the dynamics;
- ``"ray"``: the ranger's ray kernel, the largest part, which only a run that
  reads a scan needs (``WorldState.scan``), and the walls' near lists;
- ``"still"``: the kernels that list what robots standing still can see
  (``still_scans``): only a speed-up, so the first run does not wait for them
  (its robots are not pinned until they are compiled; the scans are the same).

Each part calls its kernels on empty arguments typed exactly as the engine
types them, so the signature compiled ahead is the one runs call (tested:
after a run and a warm-up, each kernel has one signature).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
from numba import njit

from mimics.engine.dynamics import advance_pose, move_robots
from mimics.engine.helper_threads.chunks import LEAD
from mimics.engine.helper_threads.threads import _finish_and_wait, _join, solo_arrays
from mimics.engine.motion_checks import _check_kernel
from mimics.engine.ranging.beam_fan import FAN_COLUMNS, beam_fans
from mimics.engine.ranging.beam_sweep import PLAN
from mimics.engine.ranging.point_cull import no_sight_lists
from mimics.engine.ranging.ranger_noise import _add_noise
from mimics.engine.ranging.ray_kernel import RangerQuery, _cast_rows

# the hook by which the first scan waits for a process compiling the ray part (it lives
# with the scanner that calls it; named here for the first-run compile that sets it)
from mimics.engine.ranging.scanner import _ray_part_elsewhere as _ray_part_elsewhere
from mimics.engine.ranging.scanner import await_ray_part as await_ray_part
from mimics.engine.ranging.scanner import forget_ray_part as forget_ray_part
from mimics.engine.ranging.scanner import (
    ray_part_compiling_elsewhere as ray_part_compiling_elsewhere,
)
from mimics.engine.ranging.still_scans import _pin, _settle
from mimics.engine.ranging.still_scans import forget_still_part as forget_still_part
from mimics.engine.ranging.still_scans import (
    still_part_compiling_elsewhere as still_part_compiling_elsewhere,
)
from mimics.engine.ranging.wall_index import _near_lists
from mimics.engine.ranging.wall_occlusion import MARGIN, cull_hidden
from mimics.engine.robot_index import RobotIndex, _bucket, empty_robot_index
from mimics.engine.spatial_index import SegmentGrid, _build_csr, build_segment_grid
from mimics.engine.stall import _record_and_screen

# a kernel of each part whose index file in Numba's cache tells the part was compiled (named
# again in mimics/interfaces/cli/kernel_cache.py, which the CLI reads before importing Numba:
# a test fails when the two lists differ)
_WITNESSES = {"index": (_build_csr, _bucket, _record_and_screen),
              "motion": (_check_kernel, move_robots, _finish_and_wait, _join),
              "ray": (_cast_rows, _near_lists, cull_hidden, beam_fans, _add_noise),
              "still": (_settle, _pin)}


# Built by hand, not with build_segment_grid or empty_robot_index: those would compile the
# index part's kernels in the motion and ray processes too.
def _empty_grid() -> SegmentGrid:
    return SegmentGrid(np.zeros((0, 4)), np.zeros(0, np.int64), np.zeros(2), 1.0,
                       np.ones(2, np.int64), np.zeros(2, np.int64), np.zeros(0, np.int64))


def _empty_robots() -> RobotIndex:
    return RobotIndex(np.zeros((0, 5, 2)), np.zeros(0), np.zeros((0, 2)), np.zeros(2), 1.0,
                      np.ones(2, np.int64), np.zeros(2, np.int64), np.zeros(0, np.int64), 0.0)


def ready_to_compile() -> None:
    """Set up Numba's compile machinery in this process (its typing and lowering
    registries: 0.2 to 0.3 s of CPU at a process's first compile), by compiling a tiny
    function. Forks made afterwards inherit it instead of each setting it up again."""
    _first_compile(1.0)


@njit(cache=False)
def _first_compile(x: float) -> float:  # pragma: no cover - compiled
    return x + 1.0


def compile_index_kernels() -> None:
    """The walls' walking grid and the robot index (``Simulation`` builds both), and the
    stall screen (small: it balances the two parts)."""
    build_segment_grid(np.zeros((0, 4)), (0.0, 0.0, 1.0, 1.0))
    empty_robot_index()
    none, flags = np.zeros(0), np.zeros(0, bool)
    _record_and_screen(np.zeros((1, 0, 2)), np.zeros((1, 0)), 0, np.zeros((0, 3)), none, flags,
                       flags, flags, 1, 1, 0.1, 0.1)


def compile_motion_kernels() -> None:
    """The checks after the robots move, the dynamics (the odometry's arcs too) and the
    helper threads' waits, for the engine's argument types."""
    none, rows = np.zeros(0), np.zeros((0, 2))
    _check_kernel(tuple(_empty_robots()), none, none, np.zeros(0, np.int64),
                  tuple(_empty_grid()), np.zeros((0, 3)), rows, 0.0, 0.0, 1.0, 1.0, 0.1, none,
                  np.zeros(0, np.int64), *solo_arrays(0), LEAD, 0)
    gains = np.zeros((0, 3))
    move_robots(np.zeros(0, np.int64), rows, rows, rows, rows, rows, rows, none, gains, gains,
                none, none, none, none, 0.1, none, none)
    advance_pose(np.zeros((0, 3)), none, none)  # odometry: else each battery worker compiles it
    control, share = solo_arrays(0)  # the helper threads' waits (checks and rays use them)
    _join(share)
    _finish_and_wait(control, share, False, 0, 1)


def compile_ray_kernel() -> None:
    """The ray kernel, on a query of no robot: no map, index or other kernel is
    needed. The arrays are those the engine passes: C-contiguous and writeable,
    of the canonical dtypes."""
    none = np.zeros((0, 2))
    query = RangerQuery(none, np.zeros(0), np.zeros((0, 1)), np.zeros(0), np.zeros(0, np.int64),
                        np.zeros((0, 1, 2)), np.zeros((0, FAN_COLUMNS)))
    _cast_rows(tuple(query), tuple(_empty_grid()), tuple(_empty_grid()), 0.0,
               tuple(_empty_robots()), tuple(no_sight_lists()), np.zeros((0, 1)),
               np.zeros((0, 1), np.int64), *solo_arrays(0), LEAD, 0)


def compile_ray_helpers() -> None:
    """What the ray kernel's callers need first: the walls' near lists (and their culling),
    the beams' fans; and the ranger's noise (every built-in type's default)."""
    start, items = _near_lists(np.zeros((0, 4)), np.zeros(2), np.ones(2, np.int64), 1.0, 1.0)
    cull_hidden(np.zeros((0, 4)), np.zeros(2), np.ones(2, np.int64), 1.0, start, items, MARGIN)
    beam_fans(np.zeros((1, 1)))
    none, counts = np.zeros(0), np.zeros(0, np.int64)
    _add_noise(np.zeros((0, 1)), np.zeros((0, 1), np.int64), none, none, counts, np.uint64(0),
               *solo_arrays(0), LEAD, 0)


def compile_still_kernels() -> None:
    """The sight lists of robots standing still (``still_scans``)."""
    none, rows, counts, flags = np.zeros(0), np.zeros((0, 2)), np.zeros(0, np.int64), \
        np.zeros(0, bool)
    _settle(rows, rows.copy(), flags, counts, flags.copy(), none, tuple(_empty_robots()))
    _pin(rows, counts, flags, none, none, tuple(_empty_grid()), tuple(_empty_robots()),
         np.zeros((0, 4), np.int64), counts, np.zeros((0, PLAN)), 0)


def compile_ray_part() -> None:
    """The ray part: its kernel first (most of the time), then its helpers, which a
    process waiting for the kernel can compile meanwhile."""
    compile_ray_kernel()
    compile_ray_helpers()


COMPILERS: dict[str, Callable[[], None]] = {
    "index": compile_index_kernels, "motion": compile_motion_kernels, "ray": compile_ray_part,
    "still": compile_still_kernels}
PARTS = tuple(COMPILERS)


def load_step_kernels(ranging: bool) -> bool:
    """Before a run's first step: load the kernels its steps call from the cache (or
    compile them), so that the first step costs what the next ones do. With
    ``ranging`` (some robot has a ranger) the ray kernel and its helpers too, when
    Numba's cache has them and no other process is compiling them (otherwise the
    first scan compiles or waits for them, as a run may never read one).
    Returns whether the ray part was loaded (the run may then index its walls)."""
    if not _step_kernels_loaded:  # once per process (a battery builds thousands of runs)
        compile_index_kernels()
        compile_motion_kernels()
        _step_kernels_loaded.append(True)
    if not ranging or _ray_part_elsewhere:
        return False
    if not _cast_rows.signatures:  # not loaded in this process yet
        if "ray" in missing_parts():  # not compiled: left to the first scan, if any
            return False
        compile_ray_kernel()
        compile_ray_helpers()
    return True


_step_kernels_loaded: list[bool] = []


def compile_part(part: str, *, helpers: bool = True) -> None:
    """Compile one part (``PARTS``): what a process of the first-run compile runs.

    ``helpers=False``: of the ray part, the kernel alone. The run that starts such a
    process compiles the helpers itself meanwhile, at its first scan; compiled in both,
    the ranger's noise took a second of CPU twice (benchmarks/NOTES.md)."""
    if part == "ray" and not helpers:
        compile_ray_kernel()
    else:
        COMPILERS[part]()


def missing_parts() -> list[str]:
    """The parts whose kernels Numba's on-disk cache lacks (all on a fresh install).

    Looks in the folder Numba itself caches each kernel in (beside its module,
    or under ``NUMBA_CACHE_DIR`` when set).
    """
    return [part for part in PARTS
            if not all(any(_cache_folder(kernel).glob(f"{_cache_stem(kernel)}-*.nbi"))
                       for kernel in _WITNESSES[part])]


def _cache_folder(kernel: Callable[..., object]) -> Path:
    """Where Numba caches ``kernel`` (its own locator's choice)."""
    return Path(kernel._cache._cache_path)  # type: ignore[attr-defined]


def _cache_stem(kernel: Callable[..., object]) -> str:
    """How Numba's cache files of ``kernel`` begin: ``module.qualname``."""
    py_func = kernel.py_func  # type: ignore[attr-defined]
    return f"{py_func.__module__.rsplit('.', 1)[-1]}.{py_func.__qualname__}"
