"""Shared pieces of the fuzzers: valid inputs of every kind, ways to damage them, a hang guard.

The fuzz tests (``tests/*/test_fuzz_*.py``) start from the valid files made
here, damage them with the strategies below (truncation, flipped bytes, wrong
types, missing keys) and check that mimics answers with a result or one
``MimicsError`` line, never another exception.
"""

from __future__ import annotations

import contextlib
import hashlib
import shutil
import signal
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st

from tests.toml_text import toml_text

SCENARIO_TOML = ('name = "fuzz"\n'
                 'map = { segments = [[0.0, 0.0, 10.0, 0.0], [0.0, 6.0, 10.0, 6.0]], '
                 'bounds = [-1, -1, 11, 7] }\n\n') + toml_text({
    "robots": [{"type": "Pioneer2DX", "x": 2.0, "y": 2.0, "goal": [8.0, 2.0]},
               {"generator": "line", "type": "Small", "count": 2, "start": [1.0, 4.0],
                "step": [1.0, 0.0], "goal_offset": [6.0, 0.0]}],
    "types": {"Small": {"base": "Pioneer2DX", "width": 0.2}},
    "settings": {"time_limit": 0.5}})

BATTERY_TOML = """\
[battery]
algorithms = ["go_to_goal"]
seeds = 1
time = 0.3
timeout = 60.0

[[scenarios]]
name = "line"
robots = 2
"""

SVG = """<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm" viewBox="0 0 100 50">
<rect x="5" y="5" width="90" height="40" fill="none" stroke="black"/>
<path d="M 20 10 L 20 40 Q 50 45 80 40" fill="none" stroke="black"/>
</svg>
"""

STAGE_WORLD = """\
define pioneer position ( size [0.44 0.38 0.22] )
floorplan ( name "cave" size [16.000 16.000 0.800] bitmap "cave.png" )
pioneer ( name "r0" pose [ -7.0 -7.0 0 45.0 ] )
pioneer ( name "r1" pose [ -6.0 -7.0 0 45.0 ] )
# pioneer ( name "r2" pose [ -5.0 -7.0 0 45.0 ] )
"""


def occupancy(height: int = 24, width: int = 32) -> np.ndarray:
    """A grey image (0 black = wall, 255 white = free) of a room with a pillar."""
    image = np.full((height, width), 255, dtype=np.uint8)
    image[0, :] = image[-1, :] = image[:, 0] = image[:, -1] = 0
    image[8:14, 10:16] = 0
    return image


def write_pgm(path: Path, image: np.ndarray) -> Path:
    """A binary PGM (P5) of ``image``."""
    height, width = image.shape
    path.write_bytes(f"P5\n{width} {height}\n255\n".encode() + image.tobytes())
    return path


def map_files(folder: Path) -> dict[str, Path]:
    """One valid map file of each kind the readers take, in ``folder``."""
    import imageio.v3 as iio

    folder.mkdir(parents=True, exist_ok=True)
    files = {
        "plain": folder / "room.txt",
        "toml": folder / "room.toml",
        "json": folder / "room.json",
        "svg": folder / "plan.svg",
        "png": folder / "grid.png",
        "pgm": folder / "grid.pgm",
        "ros": folder / "ros.yaml",
        "world": folder / "cave.world",
    }
    files["plain"].write_text("bounds 0 0 10 6\n0 0 10 0  # south\n0 6 10 6\n")
    files["toml"].write_text('name = "room"\nsegments = [[0.0, 0.0, 4.0, 0.0]]\n'
                             'bounds = [-1.0, -1.0, 5.0, 3.0]\n')
    files["json"].write_text('{"segments": [[0, 0, 4, 0], [4, 0, 4, 3]], '
                             '"bounds": [-1, -1, 5, 4]}')
    files["svg"].write_text(SVG)
    iio.imwrite(files["png"], occupancy())
    write_pgm(files["pgm"], occupancy())
    write_pgm(folder / "ros.pgm", occupancy())
    files["ros"].write_text("image: ros.pgm\nresolution: 0.05\norigin: [-1.0, -1.0, 0.0]\n"
                            "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")
    files["world"].write_text(STAGE_WORLD)
    return files


def make_run_folder(folder: Path) -> Path:
    """A finished run folder of a small run (2 robots, 0.5 s), with robot logs."""
    from mimics.records.runner import prepare, run_to_folder

    run_to_folder(prepare("line", "go_to_goal", robots=2, time=0.5, seed=1), folder,
                  robot_logs="on")
    return folder


# -- damage ---------------------------------------------------------------------

