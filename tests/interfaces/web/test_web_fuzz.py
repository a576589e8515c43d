"""The workbench's API fuzzed over real HTTP and its WebSocket (issue 53).

The app is served on 127.0.0.1 with a paused live run. Every API route (walked from
the app's router: a new route without a target in ``fuzz_targets`` fails) gets
malformed requests drawn by Hypothesis (seeded, bounded): unknown keys, wrong
types, finite but enormous numbers, missing keys, deep nesting, bad query and
path parameters. Each answer must be a 4xx whose JSON ``detail`` is one line
naming the field, never a 5xx or a dropped connection; the WebSocket must refuse
bad handshakes with a status and keep streaming through malformed messages.
Afterwards the live run is where it was, runs to its end, and re-runs from its
folder to the same digest.
"""

from __future__ import annotations

import json
import shutil
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import quote

import httpx
import pytest
import uvicorn
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from mimics.interfaces.web.app import create_app
from mimics.records.run_folder import load_run
from mimics.records.runner import prepare, run_to_folder
from mimics.world.map_files import save_map
from mimics.world.maps import Map
from tests.interfaces.web.fuzz_targets import (
    EDITS,
    Target,
    malformed_body,
    malformed_query,
    targets,
)
from tests.interfaces.web.test_web_api import scenario_body

FUZZ = settings(derandomize=True, max_examples=12, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))
SVG = (b"<svg xmlns='http://www.w3.org/2000/svg' width='100' height='60'>"
       b"<line x1='0' y1='0' x2='100' y2='0' stroke='black'/></svg>")
#: Labels the page's wording gives some fields (mimics.interfaces.web.wording._FIELDS).
LABELS = {"bounds": "map bounds", "segments": "walls", "path": "file",
          "min_spacing": "min spacing", "time_limit": "time limit", "robots": "robot",
          "scenarios": "scenario", "algorithms": "algorithm", "seeds": "seed"}


def api_routes(app: Any) -> set[tuple[str, str]]:
    """(method, path) of every API route of ``app``, WebSockets as ``WS``, walking the
    routers included in it."""
    found: set[tuple[str, str]] = set()

    def walk(routes: Any) -> None:
        for route in routes:
            inner = getattr(route, "original_router", None)
            if inner is not None:
                walk(inner.routes)
                continue
            path = getattr(route, "path", "")
            if not path.startswith("/api"):
                continue
            methods = getattr(route, "methods", None)
            if methods is None:  # a WebSocket route
                found.add(("WS", path))
            else:
                found.update((m, path) for m in methods if m != "HEAD")

    walk(app.routes)
    return found


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory, recorded_run: Path
           ) -> Iterator[tuple[str, Path, Any]]:
    """The workbench on 127.0.0.1 (a workspace with maps/room.txt, scenarios/two.toml
    and a recorded run): its URL, folder and app; its live runs end with it."""
    root = tmp_path_factory.mktemp("fuzz") / "ws"
    (root / "maps").mkdir(parents=True)
    save_map(Map.box(10.0, 6.0, name="room"), root / "maps" / "room.txt")
    shutil.copytree(recorded_run, root / "runs" / recorded_run.name)
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    app = create_app(root, port=port)
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port,
                                           log_level="critical", ws="websockets-sansio"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.02)
    url = f"http://127.0.0.1:{port}"
    assert httpx.put(f"{url}/api/scenarios/file", json=scenario_body()).status_code == 200
    yield url, root, app
    server.should_exit = True
    thread.join(10)
    app.state.live.close()


def check_refusal(answer: httpx.Response, names: set[str], what: str) -> None:
    """A 4xx whose JSON detail is one line naming one of ``names``."""
    assert 400 <= answer.status_code < 500, f"{what}: {answer.status_code} {answer.text[:300]}"
    detail = answer.json()["detail"]
    assert isinstance(detail, str) and detail and "\n" not in detail, f"{what}: {detail!r}"
    if answer.status_code == 404 and detail == "Not Found":
        return  # a path parameter that matches no route (an empty run id)
    wanted = names | {LABELS[n] for n in names if n in LABELS} | {
        n.replace("_", " ") for n in names}
    assert any(name.lower() in detail.lower() for name in wanted), \
        f"{what}: {detail!r} names none of {sorted(wanted)}"


