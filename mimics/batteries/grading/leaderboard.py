"""The class's leaderboard: ranked by mark, then by mean time to goal, as CSV and HTML.

Equal marks are ordered by the mean time to goal over the submission's runs
(shorter first; see :func:`mimics.batteries.grading.course.mean_times`); equal
marks and times share a rank (1, 2, 2, 4). The HTML page is one self-contained
file (no script, no link out) in which every value is escaped: ids, names and
reasons come from students' file names and errors.

>>> import pandas as pd
>>> table = pd.DataFrame({"student_id": ["a", "b", "c"], "mark": [7.0, 9.0, 7.0],
...                       "time_to_goal": [30.0, 40.0, 20.0], "reason": ["", "", ""]})
>>> leaderboard(table)[["rank", "student_id"]].values.tolist()
[[1, 'b'], [2, 'c'], [3, 'a']]
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import pandas as pd

from mimics.world.errors import MimicsError

COLUMNS = ("rank", "student_id", "mark", "time_to_goal", "reason")


def leaderboard(table: pd.DataFrame) -> pd.DataFrame:
    """The class table ranked: mark (high first), mean time to goal (short first, unknown
    last), student id; ``rank`` shared by rows with the same mark and time."""
    frame = table.copy()
    frame["time_to_goal"] = pd.to_numeric(frame.get("time_to_goal"), errors="coerce")
    frame["mark"] = pd.to_numeric(frame["mark"], errors="coerce").fillna(0.0)
    key = frame["time_to_goal"].fillna(math.inf)
    frame = frame.assign(_time=key).sort_values(
        ["mark", "_time", "student_id"], ascending=[False, True, True], kind="mergesort")
    ranks: list[int] = []
    previous: tuple[float, float] | None = None
    for position, (mark, time) in enumerate(zip(frame["mark"], frame["_time"], strict=True),
                                            start=1):
        ranks.append(ranks[-1] if previous == (mark, time) else position)
        previous = (mark, time)
    frame["rank"] = ranks
    frame["time_to_goal"] = frame["time_to_goal"].round(2)
    return frame[list(COLUMNS)].reset_index(drop=True)


def write_leaderboard(board: pd.DataFrame, folder: Path, title: str) -> tuple[Path, Path]:
    """``leaderboard.csv`` and ``leaderboard.html`` in ``folder``.

    Raises:
        MimicsError: a file cannot be written.
    """
    csv_path, html_path = folder / "leaderboard.csv", folder / "leaderboard.html"
    try:
        board.to_csv(csv_path, index=False)
        html_path.write_text(leaderboard_html(board, title), encoding="utf-8")
    except OSError as exc:
        raise MimicsError(f"{folder}: cannot write the leaderboard ({exc.strerror})") from None
    return csv_path, html_path


def leaderboard_html(board: pd.DataFrame, title: str) -> str:
    """One self-contained HTML page of the leaderboard, every value escaped."""
    head = "".join(f"<th>{html.escape(name.replace('_', ' '))}</th>" for name in COLUMNS)
    rows = []
    for row in board.itertuples(index=False):
        cells = []
        for name, value in zip(COLUMNS, row, strict=True):
            text = "" if _missing(value) else (f"{value:.1f}" if name == "mark" else str(value))
            align = ' class="num"' if name in ("rank", "mark", "time_to_goal") else ""
            cells.append(f"<td{align}>{html.escape(text)}</td>")
        rows.append(f"<tr>{''.join(cells)}</tr>")
    safe_title = html.escape(title)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{safe_title}</title>
<style>
body {{ font-family: sans-serif; margin: 2em; }}
table {{ border-collapse: collapse; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; }}
td.num {{ text-align: right; }}
tr:nth-child(even) {{ background: #f4f4f4; }}
</style></head><body>
<h1>{safe_title}</h1>
<p>Ranked by mark, then by the mean time to goal over the runs (shorter first; a robot
that did not arrive counts the run's whole time).</p>
<table><thead><tr>{head}</tr></thead>
<tbody>
{chr(10).join(rows)}
</tbody></table>
</body></html>
"""


def _missing(value: object) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value)) or value is pd.NA
