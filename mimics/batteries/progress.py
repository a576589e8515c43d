"""A battery's progress bar: runs done out of total, failures, rate and ETA.

Shown with Rich on a terminal, on stderr; silent when stderr is not a
terminal (a battery started by cron or nohup writes nothing per run).
"""

from __future__ import annotations

from types import TracebackType

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    Task,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)
from rich.text import Text

from mimics.batteries.tasks import FAILED_STATES


class RateColumn(ProgressColumn):
    """Runs per second, or per minute when slower than one a second."""

    def render(self, task: Task) -> Text:
        """The rate of the task, e.g. ``"3.2 runs/s"``."""
        speed = task.finished_speed or task.speed
        if not speed:
            return Text("-- runs/s", style="progress.data.speed")
        text = f"{speed:.1f} runs/s" if speed >= 1 else f"{speed * 60:.1f} runs/min"
        return Text(text, style="progress.data.speed")


class BatteryProgress:
    """Progress of one battery session (a context manager).

    Args:
        total: runs in the battery.
        finished: runs already finished before this session (done or failed).
        failed: runs already failed before this session.
        enabled: show the bar (None: only when stderr is a terminal).
        console: where to draw (default: stderr).
    """

    def __init__(self, total: int, finished: int = 0, failed: int = 0, *,
                 enabled: bool | None = None, console: Console | None = None) -> None:
        self.console = console or Console(stderr=True)
        self.enabled = self.console.is_terminal if enabled is None else enabled
        self.failed = failed
        self._progress: Progress | None = None
        if self.enabled:
            self._progress = Progress(
                TextColumn("[bold]battery"), BarColumn(), MofNCompleteColumn(),
                TextColumn("[red]{task.fields[failed]} failed"), RateColumn(),
                TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                console=self.console)
            self._task = self._progress.add_task("runs", total=total, completed=finished,
                                                 failed=failed)

    def __enter__(self) -> BatteryProgress:
        if self._progress is not None:
            self._progress.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        if self._progress is not None:
            self._progress.stop()

    def grow(self, runs: int) -> None:
        """A stopping rule listed ``runs`` more runs."""
        if self._progress is not None:
            self._progress.update(self._task, total=self._progress.tasks[0].total + runs)

    def advance(self, state: str) -> None:
        """One more run finished in ``state``."""
        if state in FAILED_STATES:
            self.failed += 1
        if self._progress is not None:
            self._progress.update(self._task, advance=1, failed=self.failed)