def url_of(base: str, path: str, params: dict[str, Any], live_id: int) -> str:
    """The route's URL, its path parameters filled in (from ``params`` when fuzzed)."""
    for name, default in (("run_id", live_id), ("job_id", 999)):
        value = params.pop(name, default)
        path = path.replace(f"{{{name}}}", quote(str(value), safe=""))
    return base + path


def fuzz_route(client: httpx.Client, key: tuple[str, str], target: Target, live_id: int
               ) -> None:
    """Draw malformed requests for one route; each must be refused cleanly."""
    method, path = key
    if target.no_input:
        answer = client.request(method, url_of(client.base_url.__str__().rstrip("/"), path,
                                               {}, live_id), params={"seeed": "5"})
        assert answer.status_code == 200, f"{key}: {answer.status_code} {answer.text[:200]}"
        return
    base = str(client.base_url).rstrip("/")
    strategies = []
    if target.body is not None:
        strategies.append(malformed_body(target))
    if target.query_kinds:
        strategies.append(malformed_query(target))
    if target.body is None and method in ("POST", "PUT") and "upload" not in path \
            and path.rsplit("/", 1)[-1] != "import":
        # a route without a body: any field sent is refused too
        strategies.append(st.tuples(st.just("body"), st.just("body"), st.sampled_from(
            [{"seeed": 5}, [1], "x", 5, {"a": {"b": [1]}}])).map(
                lambda t: (t[0], "body", t[2])))

    @FUZZ
    @given(st.one_of(*strategies))
    def one(drawn: tuple[str, str, Any]) -> None:
        kind, name, spoiled = drawn
        if kind == "query":
            params = dict(spoiled)
            body: Any = target.body
        else:
            params, body = dict(target.query), spoiled
        url = url_of(base, path, params, live_id)
        sent = {"json": body} if body is not None else {}
        if path.endswith(("/import", "/upload")):
            sent = {"content": SVG}
        answer = client.request(method, url, params=params, **sent)
        names = {name}
        if kind == "body":  # a body sent where none is taken: named, or its first key
            names = {"body", *(str(k) for k in spoiled)} if isinstance(spoiled, dict) \
                else {"body"}
        if kind == "query" and name == "options":  # import options: their own names
            names |= {"options", "scale", "tolerance", "resolution", "origin", "threshold",
                      "negate", "size", "center"}
        if kind == "query" and name in ("run_id", "job_id"):
            names |= {"live run", "job", name}
        if key == ("POST", "/api/algorithms/upload"):
            names |= {"upload"}  # off on this server: refused whatever the file
        names |= {target.aliases[n] for n in names if n in target.aliases}
        value = spoiled.get(name) if isinstance(spoiled, dict) else None
        if kind == "enormous" and isinstance(value, int | float):  # the value named instead
            names |= {str(value), f"{value:g}"}
        if kind != "query" and isinstance(spoiled, dict) and isinstance(spoiled.get(name), dict):
            names |= {k.replace("_", " ") for k in spoiled[name]}  # a table's own keys
        check_refusal(answer, names, f"{method} {path} {kind} {name}: {str(spoiled)[:200]}")

    one()


def test_every_api_route_has_a_fuzz_target(served: tuple[str, Path, Any]) -> None:
    _, _, app = served
    routes = api_routes(app)
    assert ("WS", "/api/live/{run_id}/stream") in routes and len(routes) > 40
    missing = routes - set(targets("runs/x", "scenarios/x.toml"))
    assert not missing, f"routes the fuzzer does not reach: {sorted(missing)}"


