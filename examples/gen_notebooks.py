"""Make each gallery example's notebook: ``python examples/gen_notebooks.py``.

``examples/NAME/notebook.ipynb`` runs the example as ``gallery.py`` does (its
scenario, robots, time and seed, from :data:`gallery.EXAMPLES`), shows the run
in the cell, plays its replay, and says what to try; its text is the top of
the example's README, whose last line links the notebook. ``--check`` writes
nothing and fails (status 1) when a notebook is not what this script makes now
(``tests/interfaces/notebook/test_notebooks.py`` runs it).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent / "docs")]

from gallery import EXAMPLES, Example  # noqa: E402
from notebook_files import cell as _cell  # noqa: E402
from notebook_files import notebook_text, write_or_check  # noqa: E402

NOTEBOOK = "notebook.ipynb"
LINK = f"[Open it as a notebook]({NOTEBOOK}): run it, replay it and change it in a cell."


def _call(scenario: str, options: str, example: Example) -> str:
    """The ``simulate`` line, broken before ``time=`` when it would pass 100 characters."""
    line = (f"run = mimics.simulate({scenario!r}, 'algorithm.py'{options}, "
            f"time={example.time!r}, seed={example.seed!r})")
    if len(line) <= 100:
        return line
    return (f"run = mimics.simulate({scenario!r}, 'algorithm.py'{options},\n"
            f"                      time={example.time!r}, seed={example.seed!r})")


def introduction(name: str) -> str:
    """The README's title and text up to its first code block."""
    text = (HERE / name / "README.md").read_text()
    return text.split("```", 1)[0].strip()


def notebook_of(name: str) -> str:
    """Example ``name``'s notebook as written (nbformat 4, no outputs)."""
    example = EXAMPLES[name]
    scenario = example.scenario  # a built-in name, or a file relative to the example
    options = "".join(f", {key}={value!r}" for key, value in example.params.items()
                      if key == "robots")
    params = {k: v for k, v in example.params.items() if k != "robots"}
    if params:
        options += f", params={params!r}"
    cells = [
        _cell("markdown", introduction(name)),
        _cell("markdown", "Run it (the notebook's folder is the example's: `algorithm.py` "
                          "is the algorithm; edit it and run the cells again). The cell "
                          "shows the summary and the trajectories:"),
        _cell("code", f"import mimics\n\n{_call(scenario, options, example)}\nrun"),
        _cell("markdown", "The replay, playing in the cell:"),
        _cell("code", "run.animate()"),
        _cell("markdown", "What happened, by kind of event (`run.events` has one row per "
                          "event, `run.trajectory` one per robot per step):"),
        _cell("code", 'run.events.groupby("kind").size().to_frame("events")'),
        _cell("markdown", f"Watch it live, with Play/Pause/Step/Stop: "
                          f"`mimics.show({scenario!r}, 'algorithm.py'{options}, "
                          f"time={example.time!r})`; keep the run with `run.save(\"runs/"
                          f"{name}\")` (then `mimics report runs/{name}`)."),
    ]
    return notebook_text(cells, "examples/gallery.py", "examples/gen_notebooks.py")


def main(argv: list[str] | None = None) -> int:
    """Write every example's notebook, or with ``--check`` list the stale ones (status 1)."""
    check = "--check" in (sys.argv[1:] if argv is None else argv)
    if not check:
        for name in EXAMPLES:  # the README's last line links the notebook
            readme = (HERE / name / "README.md").read_text()
            if LINK not in readme:
                (HERE / name / "README.md").write_text(readme.rstrip("\n") + f"\n\n{LINK}\n")
    return write_or_check(((HERE / name / NOTEBOOK, notebook_of(name)) for name in EXAMPLES),
                          check, "examples/gen_notebooks.py", HERE.parent,
                          lambda path: LINK not in (path.parent / "README.md").read_text())


if __name__ == "__main__":
    sys.exit(main())
