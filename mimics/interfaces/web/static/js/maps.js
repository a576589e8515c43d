// The Maps page: list/open/create maps, draw and edit walls, import, save.
import {
  api, clearError, element, fileList, guarded, mayDiscard, parseNumbers, saveFile, say,
} from "./api.js";
import { WorldView } from "./view.js";

const TOOLS = ["Select", "Segment", "Polyline", "Rectangle"];
const PICK_PX = 8; // how close (pixels) a click must be to grab a vertex or a wall

export class MapEditor {
  constructor(root) {
    this.root = root;
    this.segments = [];
    this.bounds = [0, 0, 10, 10];
    this.name = "map";
    this.tool = "Segment";
    this.points = []; // clicks of the shape being drawn
    this.cursor = null;
    this.selected = -1;
    this.undoStack = [];
    this.redoStack = [];
    this.dirty = false; // edits not saved yet (asked about before they are dropped)
    this.ownPath = null; // the workspace file opened or last saved: saved over without asking
    this.build();
  }

  build() {
    const tools = TOOLS.map((name) => element("button", {
      type: "button", "aria-pressed": String(name === this.tool),
      onclick: () => this.setTool(name) }, name));
    this.toolButtons = tools;
    this.fileListNode = element("ul", { class: "files", "aria-label": "Map files" });
    this.builtinNode = element("ul", { class: "files", "aria-label": "Built-in maps" });
    this.nameInput = element("input", { type: "text", "aria-label": "Map name", value: "map" });
    this.pathInput = element("input", { type: "text", "aria-label": "Save as",
      value: "maps/map.txt" });
    this.snapInput = element("input", { type: "checkbox", checked: true,
      "aria-label": "Snap to grid" });
    this.gridInput = element("input", { type: "number", value: "0.5", step: "0.1", min: "0.01",
      "aria-label": "Grid (m)" });
    this.boundInputs = ["xmin", "ymin", "xmax", "ymax"].map((label, k) =>
      element("input", { type: "number", step: "0.5", value: String(this.bounds[k]),
        "aria-label": label, onchange: () => this.setBounds() }));
    this.importFile = element("input", { type: "file", "aria-label": "File to import",
      accept: ".svg,.png,.pgm,.bmp,.yaml,.yml,.txt,.map,.segments,.toml,.json" });
    this.resolutionInput = element("input", { type: "number", step: "0.01", value: "0.05",
      "aria-label": "Resolution (m/px)" });
    this.scaleInput = element("input", { type: "number", step: "0.001", value: "",
      "aria-label": "SVG scale (m/unit)" });
    this.originInput = element("input", { type: "text", value: "0, 0",
      "aria-label": "Origin x, y (m)" });
    this.typedWall = element("input", { type: "text", placeholder: "x1, y1, x2, y2",
      "aria-label": "Wall x1, y1, x2, y2 (m)" });
    this.info = element("span", { "aria-label": "Wall count" });
    this.coords = element("span", {});
    const side = element("div", { class: "side" },
      element("h2", {}, "Maps"), this.fileListNode,
      element("h2", {}, "Built-in"), this.builtinNode,
      element("h2", {}, "New"),
      element("div", { class: "row" }, ...this.boundInputs),
      element("button", { type: "button", onclick: () => this.newMap() }, "New map"),
      element("h2", {}, "Draw"),
      element("div", { class: "row" }, ...tools),
      element("div", { class: "row" },
        element("button", { type: "button", onclick: () => this.undo() }, "Undo"),
        element("button", { type: "button", onclick: () => this.redo() }, "Redo"),
        element("button", { type: "button", onclick: () => this.deleteSelected() }, "Delete")),
      element("div", { class: "row" }, element("label", {}, this.snapInput, " snap"),
        element("label", {}, "grid ", this.gridInput, " m")),
      element("p", { class: "hint" }, "Click to place points; a polyline ends with a "
        + "double-click or Enter; Esc cancels. Wheel zooms, right-drag pans."),
      element("label", {}, "typed wall ", this.typedWall),
      element("button", { type: "button", onclick: () => this.addTyped() }, "Add wall"),
      element("h2", {}, "Import"), this.importFile,
      element("p", { class: "hint" }, "A ROS map_server YAML is read from the workspace's "
        + "maps/ folder, beside the image it names."),
      element("label", {}, "image resolution (m/px) ", this.resolutionInput),
      element("label", {}, "image origin (m) ", this.originInput),
      element("label", {}, "SVG scale (m/unit) ", this.scaleInput),
      element("button", { type: "button", onclick: () => this.importMap() }, "Import"),
      element("h2", {}, "Save"),
      element("label", {}, "name ", this.nameInput),
      element("label", {}, "file ", this.pathInput),
      element("button", { type: "button", class: "primary", onclick: () => this.save() },
        "Save map"));
    this.canvas = element("canvas", { "aria-label": "Map canvas", tabindex: "0" });
    const stage = element("div", { class: "stage" },
      element("div", { class: "canvas-box" }, this.canvas),
      element("div", { class: "statusbar" }, this.info, this.coords));
    this.root.replaceChildren(side, stage);
    this.view = new WorldView(this.canvas, (c, view) => this.paint(c, view));
    this.view.drawStatic = (c, view) => this.paintWalls(c, view);
    this.gridInput.addEventListener("change", () => this.view.invalidate());
    this.canvas.addEventListener("pointerdown", (e) => this.pointerDown(e));
    this.canvas.addEventListener("pointermove", (e) => this.pointerMove(e));
    this.canvas.addEventListener("dblclick", () => this.finishPolyline());
    this.canvas.addEventListener("keydown", (e) => this.key(e));
    this.showInfo();
  }

