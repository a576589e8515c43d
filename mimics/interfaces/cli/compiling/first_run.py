"""The first run after an install: compile the kernels ahead, on every core, before the run.

``mimics run`` and ``mimics ros`` wrap their run in :func:`kernels_compiled_ahead`.
What Numba's disk cache lacks is compiled in parallel (``mimics.engine.compiling.warm_up``):
the index part here, the motion part and the ray kernel each in a process of its
own, the ray kernel's helpers here at the first scan. The run starts once index and
motion are ready, so its summary reports the simulation's own speed. The ray part,
the largest, only matters to a run that reads a scan: its first scan waits for that
process (and compiles the helpers meanwhile); a run that
reads none (``go_to_goal``) never waits, and the process is stopped when the
run ends (the next run that scans compiles it then). The still part (what
robots standing still can see) is only a speed-up: no run waits for it, its
robots are pinned once it is done; while the ray part is missing, it starts
once that part is done (a run that reads no scan leaves it to the next). The
time spent compiling or waiting is on ``mimics.engine.compiling.compile_clock``, which
the summary reports on a line of its own and the run's wall time leaves out.

A compile process is a fork of the run's process, made once the run has imported
the engine, where that is safe (:mod:`mimics.interfaces.cli.compiling.processes`):
it compiles at once, without importing NumPy, Numba and the engine again. Where
it is not (another OS, or threads running), it is a fresh interpreter, started as
soon as the CLI enters :func:`compiles_started`, which tells what the cache lacks
without Numba (:mod:`mimics.interfaces.cli.kernel_cache`), so that its imports
overlap the run's own.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

# nothing of mimics.engine here: importing it imports Numba (start_compiles runs before);
# the module itself, not the package's __init__ (which imports the commands: a circle)
import mimics.interfaces.cli.kernel_cache as kernel_cache
from mimics.interfaces.cli.compiling.processes import CompileProcess, can_fork, start_compile
from mimics.interfaces.cli.output import note

# the parts start_compiles found missing and the processes it started for them (none yet
# when they are to be forks of the run, made once it has imported the engine)
_started: list[tuple[list[str], dict[str, CompileProcess]]] = []


def start_compiles() -> None:
    """Tell what Numba's cache lacks, before this process imports Numba, and start
    compiling it when the compiles cannot be forks of this process.

    :func:`kernels_compiled_ahead` then starts or waits for these processes. Does
    nothing when the cache cannot be read without Numba (that function starts them)."""
    stop_compiles()  # any left by an earlier command of this process that failed
    missing = kernel_cache.missing_parts()
    if missing is not None:
        _announce(missing)
        _started.append((missing, {} if can_fork() else _start(missing)))


@contextmanager
def compiles_started() -> Iterator[None]:
    """:func:`start_compiles`, then the ``with`` block (the command's checks and heavy
    imports); the compiles are stopped if the block raises (no run follows)."""
    start_compiles()
    try:
        yield
    except BaseException:
        stop_compiles()
        raise


def stop_compiles() -> None:
    """Stop the processes :func:`start_compiles` started (the command ends before its run)."""
    while _started:
        for process in _started.pop()[1].values():
            process.kill()
            process.wait()


def _announce(missing: list[str]) -> None:
    if {"index", "motion"} & set(missing):  # what every run waits for (ray: at a scan)
        # No figure here: the measured one lives in docs/explanation/performance.md alone
        note("mimics: first run: compiling the simulation kernels (once: they are cached on "
             "disk for the next runs)")


def _start(missing: list[str]) -> dict[str, CompileProcess]:
    """The compile processes of the missing parts but the index part (this process's)
    and, while the ray part is missing, the still part (started once the ray part is
    done: even at the lowest priority it took the others' CPU; benchmarks/NOTES.md)."""
    return {part: start_compile(part) for part in missing
            if part != "index" and not (part == "still" and "ray" in missing)}


@contextmanager
def kernels_compiled_ahead() -> Iterator[None]:
    """Compile what Numba's cache lacks around the run in the ``with`` block."""
    from mimics.engine.compiling import waiting, warm_up

    if _started:
        missing, aside = _started.pop()
    else:
        missing = warm_up.missing_parts()
        _announce(missing)
        aside = {}
    if not aside and set(missing) - {"index"}:
        if can_fork() and "index" in missing:  # this process compiles too: it sets up
            warm_up.ready_to_compile()         # Numba's compile machinery once, for the forks
        aside = _start(missing)  # forks: now that the engine is imported
    if not missing:
        yield
        return
    # the parts to start once the ray part is done (at the run's first scan)
    later = ["still"] if "still" in missing and "still" not in aside else []
    try:
        if "index" in missing:
            warm_up.compile_index_kernels()
        if "motion" in aside:
            with waiting():
                aside["motion"].wait()
        if "ray" in aside:
            warm_up.ray_part_compiling_elsewhere(lambda: _await_ray(aside, later))
        if "still" in aside:
            _still_part_elsewhere(aside["still"])
        yield
    finally:
        later.clear()  # the run is over: nothing more to start
        for process in aside.values():
            if process.poll() is None:  # the ray part, unneeded: the next scanning run's
                process.kill()
            process.wait()
        warm_up.forget_ray_part()  # a wait the run never needed
        warm_up.forget_still_part()


def _await_ray(aside: dict[str, CompileProcess], later: list[str]) -> None:
    from mimics.engine.compiling.warm_up import compile_ray_helpers

    process = aside["ray"]
    if process.poll() is None:
        note("mimics: first run that reads the laser: finishing the ray kernel's compile "
             "(once: it is cached on disk for the next runs)")
    compile_ray_helpers()  # here, while the process compiles the kernel itself
    process.wait()
    if later and process.returncode == 0:  # their turn, the ray part done
        aside.update(_start(later))
        later.clear()
        _still_part_elsewhere(aside["still"])


def _still_part_elsewhere(process: CompileProcess) -> None:
    """Never waited for: the robots standing still are pinned once it is done."""
    from mimics.engine.compiling.warm_up import still_part_compiling_elsewhere

    still_part_compiling_elsewhere(lambda: process.poll() is not None)
