// The evidence of a battery (GET /api/batteries/evidence): each cell's means with 95%
// intervals (t; Wilson for proportions), each algorithm against a baseline paired by
// scenario, parameters and seed, the stopping rule's progress, identical-seed warnings.
import { api, element } from "./api.js";

export function intervalText(estimate, low, high, digits = 2) {
  if (estimate === null || estimate === undefined) return "-";
  if (low === null || low === undefined) return estimate.toFixed(digits);
  return `${estimate.toFixed(digits)} [${low.toFixed(digits)}, ${high.toFixed(digits)}]`;
}

function digitsOf(metric) { return metric === "wall_time" ? 3 : 2; }

function table(label, caption, header, rows) {
  return element("table", { "aria-label": label },
    element("caption", {}, caption),
    element("thead", {}, element("tr", {}, ...header.map((h) => element("th", { scope: "col" }, h)))),
    element("tbody", {}, ...rows.map((cells) => element("tr", {},
      ...cells.map((c) => element("td", {}, c))))));
}

export class EvidenceView {
  constructor(currentPath) {
    this.currentPath = currentPath;
    this.baseline = null;
    this.baselineSelect = element("select", { "aria-label": "Baseline",
      onchange: () => { this.baseline = this.baselineSelect.value; this.load(); } });
    this.body = element("div", {});
    this.root = element("section", { class: "evidence", "aria-label": "Evidence" },
      element("h3", {}, "Evidence"),
      element("label", {}, "baseline ", this.baselineSelect), this.body);
  }

  clear() {
    this.baseline = null;
    this.body.replaceChildren();
    this.baselineSelect.replaceChildren();
  }

  async load() {
    const path = this.currentPath();
    if (!path) return;
    const query = { path };
    if (this.baseline) query.baseline = this.baseline;
    let data;
    try {
      data = await api.get("/api/batteries/evidence", query);
    } catch (error) {
      this.body.replaceChildren(element("p", { class: "hint" }, error.message));
      return;
    }
    if (path !== this.currentPath()) return;
    this.show(data);
  }

  show(data) {
    this.baselineSelect.replaceChildren(...data.algorithms.map((a) => element("option",
      { value: a, ...(a === data.baseline ? { selected: "" } : {}) }, a)));
    const parts = [];
    if (data.until) parts.push(this.untilTable(data.until));
    parts.push(table("Intervals per cell",
      "Per cell, over done runs: mean [95% t interval]; success: proportion [95% Wilson interval]",
      ["algorithm", "scenario", "parameters", "runs", "done", ...data.metrics],
      data.intervals.map((r) => [r.algorithm, r.scenario, r.parameters, String(r.runs),
        String(r.done), ...data.metrics.map((m) => intervalText(r[m], r[`${m}_low`],
          r[`${m}_high`], digitsOf(m)))])));
    if (data.comparison.length) {
      parts.push(table("Paired comparison",
        `Paired comparison against ${data.baseline} (same scenario, parameters and seed): `
        + "mean difference [95% t interval], Wilcoxon signed-rank p",
        ["algorithm", "scenario", "parameters", "metric", "pairs", "difference", "p", "note"],
        data.comparison.map((r) => [r.algorithm, r.scenario, r.parameters, r.metric,
          String(r.pairs), intervalText(r.mean_difference, r.ci95_low, r.ci95_high,
            digitsOf(r.metric)),
          r.p_value === null ? "-" : r.p_value < 1e-4 ? "<1e-4" : r.p_value.toPrecision(2),
          r.note])));
    }
    if (data.warnings.length) {
      parts.push(element("ul", { class: "warnings", "aria-label": "Warnings" },
        ...data.warnings.map((w) => element("li", {}, `⚠ ${w}`))));
    }
    this.body.replaceChildren(...parts);
  }

  untilTable(until) {
    const rows = until.cells.map((c) => {
      const width = c.half_width === null ? "-" : c.half_width.toPrecision(3);
      // the bar fills as the half-width falls to its target (full: met)
      const value = c.half_width === null ? 0 : Math.min(1, until.half_width / Math.max(c.half_width, 1e-12));
      return [c.algorithm, c.scenario, c.parameters, `${c.seeds} of ${c.scheduled}`, width,
        element("progress", { max: "1", value: String(c.complete ? 1 : value),
          "aria-label": `Stopping rule of ${c.algorithm} ${c.parameters}` }), c.state];
    });
    return table("Stopping rule",
      `Until the 95% interval of ${until.metric} is within ± ${until.half_width} `
      + `(seeds ${until.min_seeds} to ${until.max_seeds})`,
      ["algorithm", "scenario", "parameters", "seeds", "half-width", "progress", "state"], rows);
  }
}
