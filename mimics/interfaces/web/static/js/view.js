// A Canvas showing the world (metres, y up): fit, zoom with the wheel, pan with the
// right or middle button (or Shift+drag), redraw on the next animation frame.

export class WorldView {
  constructor(canvas, draw) {
    this.canvas = canvas;
    this.context = canvas.getContext("2d");
    this.draw = draw;
    this.scale = 40; // pixels per metre
    this.offsetX = 0; // screen x of world x = 0
    this.offsetY = 0; // screen y of world y = 0
    this.pending = false;
    this.bounds = [0, 0, 10, 10];
    // What does not move (bounds, walls) is drawn once into a layer, re-drawn only when
    // the view or the content changes (invalidate()), and copied into each frame.
    this.drawStatic = null;
    this.layer = document.createElement("canvas");
    this.layerKey = "";
    this.version = 0;
    new ResizeObserver(() => this.resize()).observe(canvas);
    canvas.addEventListener("wheel", (event) => this.zoom(event), { passive: false });
    canvas.addEventListener("contextmenu", (event) => event.preventDefault());
    canvas.addEventListener("pointerdown", (event) => this.panStart(event));
  }

  resize() {
    const ratio = window.devicePixelRatio || 1;
    const { clientWidth: width, clientHeight: height } = this.canvas;
    if (!width || !height) return;
    this.canvas.width = Math.round(width * ratio);
    this.canvas.height = Math.round(height * ratio);
    if (!this.fitted) this.fit(this.bounds);
    this.redraw();
  }

  fit(bounds) {
    this.bounds = bounds;
    const { clientWidth: width, clientHeight: height } = this.canvas;
    if (!width || !height) return;
    this.fitted = true;
    const [x0, y0, x1, y1] = bounds;
    this.scale = Math.min(width / (x1 - x0), height / (y1 - y0)) * 0.92;
    this.offsetX = width / 2 - ((x0 + x1) / 2) * this.scale;
    this.offsetY = height / 2 + ((y0 + y1) / 2) * this.scale;
    this.redraw();
  }

  toScreen(x, y) { return [this.offsetX + x * this.scale, this.offsetY - y * this.scale]; }

  toWorld(px, py) { return [(px - this.offsetX) / this.scale, (this.offsetY - py) / this.scale]; }

  eventWorld(event) {
    const box = this.canvas.getBoundingClientRect();
    return this.toWorld(event.clientX - box.left, event.clientY - box.top);
  }

  zoom(event) {
    event.preventDefault();
    const box = this.canvas.getBoundingClientRect();
    const px = event.clientX - box.left;
    const py = event.clientY - box.top;
    const [wx, wy] = this.toWorld(px, py);
    this.scale *= Math.exp(-event.deltaY * 0.0015);
    this.offsetX = px - wx * this.scale;
    this.offsetY = py + wy * this.scale;
    this.redraw();
  }

  panStart(event) {
    if (!(event.button === 1 || event.button === 2 || (event.button === 0 && event.shiftKey))) {
      return;
    }
    event.preventDefault();
    event.stopImmediatePropagation();
    const start = [event.clientX, event.clientY, this.offsetX, this.offsetY];
    const move = (e) => {
      this.offsetX = start[2] + e.clientX - start[0];
      this.offsetY = start[3] + e.clientY - start[1];
      this.redraw();
    };
    const up = () => {
      window.removeEventListener("pointermove", move);
      window.removeEventListener("pointerup", up);
    };
    window.addEventListener("pointermove", move);
    window.addEventListener("pointerup", up);
  }