def test_the_api_refuses_malformed_requests_and_the_live_run_goes_on(
        served: tuple[str, Path, Any], recorded_run: Path) -> None:
    url, root, app = served
    client = httpx.Client(base_url=url, timeout=120)
    live = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                          "algorithm": "go_to_goal", "seed": 3,
                                          "paused": True, "speed": "fastest"}).json()
    live_id = live["id"]
    assert client.post(f"/api/live/{live_id}/step").json()["step"] == 1
    accepted = client.post(f"/api/live/{live_id}/edit",
                           json={"kind": "add_wall", "segment": [4.0, 0.5, 4.0, 2.5]})
    assert accepted.status_code == 200, accepted.text
    reached: set[tuple[str, str]] = set()
    for key, target in targets(f"runs/{recorded_run.name}", "scenarios/two.toml").items():
        if key[0] == "WS":
            continue  # test_the_stream_survives_malformed_messages
        fuzz_route(client, key, target, live_id)
        reached.add(key)
    for target in EDITS.values():  # the edit route, with every kind's fields
        fuzz_route(client, ("POST", "/api/live/{run_id}/edit"), target, live_id)
    assert reached == {k for k in api_routes(app) if k[0] != "WS"}
    # nothing refused changed the run: where it was, with its one edit, and it goes on
    now = client.get(f"/api/live/{live_id}").json()
    assert (now["state"], now["step"], now["error"]) == ("paused", 1, "")
    assert len(client.get(f"/api/live/{live_id}/meta").json()["map"]["segments"]) == 5
    client.post(f"/api/live/{live_id}/resume")
    end = wait_ended(client, live_id)
    assert (end["state"], end["status"]) == ("finished", "time_limit")
    folder = root / end["run"]
    recorded = load_run(folder)
    assert (recorded.events["kind"] == "edit").sum() == 1
    again = run_to_folder(prepare(folder / "scenario.toml", "go_to_goal", seed=3),
                          root / "again")
    assert again.trajectory_digest == recorded.summary["trajectory_digest"]
    assert not (root / "maps" / "fz.txt").exists() and not (root / "batteries" / "fz").exists()
    assert not (root / "scenarios" / "fz.toml").exists()


def wait_ended(client: httpx.Client, live_id: int) -> dict[str, Any]:
    for _ in range(2400):  # a bound only against a hang
        answer = client.get(f"/api/live/{live_id}").json()
        if answer["state"] in ("finished", "error"):
            return answer
        time.sleep(0.05)
    raise AssertionError(f"live run {live_id} did not end")


def test_the_stream_survives_malformed_messages_and_refuses_bad_handshakes(
        served: tuple[str, Path, Any]) -> None:
    url, _, _ = served
    client = httpx.Client(base_url=url, timeout=120)
    live_id = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                             "algorithm": "go_to_goal", "paused": True}
                          ).json()["id"]
    ws = url.replace("http://", "ws://")
    for bad in ("999", "abc", str(10**30), "-1", "1e300"):  # refused at the handshake
        with pytest.raises(InvalidStatus) as refused:
            connect(f"{ws}/api/live/{quote(bad)}/stream", open_timeout=30).close()
        assert 400 <= refused.value.response.status_code < 500, bad
    with pytest.raises(InvalidStatus) as foreign:
        connect(f"{ws}/api/live/{live_id}/stream", open_timeout=30,
                origin="http://evil.example").close()  # type: ignore[arg-type]
    assert foreign.value.response.status_code == 403

    @FUZZ
    @given(st.one_of(
        st.sampled_from([json.dumps({"seeed": 5}), json.dumps({"type": "edit",
                         "kind": "add_wall", "segment": [1e300, 0, 1, 1]}),
                         "{" * 5000, "\x00", json.dumps([1e308] * 1000), "null", ""]),
        st.binary(max_size=2000),
        st.text(max_size=500)))
    def one(message: str | bytes) -> None:
        socket_.send(message)

    with connect(f"{ws}/api/live/{live_id}/stream", open_timeout=30,
                 max_size=2**24) as socket_:
        assert json.loads(socket_.recv(timeout=30))["type"] == "meta"
        assert json.loads(socket_.recv(timeout=30))["type"] == "state"
        assert isinstance(socket_.recv(timeout=30), bytes)  # the frame at step 0
        one()
        # the stream still streams: a step sends its frame
        assert client.post(f"/api/live/{live_id}/step").json()["step"] == 1
        while isinstance(frame := socket_.recv(timeout=30), str):
            pass
        assert isinstance(frame, bytes)
    now = client.get(f"/api/live/{live_id}").json()
    assert (now["state"], now["step"], now["error"]) == ("paused", 1, "")
    client.post(f"/api/live/{live_id}/stop")
    assert wait_ended(client, live_id)["status"] == "stopped"