  async refresh() {
    const data = await guarded(() => api.get("/api/maps"));
    if (!data) return;
    this.files = data.files.map((f) => f.path);
    fileList(this.fileListNode, this.files, (p) => this.open(p));
    fileList(this.builtinNode, data.builtin, (p) => this.open(p));
  }

  async open(path) {
    if (!mayDiscard(this, "this map")) return;
    const data = await guarded(() => api.get("/api/maps/file", { path }));
    if (!data) return;
    this.load(data);
    this.ownPath = path.startsWith("maps/") ? path : null;
    const stem = path.startsWith("stage:") ? path.slice(6) : path.split("/").pop()
      .replace(/\.[^.]+$/, "");
    this.pathInput.value = path.startsWith("maps/") && /\.(txt|map|segments|toml|json)$/
      .test(path) ? path : `maps/${stem}.txt`;
    say(`opened ${path}: ${data.walls} walls`);
  }

  load(data) {
    this.segments = data.segments.map((s) => s.slice());
    this.bounds = data.bounds.slice();
    this.name = data.name;
    this.nameInput.value = data.name;
    this.boundInputs.forEach((input, k) => { input.value = String(this.bounds[k]); });
    this.undoStack = [];
    this.redoStack = [];
    this.selected = -1;
    this.points = [];
    this.view.fit(this.bounds);
    this.dirty = false;
    this.showInfo();
  }

  newMap() {
    if (!mayDiscard(this, "this map")) return;
    const bounds = this.boundInputs.map((input) => Number(input.value));
    if (!(bounds[0] < bounds[2] && bounds[1] < bounds[3])) {
      say("bounds: expected xmin < xmax and ymin < ymax", true);
      return;
    }
    this.load({ segments: [], bounds, name: "map" });
    this.ownPath = null;
    this.pathInput.value = "maps/map.txt";
    say("new map: draw its walls");
  }

  setBounds() {
    const bounds = this.boundInputs.map((input) => Number(input.value));
    if (bounds[0] < bounds[2] && bounds[1] < bounds[3]) {
      this.bounds = bounds;
      this.dirty = true;
      this.view.bounds = bounds;
      this.view.invalidate();
    }
  }

  setTool(name) {
    this.tool = name;
    this.points = [];
    this.toolButtons.forEach((b) => b.setAttribute("aria-pressed", String(b.textContent === name)));
    this.view.redraw();
  }

  snap([x, y]) {
    const step = Number(this.gridInput.value);
    if (!this.snapInput.checked || !(step > 0)) return [x, y];
    // Round to the grid, then to 1e-9 m, so that 0.1-grids give short decimal numbers.
    const round = (v) => Math.round(Math.round(v / step) * step * 1e9) / 1e9;
    return [round(x), round(y)];
  }

