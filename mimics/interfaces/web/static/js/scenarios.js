// The Scenarios page: pick a map, place robots (one, line, grid, random), drag starts and
// goals, choose the robot type and sensors, time limit, save, run; start from a built-in
// scenario (opened as a new, unsaved file).
import {
  api, clearError, element, fileList, guarded, mayDiscard, parseNumbers, saveFile, say,
  shownError, waitJob,
} from "./api.js";
import {
  dragRobot, faultOf, paintScenario, placeAt, robotAt,
} from "./scenario_canvas.js";
import { startLive } from "./live.js";
import { INLINE, openBuiltin, showInlineMap, showScenario } from "./scenario_files.js";
import { WorldView } from "./view.js";

const TOOLS = ["One", "Line", "Grid", "Random", "Move", "Remove"];
const HINTS = {
  One: "Click the start, then the goal.",
  Line: "Click the first and the last start: the count spreads along; goals are start + offset.",
  Grid: "Click two corners: rows x columns of starts; goals are start + offset.",
  Random: "Click two corners of a region: the count at random, min spacing apart.",
  Move: "Drag a robot's start or its goal.",
  Remove: "Click a robot to remove it.",
};

export class ScenarioEditor {
  constructor(root) {
    this.root = root;
    this.robots = [];
    this.types = {};
    this.map = null;
    this.mapRef = "";
    this.inlineMap = null; // a map written into the scenario file (a built-in scenario's own)
    this.tool = "Line";
    this.points = [];
    this.robotTypes = {};
    this.dirty = false; // edits not saved yet (asked about before they are dropped)
    this.ownPath = null; // the file opened or last saved: saved over without asking
    this.fault = { robots: [], walls: [] }; // what the last refused save named, drawn in red
    this.build();
  }

