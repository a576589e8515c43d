// The Runs page: replay a run folder (binary frames), play/pause/scrub, speed, colours by
// state, trails, the inspector (a clicked robot's values, beams and log up to now), events on
// the time bar, video export, the trajectories plot.
import { api, element, guarded, say, waitJob } from "./api.js";
import { parseFrames } from "./frames.js";
import { createInspector, nearestRobot } from "./inspector.js";
import { showLiveRuns } from "./live.js";
import { enlargeable } from "./plot_view.js";
import { fetchMotion, replaySource } from "./replay_inspector.js";
import { STATE_NAMES, WorldView, drawGoals, drawHeadings, drawIds, drawRobots, drawTrails }
  from "./view.js";

const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 5, 10, 25, 50, 100];
const EVENT_COLORS = { collision: "#d62728", deadlock: "#ff7f0e", livelock: "#9467bd",
  exception: "#e377c2", escaped: "#8c8c8c", reached_goal: "#2ca02c" };
const TRAIL_FRAMES = 40;

// The walls at frame k of an edited run: the last wall set of meta.walls (see runs.py) whose
// first frame is at or before k; a run without wall edits has one set.
export function wallsAt(meta, k) {
  let segments = meta.map.segments;
  for (const set of meta.walls || []) if (set.frame <= k) segments = set.segments;
  return segments;
}

// The goals at frame k, after the set_goal edits before it (meta.goal_sets, as the walls).
export function goalsAt(meta, k) {
  let goals = meta.goals;
  for (const set of meta.goal_sets || []) if (set.frame <= k) goals = set.goals;
  return goals;
}

// Robot -> sorted frames where an edit put it at a new place (meta.moves): its trail breaks.
function movesByRobot(meta) {
  const moves = new Map();
  for (const [robot, frame] of meta.moves || []) {
    if (!moves.has(robot)) moves.set(robot, []);
    moves.get(robot).push(frame);
  }
  return moves;
}

// A run's state and robot count for the list: "finished, 3 robots", "not finished", "error".
export function runState(run) {
  if (run.error) return "unreadable";
  const robots = run.robots === undefined || run.robots === null ? "" : `, ${run.robots} robots`;
  return `${run.status || "not finished"}${robots}`;
}

export class RunPage {
  constructor(root) {
    this.root = root;
    this.data = null;
    this.meta = null;
    this.frame = 0;
    this.time = 0;
    this.playing = false;
    this.selected = -1;
    this.beams = [];
    this.motion = null; // the selected robot's v, w and references per frame (/api/runs/robot)
    this.build();
  }