  remember() {
    this.dirty = true;
    clearError();
    this.undoStack.push(JSON.stringify(this.segments));
    if (this.undoStack.length > 200) this.undoStack.shift();
    this.redoStack = [];
  }

  undo() {
    if (!this.undoStack.length) return;
    this.redoStack.push(JSON.stringify(this.segments));
    this.segments = JSON.parse(this.undoStack.pop());
    this.selected = -1;
    this.showInfo();
  }

  redo() {
    if (!this.redoStack.length) return;
    this.undoStack.push(JSON.stringify(this.segments));
    this.segments = JSON.parse(this.redoStack.pop());
    this.showInfo();
  }

  addSegments(list) {
    const fresh = list.filter(([a, b, c, d]) => a !== c || b !== d);
    if (!fresh.length) return;
    this.remember();
    this.segments.push(...fresh);
    this.showInfo();
  }

  // A wall from typed numbers, as exact as typed (no snapping).
  addTyped() {
    const wall = parseNumbers(this.typedWall.value, 4);
    if (!wall) { say("typed wall: expected x1, y1, x2, y2 (four numbers)", true); return; }
    if (wall[0] === wall[2] && wall[1] === wall[3]) {
      say("typed wall: its two ends are the same point", true);
      return;
    }
    this.addSegments([wall]);
  }

  deleteSelected() {
    if (this.selected < 0) return;
    this.remember();
    this.segments.splice(this.selected, 1);
    this.selected = -1;
    this.showInfo();
  }

  pointerDown(event) {
    if (event.button !== 0 || event.shiftKey) return;
    this.canvas.focus();
    const point = this.snap(this.view.eventWorld(event));
    if (this.tool === "Select") { this.grab(event); return; }
    this.points.push(point);
    if (this.tool === "Segment" && this.points.length === 2) {
      const [[x1, y1], [x2, y2]] = this.points;
      this.addSegments([[x1, y1, x2, y2]]);
      this.points = [];
    } else if (this.tool === "Rectangle" && this.points.length === 2) {
      const [[x1, y1], [x2, y2]] = this.points;
      if (x1 !== x2 && y1 !== y2) {
        this.addSegments([[x1, y1, x2, y1], [x2, y1, x2, y2], [x2, y2, x1, y2], [x1, y2, x1, y1]]);
      }
      this.points = [];
    } else if (this.tool === "Polyline" && this.points.length >= 2) {
      const [[x1, y1], [x2, y2]] = this.points.slice(-2);
      if (x1 === x2 && y1 === y2) { this.points.pop(); this.finishPolyline(); return; }
      this.addSegments([[x1, y1, x2, y2]]);
    }
    this.view.redraw();
  }

  finishPolyline() {
    this.points = [];
    this.view.redraw();
  }

