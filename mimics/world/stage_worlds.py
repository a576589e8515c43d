"""Read robot start poses (and the floorplan) from Stage ``.world`` files.

Stage's syntax is a list of ``name ( key value ... )`` blocks, ``[a b c]``
tuples, ``define NEW BASE ( ... )`` prototypes, ``include "file"`` lines and
``#`` comments. Robots are the top-level model instances that are not the
floorplan, the window or plain obstacles. The Hospital world keeps its second
block of 1,000 robots commented out; ``include_commented=True`` reads those
one-line instances too (the MiMicS paper used both blocks).

>>> world = read_stage_world(find_stage_file("cave.world"))  # doctest: +SKIP
>>> len(world.robots), world.floorplan["size"]  # doctest: +SKIP
(100, (16.0, 16.0, 0.6))
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mimics.world.errors import MimicsError

NOT_ROBOTS = frozenset({"window", "floorplan", "model", "zone"})
_TOKEN = re.compile(r'"(?P<str>[^"\n]*)"|(?P<punct>[()\[\]])|(?P<word>[^\s()\[\]"#]+)')
_COMMENTED_INSTANCE = re.compile(r"^(\s*)#\s*([A-Za-z_][\w.-]*\s*\(.*\)\s*)$")
_DEFINE = re.compile(r"^\s*define\s+([A-Za-z_][\w.-]*)", re.MULTILINE)


@dataclass(frozen=True)
class StageRobot:
    """One robot instance: its model type, optional name and start pose."""

    model: str
    name: str | None
    x: float
    y: float
    yaw: float  # rad (Stage writes degrees)
    line: int
    commented: bool = False


@dataclass(frozen=True)
class StageWorld:
    """What mimics reads from a world file."""

    path: Path
    robots: tuple[StageRobot, ...]
    floorplan: dict[str, Any] | None = None  # its properties (bitmap, size, pose...)
    settings: dict[str, Any] = field(default_factory=dict)  # top-level key-value lines

    def poses(self) -> np.ndarray:
        """Robot start poses ``(n, 3)``: x, y (m) and yaw (rad)."""
        return np.array([(r.x, r.y, r.yaw) for r in self.robots], dtype=np.float64).reshape(-1, 3)


@dataclass
class _Block:
    kind: str
    line: int
    props: dict[str, Any] = field(default_factory=dict)
    children: list[_Block] = field(default_factory=list)
    commented: bool = False


class _Parser:
    """Recursive descent over the tokens of one file."""

    def __init__(self, path: Path, text: str, commented_lines: set[int]) -> None:
        self.path = path
        self.commented_lines = commented_lines
        self.tokens: list[tuple[str, str, int]] = []
        for number, raw in enumerate(text.splitlines(), start=1):
            line = _strip_comment(raw)
            for match in _TOKEN.finditer(line):
                kind = match.lastgroup or "word"
                self.tokens.append((kind, match.group(kind), number))
        self.pos = 0

    def error(self, line: int, message: str) -> MimicsError:
        return MimicsError(f"{self.path}, line {line}: {message}")

    def peek(self, ahead: int = 0) -> tuple[str, str, int] | None:
        index = self.pos + ahead
        return self.tokens[index] if index < len(self.tokens) else None

    def take(self) -> tuple[str, str, int]:
        token = self.tokens[self.pos]
        self.pos += 1
        return token

    def body(self, closing: bool) -> tuple[dict[str, Any], list[_Block], dict[str, str]]:
        props: dict[str, Any] = {}
        children: list[_Block] = []
        defines: dict[str, str] = {}
        while (token := self.peek()) is not None:
            kind, text, line = token
            if kind == "punct" and text == ")":
                if not closing:
                    raise self.error(line, "unexpected ')'")
                return props, children, defines
            if kind != "word":
                raise self.error(line, f"expected a name, got {text!r}")
            self.take()
            nxt = self.peek()
            if text == "define":
                names = [self.peek(), self.peek(1)]
                if any(t is None or t[0] != "word" for t in names):
                    raise self.error(line, "expected 'define NAME BASE ( ... )'")
                new, base = self.take(), self.take()
                self.expect("(", line)
                self.body(closing=True)
                self.take()
                defines[new[1]] = base[1]
            elif text == "include":
                if nxt is None or nxt[0] != "str":
                    raise self.error(line, 'expected include "file"')
                self.take()
            elif nxt is not None and nxt[:2] == ("punct", "("):
                self.take()
                sub_props, sub_children, sub_defines = self.body(closing=True)
                self.take()
                defines.update(sub_defines)
                children.append(_Block(text, line, sub_props, sub_children,
                                       commented=line in self.commented_lines))
            elif nxt is not None and nxt[:2] == ("punct", "["):
                self.take()
                values = []
                while (item := self.peek()) is not None and item[:2] != ("punct", "]"):
                    if item[0] == "punct":
                        raise self.error(item[2], f"unexpected {item[1]!r} inside [ ]")
                    values.append(_value(self.take()))
                if item is None:
                    raise self.error(line, f"'[' of {text!r} is never closed")
                self.take()
                props[text] = tuple(values)
            elif nxt is not None and nxt[0] in ("word", "str"):
                props[text] = _value(self.take())
            else:
                raise self.error(line, f"{text!r} has no value")
        if closing:
            raise self.error(self.tokens[-1][2] if self.tokens else 1, "a '(' is never closed")
        return props, children, defines

    def expect(self, punct: str, line: int) -> None:
        token = self.peek()
        if token is None or token[:2] != ("punct", punct):
            raise self.error(line, f"expected {punct!r}")
        self.take()


def _strip_comment(line: str) -> str:
    """The line without its ``#`` comment (a ``#`` inside quotes is kept)."""
    quoted = False
    for i, char in enumerate(line):
        if char == '"':
            quoted = not quoted
        elif char == "#" and not quoted:
            return line[:i]
    return line


