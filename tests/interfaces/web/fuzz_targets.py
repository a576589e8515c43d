"""What the workbench's fuzzer sends to each API route: a well-formed request to spoil,
the kinds of its fields, which are required, which must refuse enormous numbers.

Every request the fuzzer makes from these is malformed by construction (an unknown
key, a wrong type, an enormous number, a missing required key, deep nesting), so
every answer must be a 4xx naming a field. Routes that take no input at all
(``GET /api/maps``) are only called, with a stray query parameter.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import hypothesis.strategies as st

ENORMOUS_NUMBERS = (1e300, -1e300, 1e308, -1.7e308, 10**30, -(10**30), 2**64)
#: Values of the wrong type for a field of each kind (never valid for it).
WRONG_TYPES: dict[str, tuple[Any, ...]] = {
    "str": (5, 1.5, True, [1], {"a": 1}),
    "int": ("abc", [1], {"a": 1}, 1.5),
    "num": ("abc", [1], {"a": 1}, "1e300x"),
    "bool": ("abc", 2.5, [1], {"a": 1}),
    "list": ("abc", 5, {"a": 1}, True),
    "dict": ("abc", 5, [1], True),
    "until": ({"metric": {"a": 1}, "half_width": 0.2}, {"metric": ["x"], "half_width": 0.2},
              "abc", 5, [1]),
}
#: The classes of malformed bodies (the issue's).
CLASSES = ("unknown", "wrong_type", "enormous", "missing", "deep")


@dataclass(frozen=True)
class Target:
    """How to spoil the requests of one route.

    Attributes:
        body: a well-formed JSON body, or None when the route takes none.
        kinds: each body field's kind (a key of ``WRONG_TYPES``).
        required: body fields that cannot be left out.
        enormous: body fields and the enormous values they must refuse.
        query: well-formed query parameters, and their kinds in ``query_kinds``.
        query_kinds: each query parameter's kind.
        no_input: the route takes no input at all (called once, must not fail).
        aliases: other words an answer may name a field by (``name``: ``scenario``).
    """

    body: dict[str, Any] | None = None
    kinds: dict[str, str] = field(default_factory=dict)
    required: tuple[str, ...] = ()
    enormous: dict[str, tuple[Any, ...]] = field(default_factory=dict)
    query: dict[str, Any] = field(default_factory=dict)
    query_kinds: dict[str, str] = field(default_factory=dict)
    no_input: bool = False
    aliases: dict[str, str] = field(default_factory=dict)


def _numbers(*names: str) -> dict[str, tuple[Any, ...]]:
    return {name: ENORMOUS_NUMBERS for name in names}


def targets(run: str, scenario: str) -> dict[tuple[str, str], Target]:
    """The fuzzer's targets by (method, route path); ``run`` is a recorded run folder and
    ``scenario`` a saved scenario file of the workspace served."""
    robot = {"type": "Pioneer2DX", "x": 1.0, "y": 1.5}
    inline = {"name": "m", "bounds": [0.0, 0.0, 10.0, 6.0], "segments": []}
    battery = {"name": "fz", "algorithms": ["go_to_goal"], "scenarios": [{"name": "line"}],
               "seeds": 1, "dry_run": True}
    run_q = {"path": run, "robot": 0, "frame": 0}
    return {
        ("GET", "/api/maps"): Target(no_input=True),
        ("GET", "/api/maps/file"): Target(query={"path": "maps/room.txt"},
                                          query_kinds={"path": "path"}),
        ("PUT", "/api/maps/file"): Target(
            body={"path": "maps/fz.txt", "bounds": [0, 0, 10, 6], "segments": [],
                  "overwrite": False},
            kinds={"path": "str", "name": "str", "bounds": "list", "segments": "list",
                   "overwrite": "bool"},
            required=("path", "bounds"),
            enormous={"bounds": ([0, 0, 1e300, 1e300], [-1e308, 0, 1e308, 6]),
                      "segments": ([[0, 0, 1e300, 1]], [[1, 1, 2, 1e308]])}),
        ("POST", "/api/maps/import"): Target(query={"filename": "a.svg"},
                                             query_kinds={"filename": "path",
                                                          "options": "json"}),
        ("POST", "/api/maps/import-file"): Target(query={"path": "maps/room.txt"},
                                                  query_kinds={"path": "path",
                                                               "options": "json"}),
        ("GET", "/api/scenarios"): Target(no_input=True),
        ("GET", "/api/scenarios/file"): Target(query={"path": scenario},
                                               query_kinds={"path": "path"}),
        ("GET", "/api/scenarios/builtin"): Target(query={"name": "line"},
                                                  query_kinds={"name": "path"},
                                                  aliases={"name": "scenario"}),
        ("PUT", "/api/scenarios/file"): Target(
            body={"path": "scenarios/fz.toml", "map": "maps/room.txt", "robots": [robot],
                  "overwrite": False},
            kinds={"path": "str", "name": "str", "map": "str", "robots": "list",
                   "types": "dict", "settings": "dict", "overwrite": "bool"},
            required=("path", "map", "robots"),
            enormous={"robots": ([{**robot, "x": 1e300}], [{**robot, "y": -1e308}],
                                 [{**robot, "goal": [1e300, 1.0]}]),
                      "map": ({**inline, "bounds": [0, 0, 1e300, 1e300]},
                              {**inline, "segments": [[0, 0, 1e300, 1]]}),
                      "settings": ({"time_limit": 1e300}, {"dt": 1e-300})}),
        ("POST", "/api/scenarios/place"): Target(
            body={"map": "maps/room.txt", "type": "Pioneer2DX", "count": 1},
            kinds={"map": "str", "type": "str", "count": "int", "region": "list",
                   "min_spacing": "num", "seed": "int", "others": "list"},
            required=("map", "type", "count"),
            enormous={**_numbers("count", "seed"),
                      "map": ({**inline, "bounds": [0, 0, 1e300, 1e300]},)}),
        ("POST", "/api/scenarios/run"): Target(
            body={"path": scenario, "algorithm": "go_to_goal"},
            kinds={"path": "str", "algorithm": "str", "seed": "int", "time": "num",
                   "wall_limit": "num"},
            required=("path", "algorithm"),
            enormous=_numbers("seed", "time", "wall_limit")),
        ("GET", "/api/algorithms"): Target(no_input=True),
        ("POST", "/api/algorithms/upload"): Target(query={"filename": "a.py"},
                                                   query_kinds={"filename": "path"}),
        ("GET", "/api/batteries"): Target(no_input=True),
        ("POST", "/api/batteries"): Target(
            body=battery,
            kinds={"name": "str", "algorithms": "list", "scenarios": "list", "seeds": "list",
                   "time": "num", "timeout": "num", "policy": "str", "until": "until",
                   "dry_run": "bool"},
            required=("name", "algorithms", "scenarios"),
            enormous={"seeds": (10**30, [1, 10**30]),
                      "until": ({"metric": "success", "half_width": 0.1,
                                 "max_seeds": 10**30},)}),
        ("POST", "/api/batteries/resume"): Target(body={"path": "batteries/none"},
                                                  kinds={"path": "str"}, required=("path",)),
        ("POST", "/api/batteries/rerun-failed"): Target(body={"path": "batteries/none"},
                                                        kinds={"path": "str"},
                                                        required=("path",)),
        ("GET", "/api/batteries/status"): Target(query={"path": "batteries/none"},
                                                 query_kinds={"path": "path"}),
        ("GET", "/api/batteries/plot"): Target(query={"path": "batteries/none",
                                                      "name": "outcomes.png"},
                                               query_kinds={"path": "path", "name": "path"},
                                               aliases={"name": "plot"}),
        ("GET", "/api/batteries/evidence"): Target(query={"path": "batteries/none"},
                                                   query_kinds={"path": "path",
                                                                "metric": "path"},
                                                   # no battery here: its path comes first
                                                   aliases={"metric": "path"}),
        ("GET", "/api/runs"): Target(no_input=True),
        ("GET", "/api/runs/meta"): Target(query={"path": run}, query_kinds={"path": "path"}),
        ("GET", "/api/runs/frames"): Target(query={"path": run},
                                            query_kinds={"path": "path"}),
        ("GET", "/api/runs/robot"): Target(query={"path": run, "robot": 0},
                                           query_kinds={"path": "path", "robot": "int"}),
        ("GET", "/api/runs/beams"): Target(query=run_q, query_kinds={
            "path": "path", "robot": "int", "frame": "int"}),
        ("GET", "/api/runs/all_beams"): Target(query={"path": run, "frame": 0},
                                               query_kinds={"path": "path", "frame": "int"}),
        ("GET", "/api/runs/log"): Target(query={"path": run, "robot": 0}, query_kinds={
            "path": "path", "robot": "int", "until": "num"}),
        ("POST", "/api/runs/export"): Target(
            body={"path": run}, kinds={"path": "str", "speed": "num", "fps": "num",
                                       "robot": "int"},
            required=("path",), enormous=_numbers("speed", "fps", "robot")),
        ("GET", "/api/runs/video"): Target(query={"path": run}, query_kinds={"path": "path"}),
        ("GET", "/api/runs/plot"): Target(query={"path": "runs/none"},
                                          query_kinds={"path": "path"}),
        ("GET", "/api/jobs/{job_id}"): Target(query_kinds={"job_id": "int"}),
        ("GET", "/api/live"): Target(no_input=True),
        ("POST", "/api/live"): Target(
            body={"scenario": scenario, "algorithm": "go_to_goal", "seed": 1, "paused": True},
            kinds={"scenario": "str", "algorithm": "str", "seed": "int", "time": "num",
                   "speed": "num", "wall_limit": "num", "paused": "bool", "fps": "num",
                   "battery": "str", "run": "int"},
            required=("scenario",),
            enormous=_numbers("seed", "speed", "wall_limit", "fps", "run")),
        ("GET", "/api/live/{run_id}"): Target(query_kinds={"run_id": "int"}),
        ("GET", "/api/live/{run_id}/meta"): Target(query_kinds={"run_id": "int"}),
        ("GET", "/api/live/{run_id}/frame"): Target(query_kinds={"run_id": "int"}),
        ("GET", "/api/live/{run_id}/robot"): Target(query={"robot": 0},
                                                    query_kinds={"run_id": "int",
                                                                 "robot": "int"}),
        ("GET", "/api/live/{run_id}/beams"): Target(query={"robot": 0},
                                                    query_kinds={"run_id": "int",
                                                                 "robot": "int",
                                                                 "all": "bool"}),
        ("POST", "/api/live/{run_id}/pause"): Target(query_kinds={"run_id": "int"}),
        ("POST", "/api/live/{run_id}/resume"): Target(query_kinds={"run_id": "int"}),
        ("POST", "/api/live/{run_id}/step"): Target(query_kinds={"run_id": "int"}),
        ("POST", "/api/live/{run_id}/stop"): Target(query_kinds={"run_id": "int"}),
        ("POST", "/api/live/{run_id}/speed"): Target(
            body={"speed": 2.0}, kinds={"speed": "num"}, required=("speed",),
            enormous=_numbers("speed")),
        ("POST", "/api/live/{run_id}/edit"): Target(
            body={"kind": "add_wall", "segment": [4.0, 0.5, 4.0, 2.5]},
            kinds={"kind": "str", "segment": "list", "step": "int"},
            required=("kind", "segment"),
            enormous={"segment": ([1e300, 0.5, 4.0, 2.5], [4.0, -1e308, 4.0, 1e308]),
                      "step": (10**30, 2**64)}),
        ("WS", "/api/live/{run_id}/stream"): Target(query_kinds={"run_id": "int"}),
    }


#: Edits of each kind, each field's kind and what must refuse enormous numbers (the live
#: run's fuzzed edits draw from these as well as from the edit route's target).
EDITS: dict[str, Target] = {
    "move_robot": Target(body={"kind": "move_robot", "robot": 1, "x": 5.0, "y": 4.5},
                         kinds={"robot": "int", "x": "num", "y": "num", "yaw": "num"},
                         required=("kind", "robot", "x", "y"),
                         enormous=_numbers("robot", "x", "y")),
    "set_goal": Target(body={"kind": "set_goal", "robot": 0, "x": 5.0, "y": 4.5},
                       kinds={"robot": "int", "x": "num", "y": "num"},
                       required=("kind", "robot", "x", "y"),
                       enormous=_numbers("robot", "x", "y")),
    "remove_wall": Target(body={"kind": "remove_wall", "at": [0.0, 3.0]},
                          kinds={"at": "list", "wall": "int"}, required=("kind",),
                          enormous={"at": ([1e300, 3.0], [0.0, -1e308]),
                                    "wall": ENORMOUS_NUMBERS}),
    "add_wall": Target(body={"kind": "add_wall", "rectangle": [4.0, 0.2, 4.5, 0.8]},
                       kinds={"rectangle": "list"}, required=("kind", "rectangle"),
                       enormous={"rectangle": ([4.0, 0.2, 1e300, 1e300],
                                               [-1e308, -1e308, 4.5, 0.8])}),
    "remove_robot": Target(body={"kind": "remove_robot", "robot": 0},
                           kinds={"robot": "int"}, required=("kind", "robot"),
                           enormous=_numbers("robot")),
}


def deep(depth: int, as_dict: bool) -> Any:
    """A value nested ``depth`` deep: ``[[[...]]]`` or ``{"a": {"a": ...}}``."""
    value: Any = 1
    for _ in range(depth):
        value = {"a": value} if as_dict else [value]
    return value


@st.composite
def malformed_body(draw: st.DrawFn, target: Target) -> tuple[str, str, Any]:
    """(class, the field it spoils, the body) for a target with a body."""
    assert target.body is not None
    kind = draw(st.sampled_from([c for c in CLASSES if c != "enormous" or target.enormous]))
    body = dict(target.body)
    if kind == "unknown":
        key = draw(st.sampled_from(["seeed", "Seed", "scenario ", "spead", "dryrun", "x_",
                                    "__proto__", "é"]))
        body[key] = draw(st.sampled_from([5, "x", None, [1], {"a": 1}]))
        return kind, key, body
    if kind == "missing":
        name = draw(st.sampled_from(target.required))
        del body[name]
        return kind, name, body
    if kind == "enormous":
        name = draw(st.sampled_from(sorted(target.enormous)))
        body[name] = draw(st.sampled_from(target.enormous[name]))
        return kind, name, body
    name = draw(st.sampled_from(sorted(target.kinds)))
    if kind == "wrong_type":
        body[name] = draw(st.sampled_from(WRONG_TYPES[target.kinds[name]]))
    else:
        body[name] = deep(draw(st.integers(20, 200)), draw(st.booleans()))
    return kind, name, body


@st.composite
def malformed_query(draw: st.DrawFn, target: Target) -> tuple[str, str, dict[str, Any]]:
    """(class, the parameter it spoils, the query) for a target with query parameters
    (path parameters among them, e.g. ``run_id``)."""
    name = draw(st.sampled_from(sorted(target.query_kinds)))
    kind = target.query_kinds[name]
    query = dict(target.query)
    bad: list[Any] = ["abc", "[1]", "1e300x", "", "%00"]
    if kind == "int":
        bad += ["1e300", str(10**30), "-5", "1.5"]
    elif kind == "num":
        bad += ["1e999", "nan", "-inf"]
    elif kind == "path":
        bad += ["../secret", "/etc/passwd", "runs/none", "C:/x", "maps/" + "a" * 300]
    elif kind == "json":
        bad += ['{"seeed": 5}', "[1]", '{"scale": "x"}', '{"scale": 1e300}']
    if name.endswith("_id"):  # a path parameter: empty is another route (a redirect)
        bad.remove("")
    value = draw(st.sampled_from(bad + (["(missing)"] if name in query else [])))
    if value == "(missing)":
        del query[name]
    else:
        query[name] = value
    return "query", name, query