  // Select the wall under the pointer, or drag the vertex under it (with every wall end there).
  grab(event) {
    const [px, py] = [event.offsetX, event.offsetY];
    let best = -1;
    let bestEnd = null;
    let bestDistance = PICK_PX;
    this.segments.forEach(([x1, y1, x2, y2], k) => {
      const [ax, ay] = this.view.toScreen(x1, y1);
      const [bx, by] = this.view.toScreen(x2, y2);
      for (const [end, ex, ey] of [[0, ax, ay], [1, bx, by]]) {
        const d = Math.hypot(px - ex, py - ey);
        if (d < bestDistance) { bestDistance = d; best = k; bestEnd = end; }
      }
      const dx = bx - ax;
      const dy = by - ay;
      const t = Math.max(0, Math.min(1, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy || 1)));
      const d = Math.hypot(px - ax - t * dx, py - ay - t * dy);
      if (d < bestDistance - 2 && bestEnd === null) { bestDistance = d; best = k; }
    });
    this.selected = best;
    this.view.redraw();
    if (best < 0 || bestEnd === null) return;
    const seg = this.segments[best];
    const [vx, vy] = bestEnd === 0 ? [seg[0], seg[1]] : [seg[2], seg[3]];
    const ends = [];
    this.segments.forEach((s, k) => {
      if (s[0] === vx && s[1] === vy) ends.push([k, 0]);
      if (s[2] === vx && s[3] === vy) ends.push([k, 2]);
    });
    this.remember();
    const move = (e) => {
      const box = this.canvas.getBoundingClientRect();
      const [x, y] = this.snap(this.view.toWorld(e.clientX - box.left, e.clientY - box.top));
      for (const [k, at] of ends) { this.segments[k][at] = x; this.segments[k][at + 1] = y; }
      this.view.invalidate();
    };
    const up = () => {
      window.removeEventListener("pointermove", move);
      window.removeEventListener("pointerup", up);
      this.showInfo();
    };
    window.addEventListener("pointermove", move);
    window.addEventListener("pointerup", up);
  }

  pointerMove(event) {
    this.cursor = this.snap(this.view.eventWorld(event));
    this.coords.textContent = `x ${this.cursor[0].toFixed(2)} m, y ${this.cursor[1].toFixed(2)} m`;
    if (this.points.length) this.view.redraw();
  }

  key(event) {
    if (event.key === "Escape") { this.points = []; this.view.redraw(); }
    if (event.key === "Enter") this.finishPolyline();
    if (event.key === "Delete" || event.key === "Backspace") this.deleteSelected();
    if ((event.ctrlKey || event.metaKey) && event.key === "z") this.undo();
    if ((event.ctrlKey || event.metaKey) && event.key === "y") this.redo();
  }

  // The walls, their grid and vertices: the view's cached layer (redrawn on a change only),
  // so that drawing over the Hospital's thousands of walls stays fluid.
  paintWalls(c, view) {
    view.drawGrid(Number(this.gridInput.value) || 1);
    view.drawSegments(this.segments);
    if (this.segments.length < 5000) {
      c.fillStyle = "#1f6feb";
      for (const [x1, y1, x2, y2] of this.segments) {
        for (const [x, y] of [[x1, y1], [x2, y2]]) {
          const [px, py] = view.toScreen(x, y);
          c.fillRect(px - 2, py - 2, 4, 4);
        }
      }
    }
  }

  paint(c, view) {
    if (this.selected >= 0 && this.segments[this.selected]) {
      view.drawSegments([this.segments[this.selected]], "#1f6feb", 4);
    }
    if (this.points.length && this.cursor) {
      const last = this.points[this.points.length - 1];
      let preview = [[...last, ...this.cursor]];
      if (this.tool === "Rectangle") {
        const [x1, y1] = last;
        const [x2, y2] = this.cursor;
        preview = [[x1, y1, x2, y1], [x2, y1, x2, y2], [x2, y2, x1, y2], [x1, y2, x1, y1]];
      }
      view.drawSegments(preview, "#1f6feb", 1);
    }
  }

  showInfo() {
    this.info.textContent = `${this.segments.length} walls`;
    this.view.invalidate();
  }

  async importMap() {
    const file = this.importFile.files[0];
    if (!file) { say("choose a file to import first", true); return; }
    if (!mayDiscard(this, "this map")) return;
    const options = {};
    const lower = file.name.toLowerCase();
    if (/\.(png|pgm|bmp)$/.test(lower)) {
      options.resolution = Number(this.resolutionInput.value);
      options.origin = this.originInput.value.split(",").map(Number);
    }
    if (lower.endsWith(".svg") && this.scaleInput.value) {
      options.scale = Number(this.scaleInput.value);
    }
    // A ROS map YAML names its image: both are read from the workspace's maps/ folder.
    const fromWorkspace = /\.ya?ml$/.test(lower);
    const data = await guarded(() => (fromWorkspace
      ? api.post("/api/maps/import-file", undefined,
        { path: `maps/${file.name}`, options: JSON.stringify(options) })
      : api.post("/api/maps/import", file,
        { filename: file.name, options: JSON.stringify(options) })));
    if (!data) return;
    this.load(data);
    this.dirty = true; // imported, not saved
    this.ownPath = null;
    this.pathInput.value = `maps/${file.name.replace(/\.[^.]+$/, "")}.txt`;
    say(`imported ${file.name}: ${data.walls} walls (not saved yet)`);
  }

  async save() {
    const body = { path: this.pathInput.value.trim(), name: this.nameInput.value.trim() || "map",
      bounds: this.bounds, segments: this.segments };
    const data = await saveFile("/api/maps/file", body, this.ownPath, this.files);
    if (!data) return;
    this.dirty = false;
    this.ownPath = data.path;
    say(`saved ${data.path}: ${data.walls} walls`);
    this.refresh();
  }
}
