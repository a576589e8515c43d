// The Scenarios page's canvas: placing robots by clicks, dragging starts and goals, drawing
// the robots, their goals and what a refused save named (split from scenarios.js).
import { say } from "./api.js";
import { drawRobots } from "./view.js";

// The robots and walls a refused save names ("robot 2 at ... and robot 3 ...", "touches
// wall 3 (0, 6)-(0, 0)"), to draw them in red.
export function faultOf(message, robotCount) {
  const robots = [...message.matchAll(/\brobot (\d+)/g)].map((m) => Number(m[1]))
    .filter((i) => i < robotCount);
  const number = "(-?[\\d.]+(?:e-?\\d+)?)";
  const wall = new RegExp(`wall \\d+ \\(${number}, ${number}\\)-\\(${number}, ${number}\\)`, "g");
  const walls = [...message.matchAll(wall)].map((m) => m.slice(1, 5).map(Number));
  return { robots: [...new Set(robots)], walls };
}

export function robotAt(editor, x, y) {
  let best = -1;
  let bestDistance = Infinity;
  editor.robots.forEach((r, k) => {
    const d = Math.hypot(r.x - x, r.y - y);
    if (d < bestDistance) { bestDistance = d; best = k; }
  });
  return bestDistance * editor.view.scale < 12 ? best : -1;
}

export async function placeAt(editor, event) {
  if (event.button !== 0 || event.shiftKey) return;
  if (!editor.map) { say("choose a map first", true); return; }
  const [x, y] = editor.view.eventWorld(event);
  if (editor.tool === "Move") { editor.drag(event, x, y); return; }
  if (editor.tool !== "Remove" && editor.tool !== "One" && !editor.checkOffset()) {
    say("goal offset: not two numbers", true);
    return;
  }
  if (editor.tool === "Remove") {
    const k = editor.robotAt(x, y);
    if (k >= 0) { editor.robots.splice(k, 1); editor.changed(); }
    return;
  }
  editor.points.push(editor.snap([x, y]));
  if (editor.tool === "One" && editor.points.length === 2) {
    const [[sx, sy], [gx, gy]] = editor.points;
    const problem = editor.goalProblem(gx, gy, editor.currentType());
    if (problem) { editor.points.pop(); say(problem, true); editor.view.redraw(); return; }
    editor.robots.push({ type: editor.currentType(), x: sx, y: sy,
      yaw: Math.atan2(gy - sy, gx - sx), goal: [gx, gy] });
    editor.points = [];
    editor.changed();
  } else if (editor.points.length === 2) {
    const [[x1, y1], [x2, y2]] = editor.points;
    editor.points = [];
    if (editor.tool === "Line") {
      const n = Math.max(1, Math.round(Number(editor.countInput.value)));
      editor.add(Array.from({ length: n }, (_, k) => {
        const t = n === 1 ? 0 : k / (n - 1);
        return [x1 + t * (x2 - x1), y1 + t * (y2 - y1)];
      }));
    } else if (editor.tool === "Grid") {
      const rows = Math.max(1, Math.round(Number(editor.rowsInput.value)));
      const columns = Math.max(1, Math.round(Number(editor.columnsInput.value)));
      const starts = [];
      for (let r = 0; r < rows; r++) {
        for (let c = 0; c < columns; c++) {
          starts.push([x1 + (columns === 1 ? 0 : (c / (columns - 1)) * (x2 - x1)),
            y1 + (rows === 1 ? 0 : (r / (rows - 1)) * (y2 - y1))]);
        }
      }
      editor.add(starts);
    } else if (editor.tool === "Random") {
      await editor.random([Math.min(x1, x2), Math.min(y1, y2), Math.max(x1, x2), Math.max(y1, y2)]);
    }
  }
  editor.view.redraw();
}

export function dragRobot(editor, event, x, y) {
  let target = null;
  let bestDistance = 12 / editor.view.scale;
  editor.robots.forEach((r, k) => {
    const ds = Math.hypot(r.x - x, r.y - y);
    if (ds < bestDistance) { bestDistance = ds; target = [k, "start"]; }
    if (r.goal) {
      const dg = Math.hypot(r.goal[0] - x, r.goal[1] - y);
      if (dg < bestDistance) { bestDistance = dg; target = [k, "goal"]; }
    }
  });
  if (!target) return;
  const robot = editor.robots[target[0]];
  const before = robot.goal ? robot.goal.slice() : null;
  const move = (e) => {
    const [wx, wy] = editor.snap(editor.view.eventWorld(e));
    if (target[1] === "start") { robot.x = wx; robot.y = wy; } else robot.goal = [wx, wy];
    editor.dirty = true;
    editor.view.redraw();
  };
  const up = () => {
    window.removeEventListener("pointermove", move);
    window.removeEventListener("pointerup", up);
    const problem = target[1] === "goal" ? editor.goalProblem(...robot.goal, robot.type) : "";
    if (problem) { robot.goal = before; say(problem, true); editor.view.redraw(); }
  };
  window.addEventListener("pointermove", move);
  window.addEventListener("pointerup", up);
}

export function paintScenario(editor, c, view) {
  if (!editor.map) return;
  const n = editor.robots.length;
  c.strokeStyle = "#9aa4b1";
  c.lineWidth = 1;
  c.beginPath();
  for (const r of editor.robots) {
    if (!r.goal) continue;
    const [ax, ay] = view.toScreen(r.x, r.y);
    const [bx, by] = view.toScreen(r.goal[0], r.goal[1]);
    c.moveTo(ax, ay);
    c.lineTo(bx, by);
    c.moveTo(bx + 4, by);
    c.arc(bx, by, 4, 0, 2 * Math.PI);
  }
  c.stroke();
  const poses = new Float32Array(3 * n);
  const halfLength = new Float32Array(n);
  const halfWidth = new Float32Array(n);
  editor.robots.forEach((r, k) => {
    poses.set([r.x, r.y, r.yaw], 3 * k);
    [halfLength[k], halfWidth[k]] = editor.sizeOf(r.type);
  });
  const faulty = new Set(editor.fault.robots);
  drawRobots(c, view, poses, halfLength, halfWidth,
    (i) => (faulty.has(i) ? "#c62828" : "#1f77b4"), n);
  if (editor.fault.walls.length) view.drawSegments(editor.fault.walls, "#c62828", 4);
  c.strokeStyle = "#c62828";
  c.lineWidth = 2;
  for (const i of faulty) {  // a ring, so that a small robot at fault is seen too
    const [px, py] = view.toScreen(editor.robots[i].x, editor.robots[i].y);
    c.beginPath();
    c.arc(px, py, Math.max(10, halfLength[i] * view.scale * 1.8), 0, 2 * Math.PI);
    c.stroke();
  }
  if (editor.points.length) {
    const [px, py] = view.toScreen(...editor.points[0]);
    c.fillStyle = "#d62728";
    c.fillRect(px - 3, py - 3, 6, 6);
  }
}
