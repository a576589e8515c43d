"""The inspector's cost to a live run at fastest: s_sim/s and robot-steps/s with and without
one robot inspected, its requests made as the live page makes them.

    python benchmarks/live_inspect.py [--repeats 5] [--time 30] [--scenario cave]

Bar (issue 51): inspecting one robot costs the run at most 10% of its speed. The
workbench is served by uvicorn in this process (``benchmarks/live_stream.py``'s
``serve``); each live run (``deployment``, seed 1, speed ``fastest``, 60 frames/s)
steps in its worker process while a WebSocket client reads its stream as the page
does and, for each frame, asks what the page's inspector asks
(``static/js/live_inspector.js``):

* ``none``: nothing inspected;
* ``inspect``: robot 0 selected: its values and lines (``/robot``) at most every
  ``INSPECT_MS`` (250 ms), beams not asked for (the page's default);
* ``inspect+beams``: the same, and its beams (``/beams``) at most every 250 ms (the
  "beams of the selected robot" box ticked);
* ``per-frame`` (the page before issue 51): ``/robot`` and ``/beams`` asked on every
  frame, one request of each at a time.

s_sim/s and robot-steps/s are taken between the first and the last frame; medians of
``--repeats`` runs, the modes in turn. Writes ``benchmarks/results/live_inspect.json``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import platform
import statistics
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

import numpy as np
from websockets.sync.client import connect

sys.path.insert(0, str(Path(__file__).parent))
from common import add_run_options, write_json
from live_stream import post, serve

RESULTS = Path(__file__).with_name("results") / "live_inspect.json"
INSPECT_S = 0.25  # the page's INSPECT_MS
MODES = ("none", "inspect", "inspect+beams", "per-frame")
BAR = 0.10  # share of the speed inspecting one robot may cost


def get(address: str, path: str) -> None:
    with contextlib.suppress(OSError):  # (a read refused at the run's end: no failure here)
        urllib.request.urlopen(f"http://{address}{path}", timeout=60).read()


class Inspector:
    """The page's requests for robot 0, in a thread of their own (one at a time, as the
    page's): asked by ``frame()`` on each frame, as the mode says."""

    def __init__(self, address: str, run_id: int, mode: str) -> None:
        self.address, self.run_id, self.mode = address, run_id, mode
        self.wanted = threading.Event()
        self.done = False
        self.last = {"robot": 0.0, "beams": 0.0}
        self.requests = 0
        self.thread = threading.Thread(target=self.loop, daemon=True)
        self.thread.start()

    def frame(self) -> None:
        self.wanted.set()

    def loop(self) -> None:
        base = f"/api/live/{self.run_id}"
        while not self.done:
            if not self.wanted.wait(0.05):
                continue
            self.wanted.clear()
            asks = ["robot"] + (["beams"] if self.mode in ("inspect+beams", "per-frame") else [])
            for name in asks:
                now = time.perf_counter()
                if self.mode != "per-frame" and now - self.last[name] < INSPECT_S:
                    self.wanted.set()  # the page's trailing call, when it is due
                    continue
                self.last[name] = now
                get(self.address, f"{base}/{name}?robot=0")
                self.requests += 1
            if self.mode != "per-frame" and self.wanted.is_set():
                time.sleep(0.01)


def live_once(address: str, scenario: str, sim_time: float, mode: str) -> dict[str, float]:
    run = post(address, "/api/live", {"scenario": scenario, "algorithm": "deployment",
                                      "seed": 1, "time": sim_time, "speed": "fastest",
                                      "paused": True, "fps": 60})
    robots = int(json.loads(urllib.request.urlopen(
        f"http://{address}/api/live/{run['id']}/meta", timeout=60).read())["robots"])
    inspector = Inspector(address, run["id"], mode) if mode != "none" else None
    arrivals: list[tuple[float, float]] = []
    with connect(f"ws://{address}/api/live/{run['id']}/stream", max_size=None) as stream:
        for _ in range(3):  # meta, state, the first frame
            stream.recv()
        post(address, f"/api/live/{run['id']}/resume", {})
        for message in stream:
            if isinstance(message, bytes):
                arrivals.append((time.perf_counter(),
                                 float(np.frombuffer(message, "<f4", 1, 8)[0])))
                if inspector is not None:
                    inspector.frame()
    if inspector is not None:
        inspector.done = True
        inspector.thread.join(5)
    (wall0, sim0), (wall1, sim1) = arrivals[0], arrivals[-1]
    dt = 0.1
    seconds = wall1 - wall0
    return {"sim_speed": (sim1 - sim0) / seconds,
            "robot_steps": robots * round((sim1 - sim0) / dt) / seconds,
            "fps": (len(arrivals) - 1) / seconds,
            "requests_per_s": (inspector.requests / seconds) if inspector else 0.0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_options(parser, repeats=5, time=30.0, scenario="cave")
    args = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="mimics-inspect-bench-"))
    address, server = serve(root)
    live_once(address, args.scenario, 2.0, "inspect+beams")  # kernels, caches
    samples: dict[str, list[dict[str, float]]] = {mode: [] for mode in MODES}
    for _ in range(args.repeats):
        for mode in MODES:
            samples[mode].append(live_once(address, args.scenario, args.time, mode))
    rows = {}
    for mode in MODES:
        rows[mode] = {key: statistics.median(s[key] for s in samples[mode])
                      for key in ("sim_speed", "robot_steps", "fps", "requests_per_s")}
    base = rows["none"]["sim_speed"]
    for mode in MODES:
        row = rows[mode]
        row["cost"] = 1.0 - row["sim_speed"] / base
        print(f"{mode:14s} {row['sim_speed']:7.2f} s_sim/s  {row['robot_steps']:9.0f} "
              f"robot-steps/s  {row['fps']:5.1f} frames/s  {row['requests_per_s']:5.1f} "
              f"requests/s  cost {row['cost']:+.1%}")
    met = rows["inspect"]["cost"] <= BAR
    print(f"inspecting one robot costs {rows['inspect']['cost']:.1%} of the speed (bar <= "
          f"{BAR:.0%}): {'met' if met else 'NOT met'}")
    server.should_exit = True
    write_json(RESULTS, {
        "machine": platform.node(), "python": platform.python_version(),
        "scenario": args.scenario, "sim_time": args.time, "repeats": args.repeats,
        "rows": rows, "bar": BAR, "bar_met": met})


if __name__ == "__main__":
    main()
