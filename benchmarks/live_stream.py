"""The live stream: frames a second reaching a page while a live run runs, and its speed.

    python benchmarks/live_stream.py [--repeats 3] [--cave-time 60] [--hospital-time 10]

Bars (issue 40): Cave (100 robots, ``deployment``) at >= 30 frames/s received while
the simulation keeps >= 50% of its headless speed; Hospital (2,000 robots) at
>= 15 frames/s. The workbench is served by uvicorn in this process, as ``mimics
ui`` does; each live run (``POST /api/live``, speed ``fastest``, at most 60
frames/s) steps in its worker process, and a WebSocket client reads the stream
as the page does (``websockets``' client). Frames/s and the live run's s_sim/s
are taken between the first and the last frame; the headless speed is that of
the same run (scenario, algorithm, seed, time) recorded by ``run_to_folder`` in
this process, as ``mimics run`` does. Medians of ``--repeats`` runs, live and
headless alternating. Writes ``benchmarks/results/live_stream.json``.
"""

from __future__ import annotations

import argparse
import json
import platform
import socket
import statistics
import tempfile
import threading
import time
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np
import uvicorn
from common import write_json
from websockets.sync.client import connect

from mimics.interfaces.web.app import create_app
from mimics.records.runner import prepare, run_to_folder

RESULTS = Path(__file__).with_name("results") / "live_stream.json"
BARS = {"cave": {"fps": 30.0, "speed_share": 0.5}, "hospital": {"fps": 15.0}}


def serve(root: Path) -> tuple[str, uvicorn.Server]:
    """``mimics ui``'s app serving ``root`` from a thread of this process, on a free port;
    returns its address (``host:port``) and the server (``should_exit`` stops it)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(create_app(root, port=port), host="127.0.0.1",
                                           port=port, log_level="warning"))
    threading.Thread(target=server.run, daemon=True).start()
    while not server.started:
        time.sleep(0.02)
    return f"127.0.0.1:{port}", server


def post(address: str, path: str, body: Any) -> Any:
    """POST ``body`` as JSON to the workbench at ``address``; its JSON answer."""
    request = urllib.request.Request(f"http://{address}{path}", method="POST",
                                     data=json.dumps(body).encode(),
                                     headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=600) as answer:
        return json.loads(answer.read())


def live_once(address: str, scenario: str, sim_time: float) -> dict[str, float]:
    """Frames/s and s_sim/s of one live run, read as the page reads them."""
    run = post(address, "/api/live", {"scenario": scenario, "algorithm": "deployment",
                                      "seed": 1, "time": sim_time, "speed": "fastest",
                                      "paused": True, "fps": 60})
    arrivals: list[tuple[float, float]] = []  # (wall, simulated time) of each frame
    with connect(f"ws://{address}/api/live/{run['id']}/stream",
                 max_size=None) as stream:
        for _ in range(3):  # meta, state, the first frame
            stream.recv()
        post(address, f"/api/live/{run['id']}/resume", {})
        for message in stream:  # until the server closes it after the last frame
            if isinstance(message, bytes):
                arrivals.append((time.perf_counter(),
                                 float(np.frombuffer(message, "<f4", 1, 8)[0])))
    (wall0, sim0), (wall1, sim1) = arrivals[0], arrivals[-1]
    return {"frames": len(arrivals), "fps": (len(arrivals) - 1) / (wall1 - wall0),
            "sim_speed": (sim1 - sim0) / (wall1 - wall0)}


def headless_once(scenario: str, sim_time: float, folder: Path) -> float:
    sim = prepare(scenario, "deployment", time=sim_time, seed=1)
    return run_to_folder(sim, folder).summary()["sim_speed"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cave-time", type=float, default=60.0)
    parser.add_argument("--hospital-time", type=float, default=10.0)
    args = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="mimics-live-bench-"))
    address, server = serve(root)
    rows = []
    for scenario, sim_time in (("cave", args.cave_time), ("hospital", args.hospital_time)):
        headless_once(scenario, 1.0, root / f"warm-{scenario}")  # kernels, caches
        lives, headless = [], []
        for k in range(args.repeats):
            lives.append(live_once(address, scenario, sim_time))
            headless.append(headless_once(scenario, sim_time, root / f"{scenario}-{k}"))
        row = {"scenario": scenario, "sim_time": sim_time, "repeats": args.repeats,
               "fps": statistics.median(r["fps"] for r in lives),
               "live_sim_speed": statistics.median(r["sim_speed"] for r in lives),
               "headless_sim_speed": statistics.median(headless),
               "frames": [r["frames"] for r in lives]}
        row["speed_share"] = row["live_sim_speed"] / row["headless_sim_speed"]
        bar = BARS[scenario]
        row["bar_met"] = row["fps"] >= bar["fps"] and row["speed_share"] >= bar.get(
            "speed_share", 0.0)
        rows.append(row)
        print(f"{scenario}: {row['fps']:.1f} frames/s (bar >= {bar['fps']:g}), live "
              f"{row['live_sim_speed']:.2f} s_sim/s vs headless "
              f"{row['headless_sim_speed']:.2f} s_sim/s ({row['speed_share']:.0%}"
              f"{', bar >= 50%' if 'speed_share' in bar else ''}): "
              f"{'met' if row['bar_met'] else 'NOT met'}")
    server.should_exit = True
    write_json(RESULTS, {"machine": platform.node(), "python": platform.python_version(),
                         "rows": rows})


if __name__ == "__main__":
    main()