  build() {
    this.list = element("ul", { class: "files", "aria-label": "Runs" });
    this.summary = element("div", { class: "hint" });
    this.exportBar = element("progress", { max: "1", value: "0", "aria-label": "Export progress" });
    this.videoLink = element("p", {});
    this.plotBox = element("div", { class: "plots" });
    this.legend = element("div", { class: "legend" });
    this.liveList = element("ul", { class: "files", "aria-label": "Live runs" });
    const side = element("div", { class: "side" },
      element("h2", {}, "Live runs"), this.liveList,
      element("h2", {}, "Runs"), this.list, element("h2", {}, "Run"), this.summary,
      this.legend, element("h2", {}, "Video"),
      element("button", { type: "button", onclick: () => this.exportVideo() }, "Export video"),
      this.exportBar, this.videoLink,
      element("h2", {}, "Plot"),
      element("button", { type: "button", onclick: () => this.showPlot() }, "Trajectories plot"),
      this.plotBox);
    this.canvas = element("canvas", { "aria-label": "Replay canvas" });
    // disabled until a run's frames are loaded, so a click never falls into the gap
    // aria-pressed shows which of Play and Pause is in effect
    this.playButton = element("button", { type: "button", disabled: true,
      "aria-pressed": "false", onclick: () => this.play() }, "Play");
    this.pauseButton = element("button", { type: "button", "aria-pressed": "true",
      onclick: () => this.pause() }, "Pause");
    this.scrub = element("input", { type: "range", min: "0", max: "0", value: "0", step: "1",
      "aria-label": "Time", oninput: () => this.seekFrame(Number(this.scrub.value)) });
    this.speed = element("select", { "aria-label": "Speed" },
      ...SPEEDS.map((s) => element("option", { value: String(s) }, `x${s}`)));
    this.speed.value = "1";
    this.trails = element("input", { type: "checkbox", checked: true, "aria-label": "Trails",
      onchange: () => this.view.redraw() });
    this.clock = element("span", { role: "timer", "aria-label": "Simulated time" },
      "t = 0.00 s");
    this.timebar = element("canvas", { id: "timebar", "aria-label": "Events on the time bar" });
    this.timebar.addEventListener("pointerdown", (e) => {
      if (!this.data) return;
      const box = this.timebar.getBoundingClientRect();
      this.seekTime(((e.clientX - box.left) / box.width) * this.meta.duration);
    });
    this.inspectorPanel = element("div", { class: "inspector", "aria-label": "Inspector" });
    this.inspector = createInspector(this.inspectorPanel, replaySource(this));
    this.root.replaceChildren(side, element("div", { class: "stage" },
      element("div", { class: "canvas-box" }, this.canvas), this.timebar,
      element("div", { class: "controls" }, this.playButton, this.pauseButton, this.scrub,
        this.clock, element("label", {}, "speed ", this.speed),
        element("label", {}, this.trails, " trails"))), this.inspectorPanel);
    this.view = new WorldView(this.canvas, (c, view) => this.paint(c, view));
    this.view.drawStatic = (c, view) => {
      if (!this.meta) return;
      view.drawSegments(wallsAt(this.meta, this.frame));
      this.paintGoals(c, view);
    };
    this.canvas.addEventListener("pointerdown", (e) => this.pick(e));
  }

  async refresh() {
    showLiveRuns(this.liveList); // live runs of this server, above the run folders
    const data = await guarded(() => api.get("/api/runs"));
    if (!data) return;
    this.list.replaceChildren(...data.runs.map((run) => element("li", {},
      element("button", { type: "button", onclick: () => this.open(run.path) },
        run.path, " ", element("span", { class: "run-state" }, runState(run))))));
  }

  enter(params) {
    const path = params.get("path");
    if (path && (!this.meta || this.meta.path !== path)) this.open(path);
  }

  leave() { this.pause(); }

  async open(path) {
    this.pause();
    this.playButton.disabled = true;
    say(`loading ${path}...`);
    const [meta, buffer] = await Promise.all([
      guarded(() => api.get("/api/runs/meta", { path })),
      guarded(() => api.binary("/api/runs/frames", { path }))]);
    if (!meta || !buffer) return;
    this.meta = meta;
    this.data = parseFrames(buffer);
    this.halfLength = Float32Array.from(meta.half_length);
    this.halfWidth = Float32Array.from(meta.half_width);
    this.colors = STATE_NAMES.map((name) => meta.colors[name]);
    this.selected = -1;
    this.beams = [];
    this.motion = null;
    this.moves = movesByRobot(meta);
    this.wallsShown = null;
    this.goalsShown = null;
    this.inspector.select(-1);
    this.plotBox.replaceChildren();
    this.videoLink.replaceChildren(...(meta.video ? [this.videoAnchor()] : []));
    this.scrub.max = String(this.data.frames - 1);
    const s = meta.summary;
    this.summary.textContent = `${meta.title}: ${s.status}, ${meta.robots} robots, `
      + `${s.reached_goal ?? "?"} reached goal, ${s.collisions ?? "?"} collisions, `
      + `${s.deadlocks ?? "?"} deadlocks, ${(s.sim_time ?? meta.duration).toFixed(1)} s`
      + (meta.stride > 1 ? ` (every ${meta.stride}th step shown)` : "")
      // the error names the file and line of the user's code, then shows that line
      + (s.error ? `\nerror: ${s.error}` : "");
    this.summary.style.whiteSpace = s.error ? "pre-wrap" : "";
    this.legend.replaceChildren(...STATE_NAMES.map((name, k) => element("span", {},
      element("i", { style: `background:${this.colors[k]}` }), name.replace("_", " "))));
    this.view.fit(meta.map.bounds);
    this.view.invalidate();
    this.seekFrame(0);
    this.drawTimebar();
    window.history.replaceState(null, "", `#/runs?path=${encodeURIComponent(path)}`);
    say(`${path}: ${this.data.frames} frames of ${meta.robots} robots`);
    this.playButton.disabled = false;
  }