@st.composite
def damaged_bytes(draw: Any, data: bytes) -> bytes:
    """``data`` truncated, with bytes flipped, with a stretch replaced, or emptied."""
    how = draw(st.sampled_from(["truncate", "flip", "splice", "empty", "garbage"]))
    if how == "empty" or not data:
        return b""
    if how == "truncate":
        return data[:draw(st.integers(0, len(data) - 1))]
    if how == "garbage":
        return draw(st.binary(min_size=1, max_size=200))
    out = bytearray(data)
    if how == "flip":
        for _ in range(draw(st.integers(1, 8))):
            k = draw(st.integers(0, len(out) - 1))
            out[k] ^= draw(st.integers(1, 255))
        return bytes(out)
    start = draw(st.integers(0, len(out) - 1))
    end = draw(st.integers(start, min(len(out), start + 40)))
    out[start:end] = draw(st.binary(max_size=40))
    return bytes(out)


#: Values of the wrong type or at the edges, for any key of a TOML/JSON document.
EDGE_VALUES = st.sampled_from([
    "nan", "inf", "-inf", "1e999", "-1", "0", "-0.0", "5e-324", "1e300", "9223372036854775808",
    "340282366920938463463374607431768211456", "-9223372036854775809", '""', '"ü→∞"',
    "true", "[]", "[[]]", "{}", '"a"', "[1.0]", "[nan, nan]", "[1e308, 1e308]",
    "[0.0, 0.0, 0.0, 0.0]", "2.5", "100000000000",
])


@st.composite
def mutated_toml(draw: Any, text: str) -> str:
    """``text`` (one ``key = value`` per line) with a value replaced, a line dropped, or
    a key renamed."""
    lines = text.splitlines()
    assignments = [k for k, line in enumerate(lines) if " = " in line and
                   not line.lstrip().startswith("#")]
    for _ in range(draw(st.integers(1, 3))):
        k = draw(st.sampled_from(assignments))
        key, _, _ = lines[k].partition(" = ")
        how = draw(st.sampled_from(["value", "drop", "rename"]))
        if how == "value":
            lines[k] = f"{key} = {draw(EDGE_VALUES)}"
        elif how == "drop":
            lines[k] = ""
        else:
            lines[k] = f"{key}_x = 1"
    return "\n".join(lines) + "\n"


# -- snapshots and the hang guard -----------------------------------------------

def snapshot(folder: Path) -> dict[str, str]:
    """Every file under ``folder`` (relative path) -> SHA-1 of its bytes."""
    out = {}
    for path in sorted(folder.rglob("*")):
        if path.is_file() and not path.is_symlink():
            out[path.relative_to(folder).as_posix()] = hashlib.sha1(path.read_bytes()).hexdigest()
    return out


class Hung(Exception):
    """A command ran past the guard's time."""


@contextlib.contextmanager
def time_guard(seconds: int, what: str) -> Iterator[None]:
    """Raise :class:`Hung` naming ``what`` if the block runs past ``seconds`` (SIGALRM:
    main thread only, as pytest and its xdist workers run tests)."""
    def expire(signum: int, frame: Any) -> None:
        raise Hung(f"{what} still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def copy_tree(source: Path, target: Path) -> Path:
    """A copy of a folder (inputs are copied fresh for every example)."""
    shutil.copytree(source, target)
    return target


# -- the second round's classes (issue 53) ----------------------------------------

#: Finite but enormous numbers: they pass a NaN/infinity check and must meet a limit.
ENORMOUS = ["1e300", "1e308", "1.7976931348623157e308", "-1e300", "1e18", "2147483648e3"]
#: Python values of types no plain number/path check covers.
WRONG_TYPES: list[Any] = [True, False, "5", "", b"5", [1.0], [], {}, {"a": 1}, (1, 2), None,
                          1e300, 1e308, -1, 0, 2**70, float("nan"), object()]


def foreign_run_folder(run: Path, target: Path) -> Path:
    """A copy of ``run`` whose trajectory.parquet is a valid Parquet file of another table
    (its events), which must be refused, not read as an empty or wrong trajectory."""
    shutil.copytree(run, target)
    shutil.copyfile(run / "events.parquet", target / "trajectory.parquet")
    return target


#: Paths that alias a run folder's records: the records themselves, through ``..``, and
#: the folder itself.
RUN_ALIASES = ["{run}/summary.json", "{run}/trajectory.parquet", "{run}/../{name}/events.parquet",
               "{run}/scenario.toml", "{run}/robots/robot_0000.log", "{run}"]
#: Paths that alias a battery folder's records.
BATTERY_ALIASES = ["{folder}/battery.db", "{folder}/runs", "{folder}/battery.db-wal",
                   "{folder}/../{name}/battery.db"]
