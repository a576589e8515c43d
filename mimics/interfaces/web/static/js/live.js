// The live page (#/live/ID): a run stepping in a worker process, drawn as it runs from the
// frames of its WebSocket (the replay's binary layout and renderer), with Pause, Resume,
// Step, Stop, the speed, and edits by mouse (move a robot, set a goal, add or remove a wall,
// remove a robot). Leaving the page closes the socket; the run goes on.
import { api, element, guarded, say } from "./api.js";
import { createInspector } from "./inspector.js";
import { fetchLiveBeams, liveSource } from "./live_inspector.js";
import { liveStateLine, refusalSentence } from "./live_words.js";
import { parseFrames } from "./frames.js";
import { STATE_NAMES, WorldView, drawGoals, drawHeadings, drawIds, drawRobots, drawTrails }
  from "./view.js";

const SPEEDS = ["0.1", "0.25", "0.5", "1", "2", "5", "10", "25", "50", "100", "fastest"];
const TRAIL_FRAMES = 40; // frames kept for the trails...
const TRAIL_POINTS = 12; // ...of which this many are drawn
const TOOLS = [
  ["move", "Select / drag robot"], ["goal", "Set goal of selected robot"],
  ["wall", "Draw wall"], ["rectangle", "Draw rectangle"], ["unwall", "Remove wall"],
  ["unrobot", "Remove robot"]];

// Live runs of the server, for the top of the Runs page: a link to each one's live page.
export async function showLiveRuns(list) {
  const data = await guarded(() => api.get("/api/live"));
  if (!data) return;
  list.replaceChildren(...data.live.map((run) => element("li", {},
    element("a", { href: `#/live/${run.id}` }, `live ${run.id}: ${run.scenario} / `
      + `${run.algorithm} / seed ${run.seed}`, " ",
    element("span", { class: "run-state" }, `${run.state}, t = ${run.time.toFixed(1)} s`
      + (run.run ? ` → ${run.run}` : ""))))));
}

// Start a live run (POST /api/live) and open its page; the error is shown on failure.
export async function startLive(body) {
  say("starting a live run...");
  const run = await guarded(() => api.post("/api/live", body));
  if (run) {
    say(`live run ${run.id} started`);
    window.location.hash = `#/live/${run.id}`;
  }
  return run;
}

export class LivePage {
  constructor(root) {
    this.root = root;
    this.id = null;
    this.socket = null;
    this.meta = null;
    this.status = null; // the last state message (GET /api/live/ID)
    this.frame = null; // { robots, poses, states, time } of the latest frame
    this.frames = 0; // frames received on this page (tests and the frame rate)
    this.past = []; // earlier frames for the trails: { poses, jumped: robots moved since }
    this.moved = new Set(); // robots an edit moved since the last frame (their trails break)
    this.selected = -1;
    this.beams = []; // segments of the inspector's beams (live_inspector.js)
    this.drag = null; // a robot being dragged, or a wall being drawn
    this.build();
  }

