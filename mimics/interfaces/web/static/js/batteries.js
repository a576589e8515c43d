// The Batteries page: algorithms x scenarios x seeds x parameter values, start, live
// progress from the battery's SQLite state, result table, resume and re-run failed runs;
// the evidence: intervals per cell, the paired comparison, the stopping rule's progress.
import { api, element, guarded, say } from "./api.js";
import { EvidenceView } from "./evidence.js";
import { startLive } from "./live.js";
import { enlargeable } from "./plot_view.js";

const COLUMNS = ["id", "algorithm", "scenario", "parameters", "seed", "state", "status",
  "reached_goal", "collisions", "deadlocks", "livelocks", "escaped", "exceptions", "sim_time",
  "wall_time"];

// "robots=2,4; time_limit=10" -> {robots: [2, 4], time_limit: 10}
export function parseParams(text) {
  const params = {};
  for (const part of text.split(";").map((p) => p.trim()).filter(Boolean)) {
    const [key, raw = ""] = part.split("=").map((s) => s.trim());
    const values = raw.split(",").map((v) => v.trim()).filter(Boolean).map((v) => {
      if (v === "true" || v === "false") return v === "true";
      return Number.isFinite(Number(v)) ? Number(v) : v;
    });
    params[key] = values.length === 1 ? values[0] : values;
  }
  return params;
}

export class BatteryPage {
  constructor(root) {
    this.root = root;
    this.current = "";
    this.sortKey = "id";
    this.sortDown = false;
    this.rows = [];
    this.timer = null;
    this.build();
  }

  build() {
    const number = (label, value) => element("input", { type: "number", value,
      "aria-label": label, onchange: () => this.count() });
    this.nameInput = element("input", { type: "text", value: "battery1",
      "aria-label": "Battery name" });
    this.algorithmBox = element("div", { role: "group", "aria-label": "Algorithms" });
    this.scenarioBox = element("div", { role: "group", "aria-label": "Scenarios" });
    this.seedsInput = number("Seeds", "2");
    this.timeInput = number("Simulated seconds per run", "");
    this.untilInput = element("input", { type: "text", placeholder: "time_to_goal:0.2",
      "aria-label": "Stop when", onchange: () => this.count() });
    this.minSeedsInput = number("Minimum seeds", "10");
    this.maxSeedsInput = number("Maximum seeds", "500");
    this.runCount = element("p", { "aria-live": "polite" }, "");
    this.list = element("ul", { class: "files", "aria-label": "Batteries" });
    const side = element("div", { class: "side" },
      element("h2", {}, "New battery"), element("label", {}, "name ", this.nameInput),
      element("h2", {}, "Algorithms"), this.algorithmBox,
      element("h2", {}, "Scenarios"),
      element("p", { class: "hint" }, "Parameters: name=value or name=v1,v2 (a sweep), "
        + "separated by ';', e.g. robots=2,4; time_limit=10"), this.scenarioBox,
      element("div", { class: "row" }, element("label", {}, "seeds ", this.seedsInput),
        element("label", {}, "time (s) ", this.timeInput)),
      element("p", { class: "hint" }, "Or run seeds in rounds until the 95% interval of a "
        + "metric's mean is narrow enough: METRIC:HALF_WIDTH (replaces seeds)"),
      element("div", { class: "row" }, element("label", {}, "until ", this.untilInput),
        element("label", {}, "min ", this.minSeedsInput),
        element("label", {}, "max ", this.maxSeedsInput)),
      this.runCount,
      element("button", { type: "button", class: "primary", onclick: () => this.start() },
        "Start battery"),
      element("h2", {}, "Batteries"), this.list);
    this.title = element("h2", {}, "");
    this.progressText = element("p", { "aria-live": "polite", "aria-label": "Progress" }, "");
    this.bar = element("progress", { max: "1", value: "0", "aria-label": "Battery progress" });
    this.filter = element("input", { type: "text", placeholder: "filter rows",
      "aria-label": "Filter runs", oninput: () => this.showTable() });
    this.onlyBad = element("input", { type: "checkbox", "aria-label": "Only misbehaving runs",
      onchange: () => this.showTable() });
    this.resumeButton = element("button", { type: "button", onclick: () => this.restart("resume") },
      "Resume");
    this.rerunButton = element("button", { type: "button",
      onclick: () => this.restart("rerun-failed") }, "Re-run failed");
    this.table = element("table", { "aria-label": "Runs of the battery" });
    this.plots = element("div", { class: "plots" });
    this.evidence = new EvidenceView(() => this.current);
    this.root.replaceChildren(side, element("div", { class: "table-box" }, this.title,
      this.progressText, this.bar,
      element("div", { class: "row" }, this.filter,
        element("label", {}, this.onlyBad, " only misbehaving"), this.resumeButton,
        this.rerunButton,
        element("button", { type: "button", onclick: () => this.showPlots() }, "Plots")),
      this.table, this.evidence.root, this.plots));
  }

