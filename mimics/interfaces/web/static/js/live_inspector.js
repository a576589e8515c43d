// The inspector's source on the live page (interface in inspector.js): a robot's values now,
// from the latest frame (pose, state, time), the meta (goal) and the worker's answer for that
// robot (/api/live/ID/robot: type, v, w, references, its events so far as log lines); and
// the beams of its last scan, or every robot's (/api/live/ID/beams).
import { api } from "./api.js";
import { STATE_NAMES } from "./view.js";

// The beams drawn on the live page: every robot's when the inspector's toggle is on, else
// the selected robot's, as the engine sensed them; one request at a time, then one more if
// frames came meanwhile (drawn a frame or two late while it runs, as the replay's).
export async function fetchLiveBeams(page) {
  const all = page.inspector.allBeams;
  const robot = page.inspector.selected;
  const state = page.status ? page.status.state : "";
  if ((!all && robot < 0) || (state !== "running" && state !== "paused")) return;
  if (page.beamsPending) { page.beamsWanted = true; return; }
  const id = page.id;
  page.beamsPending = true;
  page.beamsWanted = false;
  let data;
  try {
    data = await api.get(`/api/live/${id}/beams`, all ? { all: true } : { robot });
  } catch (error) {
    data = undefined; // the run ended meanwhile: the last beams stay
  }
  page.beamsPending = false;
  if (data && id === page.id && all === page.inspector.allBeams
      && (all || robot === page.inspector.selected)) {
    page.beams = data.segments;
    page.view.redraw();
  }
  if (page.beamsWanted && id === page.id) fetchLiveBeams(page);
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
    // called by the inspector as the time moves, one request at a time: the robot's values
    // come with its lines (kept in page.details for robotAt)
    logLines: async (i) => {
      const state = page.status ? page.status.state : "";
      if (state === "running" || state === "paused") {
        try {
          const details = await api.get(`/api/live/${page.id}/robot`, { robot: i });
          if (i === page.inspector.selected) {
            page.details = details;
            page.inspector.update();
          }
        } catch (error) {
          return undefined; // the run ended meanwhile: the last values stay
        }
      }
      const known = page.details && page.details.id === i ? page.details : null;
      return known ? { lines: known.lines, skipped: known.skipped } : undefined;
    },
    beamsChanged: () => { page.beams = []; page.view.redraw(); fetchLiveBeams(page); },
  };
}
