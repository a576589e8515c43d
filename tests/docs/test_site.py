"""The documentation site builds in strict mode (no broken link, no missing page) and offline.

One test builds the site once (a build takes a few seconds) and checks it
from several sides.
"""

import re
import subprocess
import sys
from pathlib import Path

from typer.main import get_command

from mimics.interfaces.cli.program import app

ROOT = Path(__file__).resolve().parents[2]
REMOTE_ASSET = re.compile(r"<(?:link|script)\b[^>]*\b(?:href|src)=\"(?:https?:)?//", re.I)


def test_site_builds_strict_offline_with_generated_cli_and_api_pages(tmp_path):
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                           "--site-dir", str(tmp_path)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr

    for page in ("tutorials/first-algorithm", "reference/cli", "reference/api", "examples",
                 "explanation/performance", "how-to/deadlocks"):
        assert (tmp_path / page / "index.html").is_file(), page

    # offline: no page pulls fonts, styles or scripts from the network
    pages = list(tmp_path.rglob("*.html"))
    assert len(pages) > 20
    for page in pages:
        found = REMOTE_ASSET.search(page.read_text())
        assert found is None, f"{page.relative_to(tmp_path)}: {found.group(0)}"

    # the CLI page is generated from the app: every command is on it
    html = (tmp_path / "reference/cli/index.html").read_text()
    root = get_command(app)
    for name in root.list_commands(root.context_class(root, info_name="mimics")):
        assert f"mimics {name}</code>" in html, name

    # the API page renders the docstrings' first lines, as written in the code
    html = (tmp_path / "reference/api/index.html").read_text()
    assert "Run one simulation and return its outcome" in html
    assert "The outcome of one simulation" in html

    # the examples gallery is made from the examples themselves: each README and its figure
    html = (tmp_path / "examples/index.html").read_text()
    for folder in sorted((ROOT / "examples").glob("*/algorithm.py")):
        name = folder.parent.name
        title = (folder.parent / "README.md").read_text().splitlines()[0].lstrip("# ")
        assert title in html, name
        figure = tmp_path / "images" / "examples" / f"{name}.png"
        assert figure.read_bytes() == (folder.parent / "figure.png").read_bytes(), name
        assert f"images/examples/{name}.png" in html, name