  async refresh() {
    const [algorithms, scenarios, batteries] = await Promise.all([
      guarded(() => api.get("/api/algorithms")), guarded(() => api.get("/api/scenarios")),
      guarded(() => api.get("/api/batteries"))]);
    if (!algorithms || !scenarios || !batteries) return;
    if (!this.algorithmBox.children.length) {
      const names = [...algorithms.builtin.map((a) => a.name), ...algorithms.files];
      this.algorithmBox.replaceChildren(...names.map((n) => element("label", {},
        element("input", { type: "checkbox", value: n, onchange: () => this.count() }), ` ${n}`)));
      const names2 = [...scenarios.files, ...scenarios.builtin.map((s) => s.name)];
      this.scenarioBox.replaceChildren(...names2.map((n) => element("div", {},
        element("label", {}, element("input", { type: "checkbox", value: n,
          onchange: () => this.count() }), ` ${n}`),
        element("input", { type: "text", "aria-label": `Parameters of ${n}`,
          "data-scenario": n, onchange: () => this.count() }))));
    }
    this.showList(batteries.batteries);
  }

  async refreshList() {
    const batteries = await guarded(() => api.get("/api/batteries"));
    if (batteries) this.showList(batteries.batteries);
  }

  // Each battery with its state: running, stopped (runs left) or finished. The watched
  // battery's poll refreshes the list when its state changes, so that no entry stays
  // "running" after the battery stopped.
  showList(batteries) {
    this.listed = Object.fromEntries(batteries.map((b) => [b.path, b.running]));
    this.list.replaceChildren(...batteries.map((b) => {
      const left = (b.counts.pending || 0) + (b.counts.running || 0);
      const state = b.running ? "running" : left ? "stopped" : "finished";
      return element("li", {}, element("button", { type: "button",
        onclick: () => this.watch(b.path) }, `${b.path} (${b.total} runs, ${state})`));
    }));
  }

  body(dryRun) {
    const checked = (box) => [...box.querySelectorAll("input[type=checkbox]:checked")]
      .map((i) => i.value);
    const scenarios = checked(this.scenarioBox).map((name) => ({ name,
      params: parseParams(this.scenarioBox.querySelector(`input[data-scenario="${CSS.escape(name)}"]`)
        .value) }));
    const seeds = Math.round(Number(this.seedsInput.value));
    const body = { name: this.nameInput.value.trim(), algorithms: checked(this.algorithmBox),
      scenarios, seeds, time: Number(this.timeInput.value) || null, dry_run: dryRun };
    const until = this.untilInput.value.trim();
    if (until) {
      const [metric, width] = until.split(":").map((t) => t.trim());
      body.until = { metric, half_width: Number(width),
        min_seeds: Math.round(Number(this.minSeedsInput.value)),
        max_seeds: Math.round(Number(this.maxSeedsInput.value)) };
    }
    return body;
  }

  async count() {
    const body = this.body(true);
    if (!body.algorithms.length || !body.scenarios.length) {
      this.runCount.textContent = "choose algorithms and scenarios";
      return;
    }
    try {
      const data = await api.post("/api/batteries", body);
      this.runCount.textContent = data.max_runs
        ? `${data.runs} runs in the first round, at most ${data.max_runs}` : `${data.runs} runs`;
    } catch (error) {
      this.runCount.textContent = error.message;
    }
  }

  async start() {
    const data = await guarded(() => api.post("/api/batteries", this.body(false)));
    if (!data) return;
    say(`started ${data.path}: ${data.runs} runs`);
    this.watch(data.path);
    this.refresh();
  }

  async restart(kind) {
    if (!this.current) return;
    const data = await guarded(() => api.post(`/api/batteries/${kind}`, { path: this.current }));
    if (data) { say(`${kind}: ${this.current}`); this.watch(this.current); }
  }

  watch(path) {
    this.current = path;
    this.title.textContent = path;
    this.plots.replaceChildren();
    this.evidence.clear();
    this.shownFinished = -1;
    window.history.replaceState(null, "", `#/batteries?path=${encodeURIComponent(path)}`);
    clearTimeout(this.timer);
    this.poll();
  }

