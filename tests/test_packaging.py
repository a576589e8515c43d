"""The distribution a class installs: the sdist and the wheel built from it (``python -m
build``), both passing ``twine check``, under a name not taken on PyPI, with everything a
course needs inside the wheel and no tests or benchmarks (issue 54)."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from email.parser import Parser
from pathlib import Path

import pytest
import yaml

import mimics

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
# what is not part of a source tree (the checkout is shared: the build runs on a copy)
NOT_SOURCE = shutil.ignore_patterns(".git", ".venv", "venv", "runs", "build", "dist", "site",
                                    "__pycache__", "*.egg-info", ".cache", ".hypothesis",
                                    ".pytest_cache", ".ruff_cache", "node_modules")

@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The sdist and the wheel, the wheel built from the sdist as ``python -m build`` does."""
    work = tmp_path_factory.mktemp("packaging")
    source = work / "source"
    shutil.copytree(ROOT, source, ignore=NOT_SOURCE)
    # no isolation: the build backend is this environment's setuptools (no download)
    done = subprocess.run([sys.executable, "-m", "build", "--no-isolation", "--outdir",
                           str(work / "dist"), str(source)], capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    (wheel,) = (work / "dist").glob("*.whl")
    (sdist,) = (work / "dist").glob("*.tar.gz")
    return {"wheel": wheel, "sdist": sdist}


def test_both_pass_twine_check(built: dict[str, Path]) -> None:
    done = subprocess.run([sys.executable, "-m", "twine", "check", "--strict",
                           str(built["sdist"]), str(built["wheel"])], capture_output=True,
                          text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.count("PASSED") == 2, done.stdout


def test_the_name_is_the_distributions_and_the_import_and_command_stay_mimics(
        built: dict[str, Path]) -> None:
    assert PROJECT["name"] == "mimics-sim"  # "mimics" on PyPI is an unrelated project
    assert built["wheel"].name == f"mimics_sim-{PROJECT['version']}-py3-none-any.whl"
    with zipfile.ZipFile(built["wheel"]) as wheel:
        names = wheel.namelist()
        info = next(n for n in names if n.endswith(".dist-info/METADATA"))
        metadata = Parser().parsestr(wheel.read(info).decode())
        scripts = next(n for n in names if n.endswith(".dist-info/entry_points.txt"))
        entry_points = wheel.read(scripts).decode()
    assert metadata["Name"] == "mimics-sim"
    for page in ("README.md", "examples/teaching_kit/ASSIGNMENT.md"):  # the install steps
        text = (ROOT / page).read_text()
        assert f"pip install {built['wheel'].name}" in text, page
        assert "py -3.11 -m venv .venv" in text and "python3 -m venv .venv" in text, page
    assert metadata["Version"] == PROJECT["version"] == mimics.__version__
    assert "mimics = mimics.interfaces.cli.leave:console" in entry_points
    # every extra a page tells people to install exists
    assert set(PROJECT["optional-dependencies"]) <= set(metadata.get_all("Provides-Extra"))


def test_the_wheel_holds_what_a_course_runs_and_no_tests(built: dict[str, Path]) -> None:
    with zipfile.ZipFile(built["wheel"]) as wheel:
        names = set(wheel.namelist())
    package = ROOT / "mimics"
    wanted = {
        "built-in algorithms": sorted(package.glob("algorithms/*.py")),
        "built-in scenarios": sorted(package.glob("scenarios/*.py")),
        "the workbench's static files": sorted(p for p in package.glob(
            "interfaces/web/static/**/*") if p.is_file()),
        "the notebook widget's script": sorted(package.glob("interfaces/notebook/*.js")),
        "the C header and host": [package / "include/mimics.h", package / "native/host.c"],
        "the ROS launch files": sorted(package.glob("interfaces/ros/files/*")),
    }
    for what, paths in wanted.items():
        assert paths, what  # the source has them: the check below means something
        missing = [str(p.relative_to(ROOT)) for p in paths
                   if str(p.relative_to(ROOT)) not in names]
        assert not missing, f"{what} missing from the wheel: {missing}"
    tops = {name.split("/")[0] for name in names}
    assert tops == {"mimics", f"mimics_sim-{PROJECT['version']}.dist-info"}, tops
    assert not [n for n in names if "/tests/" in n or "/benchmarks/" in n
                or "__pycache__" in n or n.endswith(".pyc")]


def test_the_sdist_builds_the_same_package(built: dict[str, Path]) -> None:
    with tarfile.open(built["sdist"]) as sdist:
        names = {name.split("/", 1)[1] for name in sdist.getnames() if "/" in name}
    assert {"pyproject.toml", "README.md", "mimics/__init__.py",
            "mimics/interfaces/notebook/widget.js", "mimics/include/mimics.h"} <= names


def test_a_video_without_the_video_extra_is_one_error_before_the_run(tmp_path: Path) -> None:
    """imageio-ffmpeg (160 MB) is the ``video`` extra: without it, ``--video`` says which
    extra to install, exit 2, before anything runs."""
    code = ("import sys; sys.modules['imageio_ffmpeg'] = None  # as if not installed\n"
            "from mimics.interfaces.cli import main\n"
            "sys.exit(main(['run', 'line', 'go_to_goal', '--robots', '2', '--time', '1', "
            "'--out', 'run', '--video', 'run.mp4']))")
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120, check=False)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "pip install 'mimics-sim[video]'" in done.stderr
    assert not (tmp_path / "run").exists()
    extras = PROJECT["optional-dependencies"]
    assert not any(d.startswith("imageio-ffmpeg") for d in PROJECT["dependencies"])
    for extra in ("video", "notebook", "ui"):  # the features that draw videos
        assert any(d.startswith("imageio-ffmpeg") for d in extras[extra]), extra


# `pip install mimics`, `pip install 'mimics[ui]'`: the unrelated PyPI project of that name
WRONG_INSTALL = re.compile(r"pip install (?:-\w+ )*['\"]?mimics(?:\[|['\"\s`]|$)", re.M)


def test_nothing_tells_anyone_to_pip_install_the_other_projects_name() -> None:
    texts = [ROOT / "README.md", *ROOT.glob("docs/**/*.md"), *ROOT.glob("docs/**/*.ipynb"),
             *ROOT.glob("examples/**/*.md"), *ROOT.glob("mimics/**/*.py"),
             *ROOT.glob("docs/snippets/**/*")]
    found = [f"{path.relative_to(ROOT)}: {match.group(0)}" for path in texts if path.is_file()
             for match in WRONG_INSTALL.finditer(path.read_text(encoding="utf-8"))]
    assert not found, "\n".join(found)
    assert WRONG_INSTALL.search("pip install 'mimics[ui]'")  # the pattern sees what it must
    assert WRONG_INSTALL.search("run `pip install mimics` first")
    assert not WRONG_INSTALL.search("pip install 'mimics-sim[ui]'")
    assert not WRONG_INSTALL.search("pip install mimics_sim-0.1.0-py3-none-any.whl")


def test_the_ci_workflow_runs_the_readmes_test_command_on_three_systems() -> None:
    workflow = yaml.safe_load((ROOT / ".github/workflows/ci.yml").read_text())
    job = workflow["jobs"]["test"]
    systems = {entry["os"] for entry in job["strategy"]["matrix"]["include"]}
    assert systems == {"ubuntu-latest", "macos-latest", "windows-latest"}
    runs = {step.get("name", ""): step for step in job["steps"]}
    readme = (ROOT / "README.md").read_text()
    test_command = re.search(r"^python3 -m venv \.venv && .*pytest.*$", readme, re.M)
    assert test_command is not None
    assert runs["The README's test command (macOS)"]["run"].strip() == test_command[0]
    assert test_command[0] in (ROOT / ".ci/run").read_text()  # what Linux runs
    windows = runs["The README's test command, Windows' form (PowerShell)"]["run"]
    assert "-3.11" in windows and ".venv\\Scripts\\python -m pytest -n 2 -q" in windows
    setup = next(step for step in job["steps"] if "setup-python" in step.get("uses", ""))
    assert setup["with"]["python-version"] == "3.11"