  build() {
    const number = (label, value, step = "1") => element("input", { type: "number", value,
      step, "aria-label": label });
    this.toolButtons = TOOLS.map((name) => element("button", { type: "button",
      "aria-pressed": String(name === this.tool), onclick: () => this.setTool(name) }, name));
    this.fileListNode = element("ul", { class: "files", "aria-label": "Scenario files" });
    this.mapSelect = element("select", { "aria-label": "Map", onchange: () => this.pickMap() });
    this.builtinSelect = element("select", { "aria-label": "Built-in scenario" });
    this.typeSelect = element("select", { "aria-label": "Robot type",
      onchange: () => this.showType() });
    this.beamsInput = number("Beams", "180");
    this.rangeInput = number("Range (m)", "8", "0.1");
    this.noiseInput = number("Noise sigma (m)", "0", "0.01");
    this.countInput = number("Count", "5");
    this.rowsInput = number("Rows", "2");
    this.columnsInput = number("Columns", "3");
    this.spacingInput = number("Min spacing (m)", "0.8", "0.1");
    this.offsetInput = element("input", { type: "text", value: "5, 0",
      "aria-label": "Goal offset dx, dy (m)", "aria-describedby": "offset-problem",
      oninput: () => this.checkOffset() });
    this.offsetProblem = element("span", { id: "offset-problem", class: "field-error",
      role: "alert" });
    this.snapInput = element("input", { type: "checkbox", checked: true,
      "aria-label": "Snap to grid" });
    this.typedStart = element("input", { type: "text", placeholder: "x, y or x, y, yaw",
      "aria-label": "Start x, y[, yaw] (m, rad)" });
    this.typedGoal = element("input", { type: "text", placeholder: "gx, gy (empty: no goal)",
      "aria-label": "Goal gx, gy (m)" });
    this.gridInput = element("input", { type: "number", value: "0.5", step: "0.1", min: "0.01",
      "aria-label": "Grid (m)", onchange: () => this.view.invalidate() });
    this.timeInput = number("Time limit (s)", "60", "1");
    this.toleranceInput = number("Goal tolerance (m)", "0.2", "0.05");
    this.deadlockInput = number("Deadlock window (s)", "10", "1");
    this.nameInput = element("input", { type: "text", value: "scenario",
      "aria-label": "Scenario name" });
    this.pathInput = element("input", { type: "text", value: "scenarios/scenario.toml",
      "aria-label": "Save scenario as" });
    this.algorithmSelect = element("select", { "aria-label": "Algorithm" });
    this.seedInput = number("Seed", "0");
    this.progress = element("progress", { max: "1", value: "0", "aria-label": "Run progress" });
    this.hint = element("p", { class: "hint" }, HINTS[this.tool]);
    this.info = element("span", {});
    const side = element("div", { class: "side" },
      element("h2", {}, "Scenarios"), this.fileListNode,
      element("div", { class: "row" }, this.builtinSelect,
        element("button", { type: "button", onclick: () => openBuiltin(this) },
          "Open built-in")),
      element("h2", {}, "Map"), this.mapSelect,
      element("h2", {}, "Robot type and sensors"), this.typeSelect,
      element("div", { class: "row" }, element("label", {}, "beams ", this.beamsInput),
        element("label", {}, "range ", this.rangeInput)),
      element("label", {}, "range noise sigma (m) ", this.noiseInput),
      element("h2", {}, "Place robots"), element("div", { class: "row" }, ...this.toolButtons),
      this.hint,
      element("div", { class: "row" }, element("label", {}, "count ", this.countInput),
        element("label", {}, "spacing ", this.spacingInput)),
      element("div", { class: "row" }, element("label", {}, "rows ", this.rowsInput),
        element("label", {}, "columns ", this.columnsInput)),
      element("label", {}, "goal offset dx, dy (m) ", this.offsetInput), this.offsetProblem,
      element("div", { class: "row" }, element("label", {}, this.snapInput, " snap"),
        element("label", {}, "grid ", this.gridInput, " m")),
      element("label", {}, "typed start ", this.typedStart),
      element("label", {}, "typed goal ", this.typedGoal),
      element("button", { type: "button", onclick: () => this.addTyped() }, "Add robot"),
      element("button", { type: "button", onclick: () => this.clearRobots() }, "Remove all"),
      element("h2", {}, "Settings"),
      element("label", {}, "time limit (s) ", this.timeInput),
      element("label", {}, "goal tolerance (m) ", this.toleranceInput),
      element("label", {}, "deadlock after (s) without moving ", this.deadlockInput),
      element("h2", {}, "Save"), element("label", {}, "name ", this.nameInput),
      element("label", {}, "file ", this.pathInput),
      element("button", { type: "button", class: "primary", onclick: () => this.save() },
        "Save scenario"),
      element("h2", {}, "Run"), element("label", {}, "algorithm ", this.algorithmSelect),
      element("label", {}, "seed ", this.seedInput),
      element("button", { type: "button", onclick: () => this.run() }, "Run"),
      element("button", { type: "button", onclick: () => this.runLive() }, "Run live"),
      this.progress);
    this.canvas = element("canvas", { "aria-label": "Scenario canvas" });
    this.root.replaceChildren(side, element("div", { class: "stage" },
      element("div", { class: "canvas-box" }, this.canvas),
      element("div", { class: "statusbar" }, this.info)));
    this.view = new WorldView(this.canvas, (c, view) => this.paint(c, view));
    this.view.drawStatic = (c, view) => {
      if (!this.map) return;
      if (this.snapInput.checked && Number(this.gridInput.value) > 0) {
        view.drawGrid(Number(this.gridInput.value));
      }
      view.drawSegments(this.map.segments);
    };
    this.snapInput.addEventListener("change", () => this.view.invalidate());
    this.canvas.addEventListener("pointerdown", (e) => this.pointerDown(e));
    for (const input of [this.nameInput, this.timeInput, this.toleranceInput,
      this.deadlockInput]) input.addEventListener("input", () => { this.dirty = true; });
  }

  async refresh() {
    const [scenarios, maps, algorithms] = await Promise.all([
      guarded(() => api.get("/api/scenarios")), guarded(() => api.get("/api/maps")),
      guarded(() => api.get("/api/algorithms"))]);
    if (!scenarios || !maps || !algorithms) return;
    this.files = scenarios.files;
    fileList(this.fileListNode, this.files, (p) => this.open(p));
    this.robotTypes = { ...this.robotTypes, ...scenarios.robot_types };
    const chosenBuiltin = this.builtinSelect.value;
    this.builtinSelect.replaceChildren(...scenarios.builtin.map((b) => element("option",
      { value: b.name, title: b.description }, b.name)));
    if (chosenBuiltin) this.builtinSelect.value = chosenBuiltin;
    const current = this.mapSelect.value;
    const mapNames = [...maps.files.map((f) => f.path), ...maps.builtin];
    this.mapSelect.replaceChildren(element("option", { value: "" }, "(choose a map)"),
      ...mapNames.map((p) => element("option", { value: p }, p)));
    this.mapSelect.value = mapNames.includes(current) ? current : "";
    showInlineMap(this);
    if (!this.typeSelect.options.length) {
      this.typeSelect.replaceChildren(...Object.keys(this.robotTypes).map((name) =>
        element("option", { value: name }, name)));
      this.typeSelect.value = "Pioneer2DX";
      this.showType();
    }
    const names = [...algorithms.builtin.map((a) => a.name), ...algorithms.files];
    const chosen = this.algorithmSelect.value || "go_to_goal";
    this.algorithmSelect.replaceChildren(...names.map((n) => element("option", { value: n }, n)));
    this.algorithmSelect.value = names.includes(chosen) ? chosen : names[0];
  }

