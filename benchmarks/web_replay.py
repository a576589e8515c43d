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
import re
import shutil
import statistics
import time
from pathlib import Path

from live_stream import serve
from playwright.sync_api import expect, sync_playwright

COUNTER = """() => {
  const page = window.workbench.runs;
  const draw = page.view.draw;
  window.painted = 0;
  page.view.draw = (c, v) => { window.painted += 1; draw(c, v); };
}"""


def start_of_name(run: str) -> re.Pattern[str]:
    """The accessible name of a run's button: the run, then its status and robots
    (``runs/a time_limit, 10 robots``); its slashes escaped for Playwright's selector."""
    return re.compile("^" + re.escape(run).replace("/", "\\/") + r"(\s|$)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workspace", type=Path, required=True)
    parser.add_argument("--run", required=True, help="the run folder, workspace-relative")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-trails", action="store_true", help="play with trails off")
    args = parser.parse_args()
    address, server = serve(args.workspace)
    loads, rates = [], []
    with sync_playwright() as driver:
        browser = driver.chromium.launch(executable_path=shutil.which("chromium"),
                                         args=["--no-sandbox"])
        for _ in range(args.repeats):
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"http://{address}/#/runs")
            start = time.perf_counter()
            button = page.get_by_role("button", name=start_of_name(args.run))
            button.click()
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