  setPlaying(playing) {
    this.playing = playing;
    this.playButton.setAttribute("aria-pressed", String(playing));
    this.pauseButton.setAttribute("aria-pressed", String(!playing));
  }

  play() {
    if (!this.data || this.playing) return;
    if (this.frame >= this.data.frames - 1) this.seekFrame(0);
    this.setPlaying(true);
    let last = performance.now();
    const tick = (now) => {
      if (!this.playing) return;
      const advance = ((now - last) / 1000) * Number(this.speed.value);
      last = now;
      this.seekTime(this.time + advance, false);
      if (this.frame >= this.data.frames - 1) { this.setPlaying(false); return; }
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }

  pause() { this.setPlaying(false); this.fetchBeams(); }

  seekTime(t, fetchBeams = true) {
    const { times, frames } = this.data;
    this.time = Math.max(0, Math.min(t, this.meta.duration));
    let lo = 0;
    let hi = frames - 1;
    while (lo < hi) { // last frame at or before this.time
      const mid = (lo + hi + 1) >> 1;
      if (times[mid] <= this.time + 1e-6) lo = mid; else hi = mid - 1;
    }
    this.show(lo, fetchBeams);
  }

  seekFrame(k) {
    this.time = this.data.times[k];
    this.show(k, true);
  }

  show(k, fetchBeams) {
    this.frame = k;
    this.scrub.value = String(k);
    this.clock.textContent = `t = ${this.time.toFixed(2)} s`;
    const [walls, goals] = [wallsAt(this.meta, k), goalsAt(this.meta, k)];
    if (walls !== this.wallsShown || goals !== this.goalsShown) {
      // an edit changed the walls or the goals: the static layer again
      [this.wallsShown, this.goalsShown] = [walls, goals];
      this.view.invalidate();
    }
    // while playing, beams follow one request at a time (drawn a frame or two late)
    if (fetchBeams || this.inspector.allBeams || this.selected >= 0) this.fetchBeams();
    this.view.redraw();
    this.inspector.update();
  }

  pick(event) {
    if (!this.data || event.button !== 0 || event.shiftKey) return;
    const [x, y] = this.view.eventWorld(event);
    const { robots, poses } = this.data;
    const best = nearestRobot(poses.subarray(this.frame * robots * 3, (this.frame + 1) * robots * 3),
      robots, x, y, Math.max(0.5, 15 / this.view.scale));
    this.selected = best;
    if (!this.inspector.allBeams) this.beams = [];
    this.inspector.select(best);
    this.view.redraw();
    if (best >= 0) {
      this.fetchBeams();
      fetchMotion(this, best);
    }
  }

  // The beams drawn: every robot's when the inspector's toggle is on, else the selected one's;
  // one request at a time, then one for the frame shown by then.
  async fetchBeams() {
    if (!this.data) return;
    const all = this.inspector.allBeams;
    if (!all && (this.selected < 0 || !this.meta.beams[this.selected])) return;
    if (this.beamsPending) { this.beamsWanted = true; return; }
    const [robot, frame, path] = [this.selected, this.frame, this.meta.path];
    this.beamsPending = true;
    this.beamsWanted = false;
    const data = await guarded(() => (all
      ? api.get("/api/runs/all_beams", { path, frame })
      : api.get("/api/runs/beams", { path, robot, frame })));
    this.beamsPending = false;
    if (data && all === this.inspector.allBeams && (all || robot === this.selected)
        && path === this.meta.path) {
      this.beams = data.segments;
      this.view.redraw();
    }
    if (this.beamsWanted || frame !== this.frame) this.fetchBeams();
  }

  paint(c, view) {
    if (!this.data) return;
    const { robots, poses, states } = this.data;
    const k = this.frame;
    const frame = poses.subarray(k * robots * 3, (k + 1) * robots * 3);
    if (this.trails.checked && k > 0) {
      const first = Math.max(0, k - TRAIL_FRAMES);
      const step = Math.max(1, Math.floor((k - first) / 12));
      const past = [];
      const shown = [];
      for (let f = first; f <= k; f += step) {
        past.push(poses.subarray(f * robots * 3));
        shown.push(f);
      }
      shown.push(k);
      // a robot an edit moved: no line from its old place to the new one
      const jumps = (i, j) => (this.moves.get(i) || []).some(
        (m) => shown[j - 1] < m && m <= shown[j]);
      drawTrails(c, view, past, frame, robots, this.moves.size ? jumps : null);
    }
    if (this.beams.length) view.drawBeams(this.beams);
    const stateBase = k * robots;
    drawRobots(c, view, frame, this.halfLength, this.halfWidth,
      (i) => this.colors[states[stateBase + i]] || "#000", robots);
    this.paintHeadings(c, view, frame, robots);
    this.paintIds(c, view, frame, robots);
    if (this.selected >= 0) {
      const [px, py] = view.toScreen(frame[3 * this.selected], frame[3 * this.selected + 1]);
      c.strokeStyle = "#111";
      c.lineWidth = 2;
      c.beginPath();
      c.arc(px, py, Math.max(8, this.halfLength[this.selected] * view.scale * 1.6), 0, 2 * Math.PI);
      c.stroke();
    }
  }

  // Goals, headings and ids as in the exported video (view.js; goals in the static layer).
  paintGoals(c, view) { drawGoals(c, view, goalsAt(this.meta, this.frame)); }

  paintHeadings(c, view, frame, robots) {
    drawHeadings(c, view, frame, robots, this.halfLength, this.halfWidth);
  }

  paintIds(c, view, frame, robots) {
    drawIds(c, view, frame, robots, this.halfLength, this.halfWidth);
  }

  drawTimebar() {
    const canvas = this.timebar;
    const ratio = window.devicePixelRatio || 1;
    canvas.width = Math.round(canvas.clientWidth * ratio);
    canvas.height = Math.round(canvas.clientHeight * ratio);
    const c = canvas.getContext("2d");
    c.setTransform(ratio, 0, 0, ratio, 0, 0);
    c.fillStyle = "#eef1f5";
    c.fillRect(0, 0, canvas.clientWidth, canvas.clientHeight);
    const duration = this.meta.duration || 1;
    for (const event of this.meta.events) {
      const color = EVENT_COLORS[event.kind];
      if (!color) continue;
      c.fillStyle = color;
      c.fillRect((event.time / duration) * canvas.clientWidth - 1, 3, 2, canvas.clientHeight - 6);
    }
  }

  videoAnchor() {
    return element("a", { href: `/api/runs/video?${new URLSearchParams({ path: this.meta.path })}`,
      target: "_blank" }, "replay.mp4");
  }

  async exportVideo() {
    if (!this.meta) { say("open a run first", true); return; }
    const path = this.meta.path;
    const job = await guarded(() => api.post("/api/runs/export", { path,
      speed: Math.max(1, Number(this.speed.value)),
      robot: this.selected >= 0 && this.meta.beams[this.selected] ? this.selected : null }));
    if (!job) return;
    say(`exporting ${path}/replay.mp4...`);
    const end = await guarded(() => waitJob(job.id, (j) => {
      this.exportBar.max = j.total || 1;
      this.exportBar.value = j.done;
    }));
    if (!end) return;
    if (end.state !== "done") { say(`export failed: ${end.error}`, true); return; }
    say(`wrote ${end.result.video} (${end.result.frames} frames)`);
    if (this.meta.path === path) this.videoLink.replaceChildren(this.videoAnchor());
  }

  // The plot as a thumbnail in the side panel; a click shows it over the whole page.
  showPlot() {
    if (!this.meta) return;
    this.plotBox.replaceChildren(enlargeable(element("img", {
      alt: `trajectories of ${this.meta.path}`,
      src: `/api/runs/plot?${new URLSearchParams({ path: this.meta.path })}` })));
  }
}
