// The binary frames of a run (its replay) and of a live run's stream: one layout, read
// by both pages (runs.js and live.js).

// Parse the body of /api/runs/frames (layout in runs.py): times, poses, states.
export function parseFrames(buffer) {
  const header = new DataView(buffer, 0, 8);
  const frames = header.getUint32(0, true);
  const robots = header.getUint32(4, true);
  const times = new Float32Array(buffer, 8, frames);
  const poses = new Float32Array(buffer, 8 + 4 * frames, frames * robots * 3);
  const states = new Uint8Array(buffer, 8 + 4 * frames + 12 * frames * robots, frames * robots);
  return { frames, robots, times, poses, states };
}