  showType() {
    const type = this.robotTypes[this.typeSelect.value];
    if (!type) return;
    this.beamsInput.value = String(type.ranger.beams);
    this.rangeInput.value = String(type.ranger.range);
    this.noiseInput.value = String(type.ranger.sigma);
  }

  // The type name new robots get: the built-in, or a custom type when the sensors differ.
  currentType() {
    const base = this.typeSelect.value;
    const ranger = this.robotTypes[base].ranger;
    const wanted = { beams: Math.round(Number(this.beamsInput.value)),
      range: Number(this.rangeInput.value), sigma: Number(this.noiseInput.value) };
    if (wanted.beams === ranger.beams && wanted.range === ranger.range
        && wanted.sigma === ranger.sigma) return base;
    const name = `${base}_b${wanted.beams}_r${wanted.range}_n${wanted.sigma}`.replace(/\./g, "p");
    this.types[name] = { base, ranger: wanted };
    return name;
  }

  sizeOf(typeName) {
    const type = this.robotTypes[typeName] || this.robotTypes[this.types[typeName]?.base]
      || { length: 0.3, width: 0.3 };
    return [type.length / 2, type.width / 2];
  }

  async pickMap() {
    const path = this.mapSelect.value;
    if (!path || path === INLINE) return;
    this.inlineMap = null;
    const data = await guarded(() => api.get("/api/maps/file", { path }));
    if (!data) return;
    if (this.mapRef !== path) this.dirty = true;
    this.mapRef = path;
    this.map = data;
    this.view.fit(data.bounds);
    this.view.invalidate();
    this.showInfo();
  }

  async open(path) {
    if (!mayDiscard(this, "this scenario")) return;
    const data = await guarded(() => api.get("/api/scenarios/file", { path }));
    if (!data) return;
    showScenario(this, data, path);
    this.dirty = false;
    this.ownPath = path;
    say(`opened ${path}: ${this.robots.length} robots`);
  }

  setTool(name) {
    this.tool = name;
    this.points = [];
    this.hint.textContent = HINTS[name];
    this.toolButtons.forEach((b) => b.setAttribute("aria-pressed", String(b.textContent === name)));
  }

  // The goal offset: [dx, dy], null for "no goals" (0, 0), or undefined when the text is not
  // two numbers "dx, dy" (then the field says so and nothing is placed).
  offset() {
    const numbers = parseNumbers(this.offsetInput.value, 2);
    if (!numbers) return undefined;
    const [dx, dy] = numbers;
    return dx || dy ? [dx, dy] : null;
  }

  checkOffset() {
    const bad = this.offset() === undefined;
    this.offsetProblem.textContent = bad
      ? "Type two numbers separated by a comma, such as 5, 0 (0, 0: robots without goals)." : "";
    if (bad) this.offsetInput.setAttribute("aria-invalid", "true");
    else this.offsetInput.removeAttribute("aria-invalid");
    return !bad;
  }

  snap([x, y]) {
    const step = Number(this.gridInput.value);
    if (!this.snapInput.checked || !(step > 0)) return [x, y];
    const round = (v) => Math.round(Math.round(v / step) * step * 1e9) / 1e9;
    return [round(x), round(y)];
  }

  // Why a goal at (x, y) cannot be reached by a robot of type typeName, or "" when it can:
  // off the map's bounds, or closer to a wall than the robot's half width.
  goalProblem(x, y, typeName) {
    const [xmin, ymin, xmax, ymax] = this.map.bounds;
    const at = `goal (${x.toFixed(2)}, ${y.toFixed(2)})`;
    if (x < xmin || x > xmax || y < ymin || y > ymax) {
      return `${at} is off the map (${xmin} to ${xmax}, ${ymin} to ${ymax}): not placed`;
    }
    const [, halfWidth] = this.sizeOf(typeName);
    for (const [x1, y1, x2, y2] of this.map.segments) {
      const dx = x2 - x1;
      const dy = y2 - y1;
      const t = Math.max(0, Math.min(1, ((x - x1) * dx + (y - y1) * dy) / (dx * dx + dy * dy || 1)));
      if (Math.hypot(x - x1 - t * dx, y - y1 - t * dy) < halfWidth) {
        return `${at} is in a wall (a robot there would touch it): not placed`;
      }
    }
    return "";
  }

  add(starts) {
    const offset = this.offset();
    if (offset === undefined) {
      this.checkOffset();
      say("goal offset: not two numbers", true);
      return;
    }
    const type = this.currentType();
    const yaw = offset ? Math.atan2(offset[1], offset[0]) : 0;
    if (offset) {
      const problems = starts.map(([x, y]) =>
        this.goalProblem(x + offset[0], y + offset[1], type)).filter(Boolean);
      if (problems.length) {
        say(problems.length === 1 ? problems[0]
          : `${problems[0]} (and ${problems.length - 1} more goals): no robot placed`, true);
        return;
      }
    }
    for (const [x, y, heading] of starts) {
      this.robots.push({ type, x, y, yaw: heading ?? yaw,
        goal: offset ? [x + offset[0], y + offset[1]] : null });
    }
    this.changed();
  }