  build() {
    this.title = element("p", { class: "hint" }, "No live run open.");
    this.stateLine = element("p", { "aria-label": "Live state" }, "");
    // an error names the file and line of the user's code, then shows that line
    this.errorBox = element("p", { class: "field-error", role: "alert",
      style: "white-space: pre-wrap" });
    this.editLine = element("p", { class: "hint", "aria-label": "Last edit" });
    this.replayLink = element("p", {});
    this.legend = element("div", { class: "legend" });
    this.tool = "move";
    this.toolBox = element("div", { role: "radiogroup", "aria-label": "Edit tool" },
      ...TOOLS.map(([value, text]) => element("label", {}, element("input", {
        type: "radio", name: "live-tool", value, checked: value === "move",
        onchange: () => { this.tool = value; } }), ` ${text}`)));
    const side = element("div", { class: "side" },
      element("h2", {}, "Live run"), this.title, this.stateLine, this.errorBox,
      this.replayLink, this.legend, element("h2", {}, "Edit"), this.toolBox,
      element("p", { class: "hint" }, "Edits apply at the next step and are recorded in the "
        + "run folder (events.parquet, scenario.toml). Right-drag or Shift+drag pans."),
      this.editLine);
    this.canvas = element("canvas", { "aria-label": "Live canvas" });
    const button = (text, action) => element("button", { type: "button",
      onclick: () => this.control(action) }, text);
    this.pauseButton = button("Pause", "pause");
    this.resumeButton = button("Resume", "resume");
    this.stepButton = element("button", { type: "button", onclick: () => this.control("step") },
      "Step");
    this.stopButton = element("button", { type: "button", onclick: () => this.control("stop") },
      "Stop");
    this.speed = element("select", { "aria-label": "Speed", onchange: () => this.setSpeed() },
      ...SPEEDS.map((s) => element("option", { value: s }, s === "fastest" ? s : `x${s}`)));
    this.speed.value = "1";
    this.trails = element("input", { type: "checkbox", checked: true, "aria-label": "Trails",
      onchange: () => this.view.redraw() });
    // the selected robot's beams cost the run a trace of its scan: drawn only when asked
    this.beamsBox = element("input", { type: "checkbox", "aria-label": "Selected robot's beams",
      onchange: () => { this.beams = []; this.view.redraw(); fetchLiveBeams(this); } });
    this.fitButton = element("button", { type: "button", title: "Show the whole map",
      onclick: () => { if (this.meta) this.view.fit(this.meta.map.bounds); } }, "Fit view");
    this.clock = element("span", { role: "timer", "aria-label": "Simulated time" }, "t = 0.00 s");
    // the Runs page's inspector: a clicked robot's values, beams and events so far, as it runs
    this.inspectorPanel = element("div", { class: "inspector", "aria-label": "Inspector" });
    this.inspector = createInspector(this.inspectorPanel, liveSource(this));
    this.root.replaceChildren(side, element("div", { class: "stage" },
      element("div", { class: "canvas-box" }, this.canvas),
      element("div", { class: "controls" }, this.pauseButton, this.resumeButton, this.stepButton,
        this.stopButton, element("label", {}, "speed ", this.speed), this.clock,
        element("label", {}, this.trails, " trails"),
        element("label", {}, this.beamsBox, " beams of the selected robot"), this.fitButton)),
    this.inspectorPanel);
    this.view = new WorldView(this.canvas, (c, view) => this.paint(c, view));
    this.view.drawStatic = (c, view) => {
      if (!this.meta) return;
      view.drawSegments(this.meta.map.segments);
      drawGoals(c, view, this.meta.goals);
    };
    this.canvas.addEventListener("pointerdown", (e) => this.pointerDown(e));
    this.canvas.addEventListener("pointermove", (e) => this.pointerMove(e));
    this.canvas.addEventListener("pointerup", (e) => this.pointerUp(e));
    this.showControls();
  }

  refresh() {}

  enter(params) {
    const id = params.get("id");
    if (id && id !== this.id) this.open(id);
    else if (id && !this.socket) this.connect();
  }

  // Leaving the page closes its socket only: the run goes on in its worker.
  leave() { this.disconnect(); }

  open(id) {
    this.disconnect();
    this.id = id;
    this.meta = null;
    this.status = null;
    this.frame = null;
    this.frames = 0;
    this.past = [];
    this.moved = new Set();
    this.selected = -1;
    this.details = null;
    this.beams = [];
    this.inspector.select(-1);
    this.errorBox.textContent = "";
    this.editLine.textContent = "";
    this.replayLink.replaceChildren();
    this.title.textContent = `live run ${id}: connecting...`;
    this.connect();
  }

  connect() {
    const scheme = window.location.protocol === "https:" ? "wss" : "ws";
    const socket = new WebSocket(`${scheme}://${window.location.host}/api/live/${this.id}/stream`);
    socket.binaryType = "arraybuffer";
    socket.onmessage = (event) => this.receive(event.data);
    socket.onclose = () => { if (this.socket === socket) this.socket = null; };
    this.socket = socket;
  }

  disconnect() {
    if (this.socket) { const s = this.socket; this.socket = null; s.close(); }
  }

  receive(data) {
    if (typeof data !== "string") {
      const parsed = parseFrames(data);
      if (this.frame && this.frame.robots === parsed.robots) {
        this.past.push({ poses: this.frame.poses, jumped: this.frame.jumped });
        if (this.past.length > TRAIL_FRAMES) this.past.shift();
      }
      this.frame = { robots: parsed.robots, poses: parsed.poses, states: parsed.states,
        time: parsed.times[0], jumped: this.moved };
      this.moved = new Set();
      this.frames += 1;
      this.showClock();
      this.view.redraw();
      if (this.inspector.selected >= 0 && this.inspector.selected < parsed.robots) {
        this.inspector.update();
      }
      fetchLiveBeams(this);
      return;
    }
    const message = JSON.parse(data);
    if (message.type === "meta") this.takeMeta(message);
    else if (message.type === "state") this.takeState(message);
    else if (message.type === "moved") this.moved.add(message.robot);
  }

