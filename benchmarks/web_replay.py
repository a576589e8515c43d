"""How fast the workbench's replay loads and draws a run in headless Chromium.

    python benchmarks/web_replay.py --workspace DIR --run runs/NAME [--seconds 5] [--repeats 3]
        [--no-trails]

Serves ``DIR`` with ``mimics ui``'s app in this process, opens the Runs page in
Debian's ``chromium`` (Playwright), and for each repeat: opens the run (the
time from the click to the page saying it has the frames: the binary body's
transfer and parse), then plays it at x1 for ``--seconds`` and counts the
frames the page painted (its draw function is wrapped to count calls). Prints
the medians. Headless Chromium paints on the CPU here (no GPU), so a desktop
browser is faster; the machine is shared, so figures are noisy.
"""

from __future__ import annotations

import argparse
import shutil
import socket
import statistics
import threading
import time
from pathlib import Path

import uvicorn
from playwright.sync_api import expect, sync_playwright

from mimics.interfaces.web.app import create_app

COUNTER = """() => {
  const page = window.workbench.runs;
  const draw = page.view.draw;
  window.painted = 0;
  page.view.draw = (c, v) => { window.painted += 1; draw(c, v); };
}"""


def serve(workspace: Path) -> tuple[uvicorn.Server, int]:
    """Start the workbench on a free port in a thread; returns the server and the port."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(create_app(workspace, port=port), host="127.0.0.1",
                                           port=port, log_level="warning"))
    threading.Thread(target=server.run, daemon=True).start()
    while not server.started:
        time.sleep(0.02)
    return server, port


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workspace", type=Path, required=True)
    parser.add_argument("--run", required=True, help="the run folder, workspace-relative")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-trails", action="store_true", help="play with trails off")
    args = parser.parse_args()
    server, port = serve(args.workspace)
    loads, rates = [], []
    with sync_playwright() as driver:
        browser = driver.chromium.launch(executable_path=shutil.which("chromium"),
                                         args=["--no-sandbox"])
        for _ in range(args.repeats):
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"http://127.0.0.1:{port}/#/runs")
            start = time.perf_counter()
            page.get_by_role("button", name=args.run, exact=True).click()
            expect(page.get_by_role("status")).to_contain_text("frames of", timeout=300_000)
            loads.append(time.perf_counter() - start)
            robots = page.evaluate("window.workbench.runs.data.robots")
            frames = page.evaluate("window.workbench.runs.data.frames")
            page.evaluate(COUNTER)
            if args.no_trails:
                page.get_by_label("Trails").uncheck()
            page.get_by_role("button", name="Play").click()
            page.wait_for_timeout(args.seconds * 1000)
            painted = page.evaluate("window.painted")
            page.get_by_role("button", name="Pause").click()
            rates.append(painted / args.seconds)
            page.close()
        browser.close()
    server.should_exit = True
    print(f"{args.run}: {robots} robots, {frames} frames sent")
    print(f"load (transfer + parse), median of {args.repeats}: {statistics.median(loads):.2f} s "
          f"(all: {', '.join(f'{v:.2f}' for v in loads)})")
    print(f"frames painted per second while playing x1, median: {statistics.median(rates):.1f} "
          f"(all: {', '.join(f'{v:.1f}' for v in rates)})")


if __name__ == "__main__":
    main()