  async poll() {
    const path = this.current;
    let data;
    try {
      data = await api.get("/api/batteries/status", { path });
    } catch (error) {
      say(error.message, true);
      return;
    }
    if (path !== this.current) return;
    if (this.listed && !data.starting && this.listed[path] !== data.running) this.refreshList();
    const counts = Object.entries(data.counts).map(([k, v]) => `${v} ${k}`).join(", ");
    const rate = data.rate ? `, ${data.rate.toFixed(2)} runs/s` : "";
    const eta = data.running && data.eta ? `, ${Math.ceil(data.eta)} s left` : "";
    const state = data.starting ? "starting" : data.running ? "running" : "stopped";
    this.progressText.textContent = `${data.finished} of ${data.total} runs finished (${state}`
      + `${counts ? `; ${counts}` : ""}${rate}${eta})${data.job_error ? ` error: ${data.job_error}` : ""}`;
    this.bar.max = data.total || 1;
    this.bar.value = data.finished;
    this.resumeButton.disabled = data.running || data.finished === data.total;
    const failed = ["error", "timeout", "crashed"].reduce((n, k) => n + (data.counts[k] || 0), 0);
    this.rerunButton.disabled = data.running || failed === 0;
    this.rows = data.runs;
    this.showTable();
    if (data.finished !== this.shownFinished && !data.starting) {  // new results: new evidence
      this.shownFinished = data.finished;
      this.evidence.load();
    }
    if (data.running && !document.hidden) this.timer = setTimeout(() => this.poll(), 700);
    else if (data.running) this.timer = setTimeout(() => this.poll(), 3000);
  }

  showTable() {
    const needle = this.filter.value.trim().toLowerCase();
    let rows = this.rows.filter((r) => (!this.onlyBad.checked || r.misbehaving)
      && (!needle || COLUMNS.some((c) => String(r[c] ?? "").toLowerCase().includes(needle))));
    const key = this.sortKey;
    rows = rows.slice().sort((a, b) => {
      const x = a[key] ?? "";
      const y = b[key] ?? "";
      const order = typeof x === "number" && typeof y === "number" ? x - y
        : String(x).localeCompare(String(y));
      return this.sortDown ? -order : order;
    });
    const head = element("tr", {}, ...COLUMNS.map((c) => element("th", {
      scope: "col", "aria-sort": c === key ? (this.sortDown ? "descending" : "ascending") : "none",
      onclick: () => { this.sortDown = c === key ? !this.sortDown : false; this.sortKey = c;
        this.showTable(); } }, c.replace(/_/g, " "))), element("th", { scope: "col" }, "live"));
    const body = rows.map((r) => element("tr", {
      class: `${r.misbehaving ? "misbehaving" : ""} ${r.folder ? "clickable" : ""}`,
      title: r.error || "",
      onclick: () => { if (r.folder) window.location.hash = `#/runs?path=${encodeURIComponent(r.folder)}`; },
    }, ...COLUMNS.map((c) => element("td", {}, c === "state" && r.misbehaving
      ? `⚠ ${r[c]}` : formatCell(r[c]))), this.liveCell(r)));
    if (!body.length && this.rows.length) {  // the filter hides every run: say so
      body.push(element("tr", {}, element("td", { colspan: String(COLUMNS.length + 1),
        class: "empty" }, `No run of the ${this.rows.length} matches the filter`
        + `${this.onlyBad.checked ? " (only misbehaving runs)" : ""}.`)));
    }
    this.table.replaceChildren(element("thead", {}, head), element("tbody", {}, ...body));
  }

  // A row's "Run live" button: the same run (scenario, parameters, algorithm, seed) again,
  // live, in a new run folder under runs/.
  liveCell(row) {
    return element("td", {}, element("button", { type: "button",
      "aria-label": `Run live: run ${row.id}`, onclick: (event) => {
        event.stopPropagation(); // not the row's click (its replay)
        startLive({ battery: this.current, run: row.id });
      } }, "Run live"));
  }

  showPlots() {
    if (!this.current) return;
    const stamp = Date.now();
    const names = ["outcomes.png", "time_to_goal.png", "arrivals.png"]; // beside each other
    this.plots.replaceChildren(...names.map((name) =>
      enlargeable(element("img", { alt: `${name} of ${this.current}`,
        src: `/api/batteries/plot?${new URLSearchParams({ path: this.current, name })}&t=${stamp}` }))));
  }

  leave() { clearTimeout(this.timer); }

  enter(params) {
    if (params.get("path")) this.watch(params.get("path"));
    else if (this.current) this.poll();
  }
}

function formatCell(value) {
  if (value === null || value === undefined) return "";
  if (typeof value === "number" && !Number.isInteger(value)) return value.toFixed(2);
  return String(value);
}