  redraw() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      const c = this.context;
      c.setTransform(1, 0, 0, 1, 0, 0);
      c.clearRect(0, 0, this.canvas.width, this.canvas.height);
      c.drawImage(this.staticLayer(), 0, 0);
      const ratio = window.devicePixelRatio || 1;
      c.setTransform(ratio, 0, 0, ratio, 0, 0);
      this.draw(c, this);
    });
  }

  // The content changed: the static layer is drawn again at the next frame.
  invalidate() {
    this.version += 1;
    this.redraw();
  }

  staticLayer() {
    const key = [this.scale, this.offsetX, this.offsetY, this.canvas.width, this.canvas.height,
      this.version, ...this.bounds].join();
    if (key === this.layerKey) return this.layer;
    this.layerKey = key;
    this.layer.width = this.canvas.width;
    this.layer.height = this.canvas.height;
    const ratio = window.devicePixelRatio || 1;
    const main = this.context;
    this.context = this.layer.getContext("2d");
    this.context.setTransform(ratio, 0, 0, ratio, 0, 0);
    this.drawBounds();
    if (this.drawStatic) this.drawStatic(this.context, this);
    this.context = main;
    return this.layer;
  }

  drawBounds() {
    const c = this.context;
    const [x0, y0, x1, y1] = this.bounds;
    const [ax, ay] = this.toScreen(x0, y1);
    c.fillStyle = "#fbfbfd";
    c.strokeStyle = "#b8c0cc";
    c.setLineDash([4, 4]);
    c.fillRect(ax, ay, (x1 - x0) * this.scale, (y1 - y0) * this.scale);
    c.strokeRect(ax, ay, (x1 - x0) * this.scale, (y1 - y0) * this.scale);
    c.setLineDash([]);
  }

  // Draw wall segments [[x1, y1, x2, y2], ...] in one path.
  drawSegments(segments, color = "#222", width = 2) {
    const c = this.context;
    c.strokeStyle = color;
    c.lineWidth = width;
    c.lineCap = "round";
    c.beginPath();
    for (const [x1, y1, x2, y2] of segments) {
      const [ax, ay] = this.toScreen(x1, y1);
      const [bx, by] = this.toScreen(x2, y2);
      c.moveTo(ax, ay);
      c.lineTo(bx, by);
    }
    c.stroke();
  }

  // Laser beams ([x1, y1, x2, y2] each), as the replay and the live page draw them.
  drawBeams(segments) {
    this.drawSegments(segments, "rgba(214, 39, 40, 0.45)", 1);
  }

  // Draw the grid of spacing `step` metres (skipped when too dense).
  drawGrid(step) {
    if (step * this.scale < 6) return;
    const c = this.context;
    const [x0, y0, x1, y1] = this.bounds;
    c.strokeStyle = "#eceff3";
    c.lineWidth = 1;
    c.beginPath();
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
      const [ax, ay] = this.toScreen(x, y0);
      const [, by] = this.toScreen(x, y1);
      c.moveTo(ax, ay);
      c.lineTo(ax, by);
    }
    for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
      const [ax, ay] = this.toScreen(x0, y);
      const [bx] = this.toScreen(x1, y);
      c.moveTo(ax, ay);
      c.lineTo(bx, ay);
    }
    c.stroke();
  }
}

// Shapes in the robot's frame, in units of its half-length (x, ahead) and half-width (y,
// left): its body, and the heading's arrowhead from behind its centre to near its front.
const RECTANGLE = [[1, 1], [-1, 1], [-1, -1], [1, -1]];
const ARROW = [[0.9, 0], [-0.25, 0.6], [-0.25, -0.6]];

// Robot i's shape as a closed sub-path of the current path, in screen units (y down): no
// allocation per robot, so that thousands of robots draw fast.
function traceShape(c, view, poses, i, halfLength, halfWidth, shape) {
  const { scale, offsetX, offsetY } = view;
  const sx = offsetX + poses[3 * i] * scale;
  const sy = offsetY - poses[3 * i + 1] * scale;
  const t = poses[3 * i + 2];
  const cos = Math.cos(t) * scale;
  const sin = Math.sin(t) * scale;
  for (let k = 0; k < shape.length; k++) {
    const dx = shape[k][0] * halfLength[i];
    const dy = shape[k][1] * halfWidth[i];
    const px = sx + dx * cos - dy * sin;
    const py = sy - (dx * sin + dy * cos);
    if (k === 0) c.moveTo(px, py); else c.lineTo(px, py);
  }
  c.closePath();
}

