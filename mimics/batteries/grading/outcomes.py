"""What happened in each run of a submission, in words a student can act on.

A battery records a run's state (``done``, ``error``, ``timeout``, ``crashed``),
its counts, its error message and traceback. :func:`first_error` finds in them
where the submission failed (kind, exception, file, line, the source line) and
:func:`reason` sums a submission's runs up in one plain sentence, the reason for
its mark: ``"8 of 10 robots home without collision on 3 of 3 runs"``, ``"raised
ValueError at submissions/bob.py:12 on seed 2 (crossroads)"``, ``"stopped: step
did not return within 2 s (submissions/eve.py:7)"``, ``"file did not load:
SyntaxError at line 3 (expected ':')"``.

>>> site = ErrorSite("raised", "ValueError", "submissions/bob.py", 12, "x = 1 / 0",
...                  "boom", "crossroads", 2)
>>> site.sentence()
'raised ValueError at submissions/bob.py:12 on seed 2 (crossroads)'
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

#: The run states that are failures of the run (a ``done`` run finished, whatever its score).
FAILED = ("error", "timeout", "crashed")

_FRAME = re.compile(r'File "(?P<path>[^"]+)", line (?P<line>\d+)')
_SYNTAX = re.compile(r", line (?P<line>\d+): syntax error: (?P<msg>.*)")
_IMPORT = re.compile(r", line (?P<line>\d+): importing it raised (?P<exc>[\w.]+): ?(?P<msg>.*)")
_LOAD_HANG = re.compile(r", line (?P<line>\d+): importing it did not finish within "
                        r"(?P<secs>[\d.]+) s")
_STEP_HANG = re.compile(r"step\(\) did not return within the wall limit of (?P<secs>[\d.]+) s")
_RAISED = re.compile(r"^(?P<exc>[A-Za-z_][\w.]*) in robot \d+ at t=[\d.]+ s")
_PLACE = re.compile(r"(?P<file>[^\s,:\"']+\.py):(?P<line>\d+)")
_RETURNED = re.compile(r"step\(\) returned (?P<what>[^(]*)(?:\((?P<values>[^)]*)\))?")
_LIMIT = re.compile(r"\(limit (?P<secs>[\d.]+) s\)")


@dataclass(frozen=True)
class ErrorSite:
    """Where and how a run failed.

    Attributes:
        kind: ``raised`` (an exception in the running code), ``load`` (the file did not
            load: syntax error, failed import), ``load_hang`` (loading it did not end),
            ``hang`` (a step did not return), ``slow`` (the run as a whole passed the
            time-out), ``crashed`` (the worker process died) or ``other``.
        exception: the exception's class name ("" when none).
        file: the submission as the teacher names it (``submissions/bob.py``).
        line: the line in that file (0 when unknown).
        source: that line's text, stripped ("" when unknown).
        message: the error's own message, on one line.
        scenario: the run's scenario.
        seed: the run's seed.
        seconds: the time-out in seconds, for hangs (NaN otherwise).
    """

    kind: str
    exception: str
    file: str
    line: int
    source: str
    message: str
    scenario: str
    seed: int
    seconds: float = math.nan

    def place(self) -> str:
        """``submissions/bob.py:12`` (or the file alone when the line is unknown)."""
        return f"{self.file}:{self.line}" if self.line else self.file

    def sentence(self) -> str:
        """The failure in one clause, naming the seed and scenario where it is the run's."""
        where = f"on seed {self.seed} ({self.scenario})"
        secs = f"{self.seconds:g} s" if math.isfinite(self.seconds) else "the time-out"
        if self.kind == "load":
            what = self.exception or "an error"
            detail = f" ({self.message})" if self.message else ""
            return f"file did not load: {what} at line {self.line}{detail}"
        if self.kind == "load_hang":
            return f"stopped: loading the file did not finish within {secs} (line {self.line})"
        if self.kind == "hang":
            return f"stopped: step did not return within {secs} ({self.place()}) {where}"
        if self.kind == "slow":
            return f"stopped: the run took longer than {secs} of wall-clock time {where}"
        if self.kind == "raised" and (bad := _RETURNED.search(self.message)) is not None:
            values = [v.strip() for v in (bad["values"] or "").split(",") if v.strip()]
            odd = [v for v in values if re.search(r"nan|inf", v, re.IGNORECASE)] or values
            shown = f" ({', '.join(odd)})" if odd else ""
            return f"step returned {bad['what'].strip()}{shown} at {self.place()} {where}"
        if self.kind == "raised":
            return f"raised {self.exception or 'an exception'} at {self.place()} {where}"
        if self.kind == "crashed":
            return f"crashed {where}: {self.message}"
        return f"failed {where}: {self.message}"


def shown_path(ref: str, base: Path | None) -> str:
    """A submission's path as the teacher names it: relative to the battery file's folder
    when inside it, else its file name."""
    path = Path(ref)
    if base is not None:
        try:
            return path.resolve().relative_to(base.resolve()).as_posix()
        except ValueError:
            pass
    return path.name


def first_error(runs: pd.DataFrame, base: Path | None = None) -> ErrorSite | None:
    """The first failed run's failure (in the battery's order), or None when every run
    finished."""
    failed = runs[runs["state"].isin(FAILED)]
    if failed.empty:
        return None
    row = battery_order(failed).iloc[0].to_dict()
    return error_site(row, base)


def battery_order(runs: pd.DataFrame) -> pd.DataFrame:
    """Runs in the battery's order (its run ids: scenario as listed, parameters, seed)."""
    order = [c for c in ("id",) if c in runs.columns] or [
        c for c in ("scenario", "label", "seed") if c in runs.columns]
    return runs.sort_values(order) if order else runs


