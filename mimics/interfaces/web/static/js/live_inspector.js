// The inspector's source on the live page (interface in inspector.js): a robot's values now,
// from the latest frame (pose, state, time), the meta (goal) and the worker's answer for that
// robot (/api/live/ID/robot: type, v, w, references, its events so far as log lines); and
// the beams of its last scan, or every robot's (/api/live/ID/beams).
//
// Each answer costs the run a pause at a step boundary (and the beams a trace of the scan),
// so the page asks at most every INSPECT_MS while it runs, whatever its frame rate, and the
// beams only when asked for (the "beams of the selected robot" box, or every robot's). Once
// the run has ended it asks no more; a request in flight then is answered with the final
// state (`final`), and the beams drawn stay.
import { api } from "./api.js";
import { STATE_NAMES } from "./view.js";

export const INSPECT_MS = 250;

function going(page) {
  const state = page.status ? page.status.state : "";
  return state === "running" || state === "paused";
}

// Call `ask` now if the last call was INSPECT_MS ago or more, else once, when it is.
function throttled(page, key, ask) {
  const slot = page.throttle || (page.throttle = {});
  const last = slot[key] || { at: 0, timer: null };
  slot[key] = last;
  const wait = last.at + INSPECT_MS - performance.now();
  if (wait <= 0) { last.at = performance.now(); ask(); return; }
  if (!last.timer) {
    last.timer = setTimeout(() => { last.timer = null; last.at = performance.now(); ask(); },
      wait);
  }
}

// The beams drawn on the live page: every robot's when the inspector's toggle is on, else
// the selected robot's when the page's box is ticked, as the engine sensed them; one request
// at a time, then one more if frames came meanwhile (drawn a frame or two late while it
// runs, as the replay's).
export function fetchLiveBeams(page) {
  const all = page.inspector.allBeams;
  const robot = page.inspector.selected;
  const wanted = all || (robot >= 0 && page.beamsBox && page.beamsBox.checked);
  if (!wanted || !going(page)) return;
  if (page.beamsPending) { page.beamsWanted = true; return; }
  throttled(page, "beams", () => askBeams(page));
}

async function askBeams(page) {
  const all = page.inspector.allBeams;
  const robot = page.inspector.selected;
  if (!(all || (robot >= 0 && page.beamsBox && page.beamsBox.checked)) || !going(page)) return;
  const id = page.id;
  page.beamsPending = true;
  page.beamsWanted = false;
  let data;
  try {
    data = await api.get(`/api/live/${id}/beams`, all ? { all: true } : { robot });
  } catch (error) {
    data = undefined; // (a 4xx: the robot went; the last beams stay)
  }
  page.beamsPending = false;
  if (data && !data.final && id === page.id && all === page.inspector.allBeams
      && (all || robot === page.inspector.selected)) {
    page.beams = data.segments;
    page.view.redraw();
  }
  if (page.beamsWanted && id === page.id) fetchLiveBeams(page);
}

// The selected robot's values and lines from the worker, at most every INSPECT_MS and once
// per frame time (paused: once); the inspector shows them when they come.
function timeKey(page, robot) {
  return `${robot}@${page.frame ? page.frame.time : 0}`;
}

function fetchDetails(page) {
  const robot = page.inspector.selected;
  if (robot < 0 || !going(page) || timeKey(page, robot) === page.detailsKey) return;
  throttled(page, "robot", async () => {
    const i = page.inspector.selected;
    if (i < 0 || !going(page) || page.detailsPending) return;
    const asked = timeKey(page, i);
    page.detailsPending = true;
    try {
      const details = await api.get(`/api/live/${page.id}/robot`, { robot: i });
      page.detailsKey = asked;
      if (i === page.inspector.selected) {
        page.details = details;
        page.inspector.select(i); // values and lines again, at this time
      }
    } catch (error) {
      page.detailsKey = asked; // (a 4xx: the robot is not there; the last values stay)
    } finally {
      page.detailsPending = false;
    }
    if (timeKey(page, page.inspector.selected) !== page.detailsKey) fetchDetails(page);
  });
}

export function liveSource(page) {
  return {
    robotAt: (i) => {
      const { poses, states, time } = page.frame;
      const known = page.details && page.details.id === i ? page.details : null;
      const value = (name) => (known ? known[name] : null);
      return { id: i, type: value("type"), time, state: STATE_NAMES[states[i]],
        x: poses[3 * i], y: poses[3 * i + 1], yaw: poses[3 * i + 2], v: value("v"),
        w: value("w"), vRef: value("vRef"), headingRef: value("headingRef"),
        goal: page.meta.goals[i] };
    },
    // called by the inspector as the time moves: the lines known, and a request for newer
    // ones (throttled) whose answer updates the inspector again
    logLines: async (i) => {
      fetchDetails(page);
      const known = page.details && page.details.id === i ? page.details : null;
      return known ? { lines: known.lines, skipped: known.skipped } : undefined;
    },
    beamsChanged: () => { page.beams = []; page.view.redraw(); fetchLiveBeams(page); },
  };
}