// Robots as filled rectangles, one path per colour.
export function drawRobots(c, view, poses, halfLength, halfWidth, colorOf, count) {
  const groups = new Map();
  for (let i = 0; i < count; i++) {
    const color = colorOf(i);
    let group = groups.get(color);
    if (!group) { group = []; groups.set(color, group); }
    group.push(i);
  }
  for (const [color, robots] of groups) {
    c.fillStyle = color;
    c.beginPath();
    for (const i of robots) traceShape(c, view, poses, i, halfLength, halfWidth, RECTANGLE);
    c.fill();
  }
}

// What the replay and the live page draw over the robots, as the exported video does
// (interfaces/render.py): state names in code order (the frames' uint8 states), goals as
// grey crosses, headings as white lines, ids beside the robots, trails as blue lines.
export const STATE_NAMES = ["active", "reached_goal", "collided", "escaped", "deadlock", "error",
  "removed", "livelock"];
const GOAL_COLOR = "#7a7a7a";
const HEADING_COLOR = "#ffffff";
const MAX_IDS = 200; // robot ids are written when at most this many robots...
const ID_MIN_PX = 10; // ...and a robot is at least this many pixels long

// Goals [[x, y] or null, ...] as crosses.
export function drawGoals(c, view, goals) {
  const size = 4;
  c.strokeStyle = GOAL_COLOR;
  c.lineWidth = 1.5;
  c.beginPath();
  for (const goal of goals) {
    if (!goal) continue;
    const [px, py] = view.toScreen(goal[0], goal[1]);
    c.moveTo(px - size, py - size);
    c.lineTo(px + size, py + size);
    c.moveTo(px - size, py + size);
    c.lineTo(px + size, py - size);
  }
  c.stroke();
}

// Each robot's heading: a white arrowhead from behind its centre to near its front, filled
// (readable at the zoom that fits a whole map, where a line of a pixel or two read as a "U").
export function drawHeadings(c, view, frame, robots, halfLength, halfWidth) {
  c.fillStyle = HEADING_COLOR;
  c.beginPath();
  for (let i = 0; i < robots; i++) traceShape(c, view, frame, i, halfLength, halfWidth, ARROW);
  c.fill();
}

// Robot ids (0-based, as in the logs) beside the robots, when they fit.
export function drawIds(c, view, frame, robots, halfLength, halfWidth) {
  if (robots > MAX_IDS || 2 * Math.max(...halfLength) * view.scale < ID_MIN_PX) return;
  c.fillStyle = "#111";
  c.font = "11px system-ui, sans-serif";
  c.textBaseline = "bottom";
  for (let i = 0; i < robots; i++) {
    const [px, py] = view.toScreen(frame[3 * i], frame[3 * i + 1]);
    const r = Math.max(halfLength[i], halfWidth[i]) * view.scale;
    c.fillText(String(i), px + r, py - r);
  }
}

// Trails through earlier poses: `past` is a list of pose arrays (x, y, theta per robot),
// oldest first; each robot's line ends at its pose in `frame`. `jumps(i, j)`, if given, is
// true where robot i jumped between point j - 1 and point j (j = past.length: `frame`),
// moved by an edit: the line breaks there.
export function drawTrails(c, view, past, frame, robots, jumps = null) {
  if (!past.length) return;
  const { scale, offsetX, offsetY } = view;
  c.strokeStyle = "rgba(31, 119, 180, 0.35)";
  c.lineWidth = 1;
  c.beginPath();
  for (let i = 0; i < robots; i++) {
    past.forEach((poses, f) => {
      const px = offsetX + poses[3 * i] * scale;
      const py = offsetY - poses[3 * i + 1] * scale;
      if (f === 0 || (jumps && jumps(i, f))) c.moveTo(px, py); else c.lineTo(px, py);
    });
    const [px, py] = [offsetX + frame[3 * i] * scale, offsetY - frame[3 * i + 1] * scale];
    if (jumps && jumps(i, past.length)) c.moveTo(px, py); else c.lineTo(px, py);
  }
  c.stroke();
}
