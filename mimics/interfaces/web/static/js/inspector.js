// The inspector: one robot's id, type, state, pose, velocity, references and distance to its
// goal at the current time, its log lines up to that time, and the beams toggle. The Runs
// page (a replay) and the live page use it through one small interface:
//
//   const inspector = createInspector(panelElement, source);
//   inspector.select(i);   // show robot i (-1: none); the page calls it on a click
//   inspector.update();    // the time moved (or the robot did): read the source again;
//                          // cheap, so call it on every frame drawn
//   inspector.selected;    // the robot shown, -1 for none
//   inspector.allBeams;    // true while "every robot's beams" is ticked
//
// The page gives `source`, an object with:
//   robotAt(i)  -> { id, type, state, time, x, y, yaw, v, w, vRef, headingRef, goal }
//                  robot i at the current time: state a name ("active", "reached_goal",
//                  "collided", "escaped", "deadlock", "error", "removed", "livelock"), time in s,
//                  pose in m and rad, v (m/s), w (rad/s), vRef (m/s) and headingRef (rad)
//                  null when not known, goal [x, y] or null (no goal)
//   logLines(i, time) -> Promise of { lines: [string], skipped: number }   (optional)
//                  robot i's log lines up to `time`, and how many earlier ones were left out
//   beamsChanged(allBeams)   (optional) the toggle changed: the page fetches and draws beams
//
// nearestRobot(frame, count, x, y, within) finds the robot a click at world (x, y) means.
import { element } from "./api.js";

// A robot's state by its code in the frames (the engine's Status, 6 removed by an edit;
// 7: active, in a livelock): one list, in view.js
export { STATE_NAMES } from "./view.js";

// The fields shown, in order: [key, label, format of robotAt(i)].
const FIELDS = [
  ["id", "robot", (r) => String(r.id)],
  ["type", "type", (r) => r.type ?? "?"],
  ["state", "state", (r) => (r.state ?? "?").replace("_", " ")],
  ["time", "time", (r) => `${fixed(r.time, 2)} s`],
  ["x", "x", (r) => `${fixed(r.x, 3)} m`],
  ["y", "y", (r) => `${fixed(r.y, 3)} m`],
  ["yaw", "yaw", (r) => `${fixed(r.yaw, 3)} rad`],
  ["v", "speed v", (r) => `${fixed(r.v, 3)} m/s`],
  ["w", "turn rate w", (r) => `${fixed(r.w, 3)} rad/s`],
  ["v_ref", "speed reference", (r) => `${fixed(r.vRef, 3)} m/s`],
  ["heading_ref", "heading reference", (r) => `${fixed(r.headingRef, 3)} rad`],
  ["goal", "goal", (r) => (r.goal ? `${fixed(r.goal[0], 2)}, ${fixed(r.goal[1], 2)} m` : "none")],
  ["goal_distance", "distance to goal", (r) => (r.goal
    ? `${fixed(Math.hypot(r.goal[0] - r.x, r.goal[1] - r.y), 3)} m` : "no goal")],
];
const HINT = "Click a robot on the canvas to inspect it.";

function fixed(value, digits) {
  return value === null || value === undefined || Number.isNaN(value) ? "n/a"
    : Number(value).toFixed(digits);
}

export function createInspector(panel, source) {
  const values = {};
  const hint = element("p", { class: "hint" }, HINT);
  const table = element("dl", { class: "inspector-fields", hidden: true },
    ...FIELDS.flatMap(([key, label]) => {
      values[key] = element("dd", { "data-field": key });
      return [element("dt", {}, label), values[key]];
    }));
  const beamsBox = element("input", { type: "checkbox", "aria-label": "Every robot's beams",
    onchange: () => { if (source.beamsChanged) source.beamsChanged(beamsBox.checked); } });
  const logNote = element("p", { class: "hint" });
  const logBox = element("div", { class: "log", role: "log", "aria-label": "Robot log" });
  // a log row is wide (13 columns): scrolled sideways, or wrapped at will
  const wrapBox = element("input", { type: "checkbox", "aria-label": "Wrap log lines",
    onchange: () => {
      logBox.classList.toggle("wrapped", wrapBox.checked);
      logBox.scrollTop = logBox.scrollHeight;
    } });
  panel.replaceChildren(element("h2", {}, "Inspector"), hint, table,
    element("label", {}, beamsBox, " every robot's beams"),
    element("h2", {}, "Log up to now"), element("label", {}, wrapBox, " wrap lines"),
    logNote, logBox);

  const inspector = {
    selected: -1,
    get allBeams() { return beamsBox.checked; },
    select(i) {
      this.selected = i;
      loggedKey = null;
      logBox.textContent = "";
      logNote.textContent = "";
      hint.hidden = i >= 0;
      table.hidden = i < 0;
      this.update();
    },
    update() {
      if (this.selected < 0) return;
      const robot = source.robotAt(this.selected);
      for (const [key, , format] of FIELDS) {
        const text = format(robot);
        if (values[key].textContent !== text) values[key].textContent = text;
      }
      refreshLog(this.selected, robot.time);
    },
  };

  // The log follows the time: one request at a time, then one for the latest robot and time.
  let loggedKey = null;
  let fetching = false;
  async function refreshLog(robot, time) {
    const key = `${robot}@${time}`;
    if (!source.logLines || key === loggedKey || fetching) return;
    fetching = true;
    loggedKey = key;
    try {
      const log = await source.logLines(robot, time);
      if (log && key === loggedKey) {
        logNote.textContent = log.skipped ? `(${log.skipped} earlier lines not shown)` : "";
        logBox.textContent = log.lines.join("\n")
          || "(no lines yet: no per-robot log was written and the robot had no events)";
        logBox.scrollTop = logBox.scrollHeight; // the latest line in view
      }
    } finally {
      fetching = false;
    }
    const current = inspector.selected;
    if (current >= 0) refreshLog(current, source.robotAt(current).time);
  }

  return inspector;
}

// The robot whose centre is nearest world point (x, y) and within `within` metres of it, else
// -1; `frame` holds x, y, yaw of `count` robots.
export function nearestRobot(frame, count, x, y, within) {
  let best = -1;
  let bestDistance = within;
  for (let i = 0; i < count; i++) {
    const d = Math.hypot(frame[3 * i] - x, frame[3 * i + 1] - y);
    if (d < bestDistance) { bestDistance = d; best = i; }
  }
  return best;
}