  robotAt(x, y) { return robotAt(this, x, y); }

  pointerDown(event) { return placeAt(this, event); }

  async random(region) {
    const type = this.currentType();
    const base = this.types[type]?.base || type;
    const data = await guarded(() => api.post("/api/scenarios/place", {
      map: this.inlineMap || this.mapRef, type: base, count: Math.round(Number(this.countInput.value)), region,
      min_spacing: Number(this.spacingInput.value) || null,
      seed: Math.floor(Math.random() * 1e9), others: this.robots.map((r) => [r.x, r.y]) }));
    if (data) this.add(data.poses);
  }

  drag(event, x, y) { dragRobot(this, event, x, y); }

  // A robot at a typed start (and goal), as exact as typed: no snapping.
  addTyped() {
    if (!this.map) { say("choose a map first", true); return; }
    const start = parseNumbers(this.typedStart.value, 2, 3);
    if (!start) { say("typed start: expected x, y or x, y, yaw (numbers)", true); return; }
    const goalText = this.typedGoal.value.trim();
    const goal = goalText ? parseNumbers(goalText, 2) : null;
    if (goal === undefined) {
      say("typed goal: expected gx, gy (numbers), or nothing", true);
      return;
    }
    const type = this.currentType();
    const problem = goal ? this.goalProblem(goal[0], goal[1], type) : "";
    if (problem) { say(problem, true); return; }
    const [x, y, yaw] = start;
    this.robots.push({ type, x, y, goal,
      yaw: yaw ?? (goal ? Math.atan2(goal[1] - y, goal[0] - x) : 0) });
    this.changed();
  }

  clearRobots() { this.robots = []; this.changed(); }

  changed() {
    this.dirty = true;
    this.fault = { robots: [], walls: [] };
    clearError();
    this.showInfo();
  }

  paint(c, view) { paintScenario(this, c, view); }

  showInfo() {
    const mapName = this.mapRef || (this.inlineMap ? this.inlineMap.name : "no map");
    this.info.textContent = `${this.robots.length} robots on ${mapName}`;
    this.view.redraw();
  }

  body() {
    const used = new Set(this.robots.map((r) => r.type));
    const types = Object.fromEntries(Object.entries(this.types).filter(([k]) => used.has(k)));
    return { path: this.pathInput.value.trim(), name: this.nameInput.value.trim() || "scenario",
      map: this.inlineMap || this.mapRef, robots: this.robots, types,
      settings: { time_limit: Number(this.timeInput.value),
        goal_tolerance: Number(this.toleranceInput.value),
        deadlock_window: Number(this.deadlockInput.value) } };
  }

  async save() {
    if (!this.mapRef && !this.inlineMap) { say("choose a map first", true); return undefined; }
    const data = await saveFile("/api/scenarios/file", this.body(), this.ownPath,
      this.files);
    this.fault = data ? { robots: [], walls: [] } : faultOf(shownError(), this.robots.length);
    this.view.redraw();
    if (data) {
      this.dirty = false;
      this.ownPath = data.path;
      say(`saved ${data.path}: ${data.robots} robots`);
      this.refresh();
    }
    return data;
  }

  async runLive() { // save, then start a live run of the file and open its page (#/live/ID)
    const saved = await this.save();
    if (saved) {
      await startLive({ scenario: saved.path, algorithm: this.algorithmSelect.value,
        seed: Math.round(Number(this.seedInput.value)) });
    }
  }

  async run() {
    const saved = await this.save();
    if (!saved) return;
    const job = await guarded(() => api.post("/api/scenarios/run", { path: saved.path,
      algorithm: this.algorithmSelect.value, seed: Math.round(Number(this.seedInput.value)) }));
    if (!job) return;
    say(`running ${saved.path} with ${this.algorithmSelect.value}...`);
    const end = await guarded(() => waitJob(job.id, (j) => {
      this.progress.max = j.total || 1;
      this.progress.value = j.done;
    }));
    if (!end) return;
    if (end.state !== "done") { say(`run failed: ${end.error}`, true); return; }
    // an error names the file and line of the user's code (its first line; the run's page
    // shows the source line too)
    const error = end.result.error ? `: ${end.result.error.split("\n")[0]}` : "";
    say(`run finished (${end.result.status}): ${end.result.run}${error}`, Boolean(error));
    window.location.hash = `#/runs?path=${encodeURIComponent(end.result.run)}`;
  }
}
