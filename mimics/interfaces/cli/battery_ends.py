"""How a battery command ends: interrupted (Ctrl-C: what is kept, how to go on) or
finished (its line, warnings, and the runs that could not finish, exit status 1)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.console import Console

from mimics.interfaces.cli.battery_args import table_console


def interrupted(folder: Path) -> typer.Exit:
    Console(stderr=True, highlight=False).print(
        f"interrupted: finished runs are kept; go on with `mimics battery resume {folder}`",
        markup=False)
    return typer.Exit(130)



def finished(result: Any) -> None:
    table_console().print(result.line(), markup=False)
    from mimics.interfaces.cli.battery_report import print_warnings

    print_warnings(result.folder)
    if result.adopted:
        table_console().print(f"({result.adopted} run(s) had finished just before the battery "
                              "stopped: kept)", markup=False)
    table_console().print(f"table: `mimics battery report {result.folder}`", markup=False)
    from mimics.batteries.tasks import FAILED_STATES

    failed = {state: result.counts.get(state, 0) for state in FAILED_STATES
              if result.counts.get(state, 0)}
    if failed:
        total = sum(result.counts.values())
        states = ", ".join(f"{n} {state}" for state, n in failed.items())
        # Running again helps only what the machine caused: a run's own exception
        # (state error) repeats with the same seed, so it is not suggested for those.
        again = [state for state in ("timeout", "crashed") if state in failed]
        advice = (f"; runs that timed out or crashed may finish when run again: `mimics "
                  f"battery rerun-failed {result.folder} "
                  + " ".join(f"--state {state}" for state in again) + "`" if again else "")
        if "error" in failed:
            advice += ("; an error is the algorithm's own exception and repeats with the same "
                       "seed: fix the code, then run the battery again")
        Console(stderr=True, highlight=False, soft_wrap=True).print(
            f"mimics: {sum(failed.values())} of {total} runs could not finish ({states}): see "
            f"`mimics battery status {result.folder}`{advice}", markup=False)
        raise typer.Exit(1)  # exit status 1: some runs could not run (`mimics --help`)
