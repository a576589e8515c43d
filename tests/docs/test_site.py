"""The documentation site builds in strict mode (no broken link, no missing page) and offline."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
REMOTE_ASSET = re.compile(r"<(?:link|script)\b[^>]*\b(?:href|src)=\"(?:https?:)?//", re.I)


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                           "--site-dir", str(out)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return out


def test_every_page_in_the_nav_is_built(site):
    for page in ("tutorials/first-algorithm", "reference/cli", "reference/api",
                 "explanation/performance", "how-to/deadlocks"):
        assert (site / page / "index.html").is_file(), page


def test_no_page_loads_fonts_or_scripts_from_the_network(site):
    pages = list(site.rglob("*.html"))
    assert len(pages) > 20
    for page in pages:
        found = REMOTE_ASSET.search(page.read_text())
        assert found is None, f"{page.relative_to(site)}: {found.group(0)}"


def test_the_cli_page_lists_every_command(site):
    from typer.main import get_command

    from mimics.interfaces.cli.program import app

    html = (site / "reference/cli/index.html").read_text()
    root = get_command(app)
    ctx = root.context_class(root, info_name="mimics")
    for name in root.list_commands(ctx):
        assert f"mimics {name}</code>" in html, name


def test_the_api_page_renders_docstrings(site):
    html = (site / "reference/api/index.html").read_text()
    # first lines of the docstrings, as written in the code
    assert "Run one simulation and return its outcome" in html
    assert "The outcome of one simulation" in html
