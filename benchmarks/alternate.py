"""Run a benchmark command alternately on a git revision and on the working tree.

    python benchmarks/alternate.py REV [--rounds 3] [--grep REGEX] [--no-warm] -- COMMAND ...

This machine's speed drifts by 10 to 20% within an hour (more in a slow one),
so two figures taken minutes apart say little about a change. This checks
REV out in a temporary git worktree and runs COMMAND there and here in turn,
``--rounds`` times, each run in a fresh process, printing each run's output
under a heading (only the lines matching ``--grep``, if given). A first,
unprinted run in each tree fills its Numba cache (``--no-warm`` skips it).
COMMAND runs from the root of its tree, with that tree first on
``PYTHONPATH`` (an editable install points at this one) and this tree's map
data (``MIMICS_DATA``: the worktree has no ``shared/`` beside it). The benchmarks merge
their figures into ``benchmarks/results.json``: this tree's file is put back
as it was. The worktree is removed at the end.

    python benchmarks/alternate.py HEAD~3 --rounds 2 --grep '^ +100 ' -- \\
        python benchmarks/swarm.py --robots 100 --robot-logs off
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from common import with_data_folder

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "results.json"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("revision", help="the git revision to compare the working tree with")
    parser.add_argument("--rounds", type=int, default=3, help="runs of each tree (default 3)")
    parser.add_argument("--grep", help="print only the output lines matching this regex")
    parser.add_argument("--no-warm", action="store_true",
                        help="no first, unprinted run in each tree (its Numba cache is filled)")
    argv = sys.argv[1:]  # split by hand: the command has options of its own
    split = argv.index("--") if "--" in argv else len(argv)
    args, command = parser.parse_args(argv[:split]), argv[split + 1:]
    if not command:
        parser.error("give the command to run after --")
    if args.rounds < 1:
        parser.error("--rounds: expected a whole number >= 1")
    pattern = re.compile(args.grep) if args.grep else None
    kept = RESULTS.read_bytes() if RESULTS.exists() else None
    scratch = Path(tempfile.mkdtemp(prefix="mimics-alternate-"))
    worktree = scratch / "tree"
    try:
        _git("worktree", "add", "--detach", str(worktree), args.revision)
        try:
            _alternate(command, [(args.revision, worktree), ("working tree", ROOT)],
                       args.rounds, pattern, warm=not args.no_warm)
        finally:
            _git("worktree", "remove", "--force", str(worktree))
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        if kept is not None:
            RESULTS.write_bytes(kept)


def _alternate(command: list[str], trees: list[tuple[str, Path]], rounds: int,
               pattern: re.Pattern[str] | None, warm: bool) -> None:
    """Run ``command`` in each tree in turn, ``rounds`` times, printing what it prints."""
    if warm:
        for _label, tree in trees:
            _run(command, tree)
    for round_ in range(1, rounds + 1):
        for label, tree in trees:
            print(f"== round {round_}: {label}", flush=True)
            for line in _run(command, tree).splitlines():
                if pattern is None or pattern.search(line):
                    print(line, flush=True)


def _run(command: list[str], tree: Path) -> str:
    """``command`` run from ``tree`` with it first on the module path; its output."""
    env = with_data_folder({**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(tree), *filter(None, [os.environ.get("PYTHONPATH")])])})
    done = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True)
    if done.returncode:
        sys.exit(f"{' '.join(command)} failed in {tree} (status {done.returncode}):\n"
                 f"{done.stderr[-2000:]}")
    return done.stdout + done.stderr


def _git(*arguments: str) -> None:
    done = subprocess.run(["git", "-C", str(ROOT), *arguments], capture_output=True, text=True)
    if done.returncode:
        print(f"git {' '.join(arguments)}: {done.stderr.strip()}", file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
