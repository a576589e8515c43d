// The inspector's source on the Runs page (interface in inspector.js): a robot's values at
// the replay's frame, from the frames (pose, state), the meta (type, goal) and the robot's
// velocities and references per frame (/api/runs/robot, fetched when it is clicked).
import { api, guarded } from "./api.js";
import { STATE_NAMES } from "./inspector.js";

export function replaySource(page) {
  return {
    robotAt: (i) => {
      const { robots, poses, states, times } = page.data;
      const at = (page.frame * robots + i) * 3;
      const motion = page.motion && page.motion.robot === i ? page.motion : null;
      const value = (name) => (motion ? motion[name][page.frame] : null);
      return { id: i, type: page.meta.types[i], time: times[page.frame],
        state: STATE_NAMES[states[page.frame * robots + i]],
        x: poses[at], y: poses[at + 1], yaw: poses[at + 2], v: value("v"), w: value("w"),
        vRef: value("v_ref"), headingRef: value("heading_ref"),
        goal: (page.goalsShown || page.meta.goals)[i] }; // the goals of this frame
    },
    logLines: (i, time) => guarded(() => api.get("/api/runs/log",
      { path: page.meta.path, robot: i, until: time })),
    beamsChanged: () => { page.beams = []; page.view.redraw(); page.fetchBeams(); },
  };
}

// Fetch robot `robot`'s velocities and references per frame into page.motion.
export async function fetchMotion(page, robot) {
  const path = page.meta.path;
  const motion = await guarded(() => api.get("/api/runs/robot", { path, robot }));
  if (motion && path === page.meta.path && robot === page.selected) {
    page.motion = motion;
    page.inspector.update();
  }
}