  takeMeta(meta) {
    const first = !this.meta;
    this.meta = meta;
    this.halfLength = Float32Array.from(meta.half_length);
    this.halfWidth = Float32Array.from(meta.half_width);
    this.colors = STATE_NAMES.map((name) => meta.colors[name]);
    this.title.textContent = meta.title;
    this.legend.replaceChildren(...STATE_NAMES.map((name, k) => element("span", {},
      element("i", { style: `background:${this.colors[k]}` }), name.replace("_", " "))));
    if (first) this.view.fit(meta.map.bounds);
    this.view.invalidate();
  }

  takeState(status) {
    const before = this.status ? this.status.state : "";
    this.status = status;
    const ended = status.state === "finished" || status.state === "error";
    this.stateLine.textContent = liveStateLine(status);
    if (ended && before !== status.state && !status.error) {
      say(`live run ${status.id}: ${this.stateLine.textContent}`);
    }
    if (status.error) {
      this.errorBox.textContent = `error: ${status.error}`;
      say(`live run ${status.id}: ${status.error.split("\n")[0]}`, true);
    }
    if (ended && status.run) {
      this.replayLink.replaceChildren(element("a", {
        href: `#/runs?path=${encodeURIComponent(status.run)}` }, `Open the replay of ${status.run}`));
    }
    const speed = String(status.speed);
    if (SPEEDS.includes(speed)) this.speed.value = speed;
    this.showControls();
    this.showClock();
  }

  // The action at hand is highlighted: Pause while it runs, Resume while paused; the one in
  // effect is disabled, and every control once the run ends (or while it stops).
  showControls() {
    const state = this.status ? this.status.state : "starting";
    const going = state === "running" || state === "paused";
    for (const b of [this.pauseButton, this.resumeButton, this.stepButton, this.stopButton,
      this.speed]) b.disabled = !going;
    this.pauseButton.classList.toggle("primary", state === "running");
    this.resumeButton.classList.toggle("primary", state === "paused");
    if (state === "running") this.resumeButton.disabled = true;
    if (state === "paused") this.pauseButton.disabled = true;
  }

  showClock() {
    const time = this.frame ? this.frame.time : 0;
    const dt = this.meta ? this.meta.dt : 0;
    const step = dt ? ` · step ${Math.round(time / dt)}` : "";
    const speed = this.status ? ` · ${this.status.speed === "fastest" ? "fastest"
      : `x${this.status.speed}`}` : "";
    this.clock.textContent = `t = ${time.toFixed(2)} s${step}${speed}`;
  }

  async control(action) {
    if (action === "stop") this.takeState({ ...this.status, state: "stopping" });
    const answer = await guarded(() => api.post(`/api/live/${this.id}/${action}`));
    if (answer) this.takeState({ ...answer, type: "state" });
  }

  async setSpeed() {
    const value = this.speed.value;
    const answer = await guarded(() => api.post(`/api/live/${this.id}/speed`,
      { speed: value === "fastest" ? value : Number(value) }));
    if (answer) this.takeState({ ...answer, type: "state" });
  }

  // An edit: applied at the next step (the answer says which), or refused in one line.
  async edit(body) {
    try {
      const applied = await api.post(`/api/live/${this.id}/edit`, body);
      this.editLine.textContent = `step ${applied.step}: ${applied.detail || applied.kind}`;
      this.errorBox.textContent = "";
      say(`edit applied at step ${applied.step}`);
      // the selected robot's values and lines again (paused, the time did not move)
      this.detailsKey = null;
      if (this.inspector.selected >= 0) this.inspector.select(this.inspector.selected);
      return applied;
    } catch (error) {
      const sentence = refusalSentence(error.message);
      this.errorBox.textContent = `Edit refused: ${sentence}`;
      say(`edit refused: ${sentence}`, true);
      return undefined;
    }
  }

  robotAt(x, y) {
    if (!this.frame) return -1;
    const { poses, robots, states } = this.frame;
    let best = -1;
    let bestDistance = Math.max(0.3, 12 / this.view.scale);
    for (let i = 0; i < robots; i++) {
      if (states[i] === 6) continue; // removed robots cannot be picked
      const d = Math.hypot(poses[3 * i] - x, poses[3 * i + 1] - y);
      if (d < Math.max(bestDistance, this.halfLength[i])) {
        if (d < bestDistance || best < 0) { bestDistance = d; best = i; }
      }
    }
    return best;
  }

