// The inspector's source on the live page (interface in inspector.js): a robot's values now,
// from the latest frame (pose, state, time), the meta (goal) and the worker's answer for that
// robot (/api/live/ID/robot: type, v, w, references, its events so far as log lines).
import { api } from "./api.js";
import { STATE_NAMES } from "./view.js";

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
  };
}
