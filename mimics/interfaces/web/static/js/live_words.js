// The live page's words: the run's state in a line a person reads as the truth, and an
// edit's refusal as one short sentence.

// How a run ended, by its status (the engine's end statuses).
const ENDINGS = {
  stopped: "stopped",
  time_limit: "finished: the time limit was reached",
  completed: "finished: every robot is done",
  wall_limit: "ended at its wall-clock limit",
  error: "ended in error",
};

function seconds(time) {
  return `t = ${Number(time || 0).toFixed(2)} s`;
}

// "running, recording runs/x", "paused at t = 1.20 s, recording runs/x", "stopping...",
// "stopped at t = 4.10 s; recorded in runs/x".
export function liveStateLine(status) {
  const run = status.run || "";
  switch (status.state) {
    case "starting": return "starting...";
    case "running": return `running${run ? `, recording ${run}` : ""}`;
    case "paused": return `paused at ${seconds(status.time)}${run ? `, recording ${run}` : ""}`;
    case "stopping": return "stopping...";
    case "finished":
    case "error": {
      const how = ENDINGS[status.status] || (status.state === "error" ? ENDINGS.error
        : `finished (${status.status || "?"})`);
      return `${how} at ${seconds(status.time)}${run ? `; recorded in ${run}` : ""}`;
    }
    default: return status.state || "";
  }
}

// The server's refusal ("edit: robot 0 at (-0.0112477, 3.83071) would overlap robot 1") as a
// sentence's end: no "edit:" prefix naming the field, numbers to the millimetre, a full stop
// ("robot 0 at (-0.011, 3.831) would overlap robot 1.").
export function refusalSentence(message) {
  let text = String(message || "").split("\n")[0].trim();
  text = text.replace(/^edit(\[\d+\])?(\.[\w.]+)?:\s*/, "");
  text = text.replace(/-?\d+\.\d{4,}(e[-+]?\d+)?/gi, (n) => String(Number(Number(n).toFixed(3))));
  if (!text) return "the run did not take the edit.";
  return /[.!?]$/.test(text) ? text : `${text}.`;
}
