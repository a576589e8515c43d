"""The documentation site builds in strict mode (no broken link, no missing page) and offline.

One test builds the site once (a build takes a few seconds) and checks it
from several sides.
"""

import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest
from typer.main import get_command

from mimics.engine.user_code import Robot, Team
from mimics.interfaces.cli.program import app

ROOT = Path(__file__).resolve().parents[2]
# a Sphinx role as Markdown renders it (":func:<code>x</code>") or left as typed
SPHINX_ROLE = re.compile(r":(?:func|mod|class|meth|attr|data|exc|obj|py:\w+):(?:<code>|`)")
REMOTE_ASSET = re.compile(r"<(?:link|script)\b[^>]*\b(?:href|src)=\"(?:https?:)?//", re.I)


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site, built once in strict mode for the tests of this file."""
    folder = tmp_path_factory.mktemp("site")
    # from outside the checkout (issue 54: the snippets' folder and the docstrings' warnings
    # stopped a build run from another folder)
    elsewhere = tmp_path_factory.mktemp("elsewhere")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                           "--config-file", str(ROOT / "mkdocs.yml"), "--site-dir", str(folder)],
                          cwd=elsewhere, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return folder


class NavLinks(HTMLParser):
    """The menu's entries of a built page: (label, target) of every ``md-nav__link`` link
    to a page (not to a heading of this one)."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[tuple[str, str]] = []
        self._href: str | None = None
        self._text: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        if tag == "a" and "md-nav__link" in (found.get("class") or "").split():
            href = found.get("href") or ""
            self._href = None if href.startswith("#") else href
            self._text = []

    def handle_data(self, data: str) -> None:
        if self._href is not None:
            self._text.append(data)

    def handle_endtag(self, tag: str) -> None:
        if tag == "a" and self._href is not None:
            self.links.append((" ".join("".join(self._text).split()), self._href))
            self._href = None


def test_every_page_of_the_menu_has_a_title_of_its_own(site):
    """Issue 54: the tutorial's notebook showed in the menu as a second "Your first
    algorithm in 10 minutes" (mkdocs-jupyter took the notebook's first heading)."""
    parser = NavLinks()
    parser.feed((site / "index.html").read_text(encoding="utf-8"))
    targets: dict[str, set[str]] = {}
    for label, href in parser.links:
        targets.setdefault(label, set()).add(href.rstrip("/").removeprefix("./"))
    assert len(targets) > 30
    shared = {label: hrefs for label, hrefs in targets.items() if len(hrefs) > 1}
    assert not shared, f"menu entries with one title and several pages: {shared}"
    assert targets["Notebook: your first algorithm"] == {"tutorials/first-algorithm-notebook"}


def test_site_builds_strict_offline_with_generated_cli_and_api_pages(site):
    tmp_path = site

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


def test_the_built_site_shows_no_raw_sphinx_roles(site):
    """Docstrings are Markdown on the site: a Sphinx role would show as typed."""
    found = []
    for page in sorted(site.rglob("*.html")):
        text = page.read_text(encoding="utf-8")
        for match in SPHINX_ROLE.finditer(text):
            found.append(f"{page.relative_to(site)}: {text[match.start():match.end() + 60]}")
    assert not found, "raw Sphinx roles in the built site:\n" + "\n".join(found)


def test_the_role_check_sees_a_role_as_the_api_page_renders_it():
    rendered = '<p>A recorded run (use :func:<code>load_run</code>).</p>'
    assert SPHINX_ROLE.search(rendered)
    assert not SPHINX_ROLE.search("<p>ratio 1:2, see <code>load_run</code></p>")


def test_examples_readme_lists_every_example_folder():
    listed = set(re.findall(r"\[(\w+)\]\(\1/\)", (ROOT / "examples/README.md").read_text()))
    folders = {p.name for p in (ROOT / "examples").iterdir()
               if p.is_dir() and not p.name.startswith((".", "_"))}
    assert folders - listed == set(), "folders of examples/ missing from examples/README.md"
    assert listed - folders == set(), "examples/README.md lists folders that do not exist"


def test_the_robot_page_names_every_attribute_an_algorithm_can_read():
    page = (ROOT / "docs/reference/robot-and-team.md").read_text()
    for cls, prefix in ((Robot, "robot."), (Team, "team.")):
        public = {name for klass in cls.__mro__ for name in vars(klass)
                  if not name.startswith("_")} | {
                      name for name in getattr(cls, "__slots__", ()) if not name.startswith("_")}
        missing = sorted(name for name in public if f"`{prefix}{name}" not in page
                         and f", `.{name}`" not in page and f"`, `.{name}" not in page)
        assert not missing, f"{cls.__name__}: not on robot-and-team.md: {missing}"


SECONDS = re.compile(r"\b\d+(?:\.\d+)?(?: to \d+(?:\.\d+)?)? ?s\b")


def test_the_compile_time_is_given_in_one_place_only():
    """The kernels' compile time is stated on the performance page; others link to it."""
    home = ROOT / "docs/explanation/performance.md"
    texts = {path: path.read_text(encoding="utf-8")
             for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]}
    texts[ROOT / "mimics/interfaces/cli/compiling/first_run.py"] = (
        ROOT / "mimics/interfaces/cli/compiling/first_run.py").read_text(encoding="utf-8")
    figures = []
    for path, text in texts.items():
        for paragraph in re.split(r"\n\s*\n", text):
            if path != home and "compil" in paragraph and "kernel" in paragraph:
                figures += [f"{path.relative_to(ROOT)}: {m.group(0)!r} in {paragraph[:80]!r}"
                            for m in SECONDS.finditer(paragraph)]
    assert not figures, "compile times outside docs/explanation/performance.md:\n" + "\n".join(
        figures)
    assert "#the-first-runs-compile" in texts[ROOT / "README.md"]
    assert SECONDS.search(home.read_text(encoding="utf-8").split("### The first run's compile")[1])