def _value(token: tuple[str, str, int]) -> Any:
    kind, text, _ = token
    if kind == "str":
        return text
    try:
        return float(text)
    except ValueError:
        return text


def _root(kind: str, defines: dict[str, str]) -> str:
    """The built-in model a (possibly user-defined) type derives from."""
    seen = set()
    while kind in defines and kind not in seen:
        seen.add(kind)
        kind = defines[kind]
    return kind


def read_stage_world(path: str | Path, include_commented: bool = False) -> StageWorld:
    """Parse a Stage world file.

    Args:
        path: the ``.world`` file.
        include_commented: also read model instances commented out on a
            single line (``#swarmbot( name "r1000" pose [ 0 -15 0 0 ] )``).

    Raises:
        MimicsError: unreadable file or a syntax error, naming file and line.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise MimicsError(f"{path}: cannot read ({exc.strerror})") from None
    commented: set[int] = set()
    if include_commented:
        known = set(_DEFINE.findall(text))
        lines = text.splitlines()
        for i, line in enumerate(lines):
            match = _COMMENTED_INSTANCE.match(line)
            if match and match.group(2).split("(")[0].strip() in known:
                lines[i] = match.group(1) + match.group(2)
                commented.add(i + 1)
        text = "\n".join(lines)
    parser = _Parser(path, text, commented)
    settings, blocks, defines = parser.body(closing=False)
    robots = []
    floorplan = None
    for block in blocks:
        root = _root(block.kind, defines)
        if root == "floorplan" and floorplan is None:
            floorplan = dict(block.props)
        if root in NOT_ROBOTS or "pose" not in block.props:
            continue
        pose = block.props["pose"]
        if not isinstance(pose, tuple) or len(pose) not in (3, 4) or not all(
                isinstance(v, float) for v in pose):
            raise MimicsError(f"{path}, line {block.line}: pose must be [x y z a] numbers, "
                              f"got {pose!r}")
        yaw_degrees = pose[-1]
        name = block.props.get("name")
        robots.append(StageRobot(block.kind, str(name) if name is not None else None,
                                 pose[0], pose[1], math.radians(yaw_degrees), block.line,
                                 block.commented))
    return StageWorld(path, tuple(robots), floorplan, settings)


def stage_robot_poses(path: str | Path, include_commented: bool = False) -> np.ndarray:
    """Robot start poses ``(n, 3)`` (x, y in m, yaw in rad) in the order of the file."""
    return read_stage_world(path, include_commented).poses()
