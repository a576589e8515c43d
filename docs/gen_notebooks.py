"""Make the docs' notebooks from their Markdown pages: ``python docs/gen_notebooks.py``.

The Markdown page is the one source: each notebook is made from it, and
``--check`` (and ``tests/interfaces/notebook/test_notebooks.py``) fails when a
committed notebook differs from what its page makes now, so an edit of the
page reaches the notebook by running this script again. The rules:

- prose becomes Markdown cells; a heading starts a new cell;
- a code block that includes a snippet file (``--8<-- "dir/name"``) is that file:
  an algorithm (a ``.py`` with ``def step`` or ``def team_step``) or a data file
  (``.toml``...) becomes a ``%%writefile name`` cell, as the page asks the reader
  to save it; another Python file becomes a code cell;
- a shell block whose every line is a ``mimics`` command that needs no window
  becomes a ``%%bash`` cell running them (stopping at the first that fails, so
  that a failing command fails the notebook); other blocks (installing, a
  window) stay as listings;
- cells only a notebook has (a run shown in the cell, its plot and replay) are
  added after a section, named by its heading, from :data:`EXTRAS`.

Notebooks are written without outputs (the docs site and the tests run them).
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS))

from notebook_files import cell as _cell  # noqa: E402
from notebook_files import notebook_text, write_or_check  # noqa: E402

SNIPPETS = DOCS / "snippets"
FENCE = re.compile(r"^```([^\n]*)\n(.*?)^```[ \t]*$", re.S | re.M)
INCLUDE = re.compile(r'^--8<-- "([^"]+)"$')
HEADING = re.compile(r"^#{1,6} ", re.M)
#: Commands that open a window or a server: shown, not run, in a notebook.
INTERACTIVE = re.compile(r"^mimics (ui|replay \S+$|replay \S+ --(robot-beams|trail))|--view ")

_IMPORT = "import mimics"
#: Notebook-only cells by page, after the section with that heading ("" = at the top).
EXTRAS: dict[str, dict[str, list[tuple[str, str]]]] = {
    "tutorials/first-algorithm.md": {
        "## 2. Run a built-in simulation": [
            ("markdown", "In a notebook the same run is one call. It shows its summary and its "
                         "trajectories in the cell, and writes nothing unless asked "
                         "(`run.save(\"runs/first\")`):"),
            ("code", f'{_IMPORT}\n\nrun = mimics.simulate("line", "go_to_goal", robots=10, '
                     'time=25, seed=1)\nrun'),
            ("markdown", "Its events are a DataFrame (the columns of the run folder's "
                         "events.parquet); here the ten arrivals:"),
            ("code", 'run.events[run.events["kind"] == "reached_goal"]'),
        ],
        "## 5. See the run": [
            ("markdown", "In the notebook, the same figure as `mimics plot`, and the replay "
                         "playing in the cell (4 simulated seconds per second):"),
            ("code", f'{_IMPORT}\n\nmine = mimics.load_run("runs/mine")\nmine.plot()'),
            ("code", "mine.animate(fps=10, speed=4)"),
        ],
    },
    "how-to/replay-video.md": {
        "": [
            ("markdown", "This notebook first makes the run it replays (`runs/mine`):"),
            ("code", f'{_IMPORT}\n\nrun = mimics.simulate("circle_swap", "wall_aware", '
                     'robots=6, time=40, seed=0, out="runs/mine")\nrun.status'),
        ],
        "## In a window": [
            ("markdown", "In a notebook, the replay plays in the cell instead; `fps` and "
                         "`speed` are those of `--video`:"),
            ("code", "run.animate(fps=10, speed=4)"),
        ],
        "## A still picture": [
            ("markdown", "In a notebook, `run.plot()` is the same figure:"),
            ("code", "run.plot()"),
        ],
    },
    "how-to/team-form.md": {
        "": [
            ("markdown", "In a notebook: both forms on the same 200 robots and seed give the "
                         "same trajectories; the summaries tell the wall time each took."),
            ("code", f'{_IMPORT}\n\nper_robot = mimics.simulate("line", "go_to_goal", '
                     'robots=200, time=10, seed=1)\nteam = mimics.simulate("line", '
                     '"go_to_goal_team", robots=200, time=10, seed=1)\n'
                     'columns = ["time", "step", "robot", "x", "y", "theta", "v", "w"]\n'
                     'same = per_robot.trajectory[columns].equals(team.trajectory[columns])\n'
                     'print("identical trajectories:", same)\n'
                     'print(f"wall time: per robot {per_robot.summary()[\'wall_time\']:.2f} s, "\n'
                     '      f"team {team.summary()[\'wall_time\']:.2f} s")'),
            ("code", "team.plot()"),
        ],
    },
}
#: The notebooks made, by page: ``docs/PAGE.md`` -> ``docs/PAGE-notebook.ipynb``.
PAGES = tuple(EXTRAS)


def notebook_path(page: str) -> Path:
    """Where the notebook of ``page`` goes (beside it; its own name, so that its docs
    page does not take the Markdown page's address)."""
    return DOCS / page.replace(".md", "-notebook.ipynb")


def _code_block(info: str, body: str) -> tuple[str, str]:
    """A fenced block as a cell: (kind, source)."""
    lang = info.strip().split(" ")[0]
    found = INCLUDE.match(body.strip())
    if found:
        name = found.group(1)
        text = (SNIPPETS / name).read_text().rstrip("\n")
        file_name = Path(name).name
        if name.endswith(".sh"):
            return _shell(text, lang or "bash")
        if name.endswith(".py") and not re.search(r"^def (team_)?step\(", text, re.M):
            return "code", text
        return "code", f"%%writefile {file_name}\n{text}"
    if lang in ("", "bash", "sh", "console"):
        return _shell(body.rstrip("\n"), lang)
    return "markdown", f"```{info}\n{body}```"


def _shell(text: str, lang: str) -> tuple[str, str]:
    lines = [line for line in text.splitlines() if line.strip() and not line.startswith("#")]
    if lines and all(line.startswith("mimics ") and not INTERACTIVE.search(line)
                     for line in lines):
        return "code", "\n".join(["%%bash", "set -e", *lines])
    return "markdown", f"```{lang or 'bash'}\n{text}\n```"


def _sections(markdown: str) -> list[tuple[str, str]]:
    """The page cut before each heading: (heading line or "", text)."""
    starts = [m.start() for m in HEADING.finditer(markdown)]
    if not starts or starts[0] != 0:
        starts.insert(0, 0)
    parts = []
    for begin, end in zip(starts, [*starts[1:], len(markdown)], strict=True):
        text = markdown[begin:end]
        first = text.split("\n", 1)[0]
        parts.append((first.strip() if HEADING.match(first) else "", text))
    return parts


def cells_of(page: str) -> list[dict[str, object]]:
    """The cells of ``page``'s notebook."""
    markdown = (DOCS / page).read_text()
    extras = EXTRAS.get(page, {})
    known = {heading for heading, _ in _sections(markdown)} | {""}
    missing = [h for h in extras if h not in known and not h.startswith("# ")]
    if missing:
        raise SystemExit(f"docs/{page}: no section {missing[0]!r} for its notebook cells "
                         "(edit EXTRAS in docs/gen_notebooks.py)")
    cells = []
    for index, (heading, text) in enumerate(_sections(markdown)):
        at = 0
        for found in FENCE.finditer(text):
            prose = text[at:found.start()].strip()
            if prose:
                cells.append(_cell("markdown", prose))
            cells.append(_cell(*_code_block(found.group(1), found.group(2))))
            at = found.end()
        if text[at:].strip():
            cells.append(_cell("markdown", text[at:].strip()))
        if index == 0:  # after the title and its introduction
            cells.extend(_cell(kind, source) for kind, source in extras.get("", []))
        if heading and heading in extras:
            cells.extend(_cell(kind, source) for kind, source in extras[heading])
    return cells


def notebook_of(page: str) -> str:
    """``page``'s notebook as the text written (nbformat 4, no outputs)."""
    note = (f"*This notebook is made from the page `docs/{page}` by "
            "`docs/gen_notebooks.py`: edit the page, then run the script.*")
    return notebook_text([_cell("markdown", note), *cells_of(page)], f"docs/{page}",
                         "docs/gen_notebooks.py")


def main(argv: list[str] | None = None) -> int:
    """Write every notebook, or with ``--check`` list those out of date (status 1)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="write nothing; fail if stale")
    args = parser.parse_args(argv)
    return write_or_check(((notebook_path(page), notebook_of(page)) for page in PAGES),
                          args.check, "docs/gen_notebooks.py", DOCS.parent)


if __name__ == "__main__":
    sys.exit(main())
