"""MkDocs hook: the examples gallery page, built from ``examples/*/README.md`` at build time.

``docs/examples.md`` holds the marker ``<!-- mimics-examples -->``; this hook
replaces it with each example's README (headings one level down, links to
files of the example turned into paths in the repository) and adds each
example's ``figure.png`` to the site as ``images/examples/NAME.png``, so the
gallery cannot drift from the examples the tests run.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

MARKER = "<!-- mimics-examples -->"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def example_folders() -> list[Path]:
    """The gallery's examples, in the order of ``examples/README.md``'s table."""
    listed = re.findall(r"(?m)^\| \[(\w+)\]\(\1/\)", (EXAMPLES / "README.md").read_text())
    return [EXAMPLES / name for name in listed
            if all((EXAMPLES / name / part).is_file()
                   for part in ("algorithm.py", "README.md", "figure.png"))]


def example_markdown(folder: Path) -> str:
    """One example's README as a section of the gallery page."""
    text = (folder / "README.md").read_text(encoding="utf-8")
    text = re.sub(r"(?m)^(#+) ", lambda m: "#" + m.group(1) + " ", text)
    text = text.replace("](figure.png)", f"](images/examples/{folder.name}.png)")
    # links to the example's own files or to other examples: plain repository paths
    text = re.sub(r"\[([^\]]+)\]\((?!https?:|images/)([^)]+)\)",
                  lambda m: f"{m.group(1)} (`examples/{folder.name}/{m.group(2)}`)", text)
    return text.strip() + "\n"


def on_files(files: Any, config: Any, **_: Any) -> Any:
    """Add every example's figure to the site."""
    from mkdocs.structure.files import File

    for folder in example_folders():
        files.append(File.generated(config, f"images/examples/{folder.name}.png",
                                    abs_src_path=str(folder / "figure.png")))
    return files


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    """Fill the gallery page's marker."""
    if MARKER in markdown:
        return markdown.replace(MARKER, "\n".join(example_markdown(f)
                                                  for f in example_folders()))
    return markdown