  pointerDown(event) {
    if (!this.frame || event.button !== 0 || event.shiftKey) return;
    const [x, y] = this.view.eventWorld(event);
    const robot = this.robotAt(x, y);
    if (this.tool === "move") {
      this.selected = robot;
      if (!this.inspector.allBeams) this.beams = [];
      this.details = null;
      this.detailsKey = null;
      this.inspector.select(robot);
      fetchLiveBeams(this);
      if (robot >= 0) {
        this.drag = { kind: "robot", robot, from: [x, y], to: [x, y] };
        this.canvas.setPointerCapture(event.pointerId);
      }
    } else if (this.tool === "wall" || this.tool === "rectangle") {
      this.drag = { kind: this.tool, from: [x, y], to: [x, y] };
      this.canvas.setPointerCapture(event.pointerId);
    } else if (this.tool === "goal") {
      if (this.selected < 0) say("select a robot first (tool: Select / drag robot)", true);
      else this.edit({ kind: "set_goal", robot: this.selected, x, y });
    } else if (this.tool === "unwall") {
      this.edit({ kind: "remove_wall", at: [x, y] });
    } else if (this.tool === "unrobot" && robot >= 0) {
      this.edit({ kind: "remove_robot", robot });
    }
    this.view.redraw();
  }

  pointerMove(event) {
    if (!this.drag) return;
    this.drag.to = this.view.eventWorld(event);
    this.view.redraw();
  }

  pointerUp() {
    const drag = this.drag;
    if (!drag) return;
    this.drag = null;
    this.view.redraw();
    const [x0, y0] = drag.from;
    const [x1, y1] = drag.to;
    if (Math.hypot(x1 - x0, y1 - y0) * this.view.scale < 3) return; // a click: selection only
    if (drag.kind === "robot") {
      this.edit({ kind: "move_robot", robot: drag.robot, x: x1, y: y1 });
    } else if (drag.kind === "wall") {
      this.edit({ kind: "add_wall", segment: [x0, y0, x1, y1] });
    } else {
      this.edit({ kind: "add_wall", rectangle: [Math.min(x0, x1), Math.min(y0, y1),
        Math.max(x0, x1), Math.max(y0, y1)] });
    }
  }

  paint(c, view) {
    if (!this.frame || !this.meta) return;
    const { robots, poses, states } = this.frame;
    if (robots !== this.halfLength.length) return; // a frame before its meta
    if (this.trails.checked && this.past.length) this.paintTrails(c, view);
    if (this.beams.length) view.drawBeams(this.beams);
    drawRobots(c, view, poses, this.halfLength, this.halfWidth,
      (i) => this.colors[states[i]] || "#000", robots);
    drawHeadings(c, view, poses, robots, this.halfLength, this.halfWidth);
    drawIds(c, view, poses, robots, this.halfLength, this.halfWidth);
    if (this.selected >= 0 && this.selected < robots) {
      const [px, py] = view.toScreen(poses[3 * this.selected], poses[3 * this.selected + 1]);
      c.strokeStyle = "#111";
      c.lineWidth = 2;
      c.beginPath();
      c.arc(px, py, Math.max(8, this.halfLength[this.selected] * view.scale * 1.6), 0, 2 * Math.PI);
      c.stroke();
    }
    this.paintDrag(c, view);
  }

  // The trails through every k-th earlier frame, broken where an edit moved a robot (as the
  // replay breaks them): a kept point knows the robots moved since the kept point before it.
  paintTrails(c, view) {
    const { robots, poses } = this.frame;
    const every = Math.max(1, Math.floor(this.past.length / TRAIL_POINTS));
    const kept = [];
    const jumps = [];
    let since = new Set();
    this.past.forEach((entry, k) => {
      for (const robot of entry.jumped) since.add(robot);
      if (k % every === 0) { kept.push(entry.poses); jumps.push(since); since = new Set(); }
    });
    for (const robot of this.frame.jumped) since.add(robot);
    jumps.push(since);
    drawTrails(c, view, kept, poses, robots, (i, j) => j > 0 && jumps[j].has(i));
  }

  // What is being dragged: the robot's new place, or the wall or rectangle being drawn.
  paintDrag(c, view) {
    const drag = this.drag;
    if (!drag) return;
    const [ax, ay] = view.toScreen(...drag.from);
    const [bx, by] = view.toScreen(...drag.to);
    c.strokeStyle = "#d62728";
    c.lineWidth = 2;
    c.setLineDash([5, 4]);
    c.beginPath();
    if (drag.kind === "robot") {
      c.moveTo(ax, ay);
      c.lineTo(bx, by);
      c.arc(bx, by, Math.max(6, this.halfLength[drag.robot] * view.scale), 0, 2 * Math.PI);
    } else if (drag.kind === "wall") {
      c.moveTo(ax, ay);
      c.lineTo(bx, by);
    } else {
      c.rect(Math.min(ax, bx), Math.min(ay, by), Math.abs(bx - ax), Math.abs(by - ay));
    }
    c.stroke();
    c.setLineDash([]);
  }
}