def error_site(row: dict[str, Any], base: Path | None = None) -> ErrorSite:
    """Where one failed run (a row of the runs table) failed."""
    ref = str(row.get("algorithm_ref") or "")
    error = _text(row.get("error"))
    trace = _text(row.get("traceback"))
    head = error.splitlines()[0] if error else ""
    shown = shown_path(ref, base) if ref else ""
    line, exception = 0, ""
    frames = [(m["path"], int(m["line"])) for m in _FRAME.finditer(trace)]
    mine = [n for p, n in frames if ref and _same_file(p, ref)]
    if mine:  # the deepest frame in the submission: where its own code was
        line = mine[-1]
    last = [x for x in trace.strip().splitlines() if x.strip()]
    if last and ":" in last[-1] and not last[-1].startswith(" "):
        exception = last[-1].split(":")[0].rsplit(".", 1)[-1]
    elif last and not last[-1].startswith(" "):
        exception = last[-1].strip().rsplit(".", 1)[-1]
    state = str(row.get("state") or "")
    scenario, seed = str(row.get("scenario") or ""), int(row.get("seed") or 0)
    seconds = math.nan
    kind = "other"
    message = head
    if (m := _SYNTAX.search(head)) is not None:
        kind, exception, line, message = "load", "SyntaxError", int(m["line"]), m["msg"]
    elif (m := _IMPORT.search(head)) is not None:
        kind, exception, message = "load", m["exc"].rsplit(".", 1)[-1], m["msg"]
        line = line or int(m["line"])
    elif (m := _LOAD_HANG.search(head)) is not None:
        kind, line, seconds = "load_hang", int(m["line"]), float(m["secs"])
    elif (m := _STEP_HANG.search(head)) is not None:
        kind, seconds, exception = "hang", float(m["secs"]), ""
    elif state == "timeout":
        kind = "slow"
        if (m := _LIMIT.search(head)) is not None:
            seconds = float(m["secs"])
    elif state == "crashed":
        kind = "crashed"
    elif (m := _RAISED.search(head)) is not None:
        kind, exception = "raised", m["exc"].rsplit(".", 1)[-1]
    elif exception and mine:
        kind = "raised"
    if not line and kind in ("raised", "hang", "other"):
        place = next((m for m in _PLACE.finditer(error) if Path(m["file"]).name ==
                      Path(ref).name), None)
        line = int(place["line"]) if place else 0
    if kind == "other" and not head:
        message = f"the run ended in state {state or 'unknown'}"
    return ErrorSite(kind, exception, shown, line, source_line(ref, line),
                     _one_line(_unpath(message, ref, shown)), scenario, seed, seconds)


def source_line(path: str, line: int) -> str:
    """Line ``line`` of the file at ``path``, stripped ("" when unreadable)."""
    if not path or line < 1:
        return ""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, text in enumerate(handle, start=1):
                if number == line:
                    return text.strip()
    except OSError:
        return ""
    return ""


def reason(runs: pd.DataFrame, base: Path | None = None) -> str:
    """One plain sentence: why a submission's runs earned what they did.

    Failures come first (the first failed run's place, and how many runs failed),
    then what the finished runs did: robots home, collisions, deadlocks.
    """
    if runs.empty:
        return "no submission"
    total = len(runs)
    unfinished = int(runs["state"].isin(("pending", "running")).sum())
    failed = runs[runs["state"].isin(FAILED)]
    done = runs[runs["state"] == "done"]
    site = first_error(runs, base)
    parts: list[str] = []
    if site is not None:
        if site.kind in ("load", "load_hang") and len(failed) == total:
            return site.sentence()  # the same for every run: once is enough
        parts.append(f"{site.sentence()}; {len(failed)} of {total} runs failed")
    if not done.empty:
        robots = int(_counts(done, "goal_robots", "robots").sum())
        home = int(_counts(done, "reached_goal").sum())
        collided = int((_counts(done, "collisions") > 0).sum())
        deadlocked = int(_counts(done, "deadlocks").sum())
        runs_text = (f"{len(done)} of {total} runs" if site is None and not unfinished
                     else f"the {len(done)} finished runs")
        text = (f"{home} of {robots} robots home without collision on {runs_text}"
                if collided == 0 else f"{home} of {robots} robots home on {runs_text}, "
                f"with collisions in {collided} of them")
        if deadlocked:
            text += f", {deadlocked} removed as deadlocked (no progress)"
        parts.append(text)
    if unfinished:
        parts.append(f"{unfinished} runs not run yet")
    return "; ".join(parts)


def _counts(rows: pd.DataFrame, *columns: str) -> pd.Series:
    """The first of ``columns`` present, as floats (missing counts 0)."""
    for column in columns:
        if column in rows.columns:
            values = pd.to_numeric(rows[column], errors="coerce")
            if values.notna().any():
                return values.fillna(0.0).astype(float)
    return pd.Series(0.0, index=rows.index)


def _same_file(a: str, b: str) -> bool:
    try:
        return Path(a).resolve() == Path(b).resolve()
    except OSError:
        return a == b


def _text(value: Any) -> str:
    return value if isinstance(value, str) else ""


def _unpath(text: str, ref: str, shown: str) -> str:
    """The teacher's absolute paths in a message shown as the submission's short name."""
    return text.replace(ref, shown) if ref and shown else text


def _one_line(text: str, limit: int = 200) -> str:
    flat = " ".join(text.split())
    return flat if len(flat) <= limit else flat[:limit - 3] + "..."
