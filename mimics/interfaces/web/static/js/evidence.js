// The evidence of a battery (GET /api/batteries/evidence): the failed runs, each cell's
// means with 95% intervals (t; Wilson for proportions), each algorithm against a baseline
// paired by scenario, parameters and seed (Newcombe/McNemar for rates, t/Wilcoxon for
// means, raw and Holm-adjusted p), the stopping rule's progress, costs, warnings.
import { api, element } from "./api.js";

export function intervalText(estimate, low, high, digits = 2, n = null, what = "runs") {
  if (estimate === null || estimate === undefined) return "n/a";
  if (low === null || low === undefined) return estimate.toFixed(digits);
  // a sample with no spread has no interval: say so rather than print [v, v]
  if (low === high && n !== null && n >= 2) return `all ${n} ${what}: ${estimate.toFixed(digits)}`;
  return `${estimate.toFixed(digits)} [${low.toFixed(digits)}, ${high.toFixed(digits)}]`;
}

function digitsOf(metric) { return metric === "wall_time" || metric === "user_time" ? 3 : 2; }

function pText(p) {
  return p === null || p === undefined ? "-" : p < 1e-4 ? "<1e-4" : p.toPrecision(2);
}

function lines(label, css, items) {
  return element("ul", { class: css, "aria-label": label },
    ...items.map((w) => element("li", {}, w)));
}

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
    if (data.failed.length) parts.push(lines("Failed runs", "warnings", data.failed.map((f) => `failed: ${f}`)));
    if (data.unmet.length) parts.push(lines("Targets not met", "warnings", data.unmet.map((u) => `target not met: ${u}`)));
    if (data.until) parts.push(this.untilTable(data.until));
    parts.push(table("Intervals per cell",
      "Per cell, over finished runs (a failed run: success 0, reached 0, no other value): "
      + "mean [95% t interval corrected for skewness]; success: proportion [95% Wilson "
      + "interval]; time_to_goal: "
      + "restricted mean, robots that never arrived counted at the horizon",
      ["algorithm", "scenario", "parameters", "runs / done / failed", ...data.metrics],
      data.intervals.map((r) => [r.algorithm, r.scenario, r.parameters,
        `${r.runs} / ${r.done} / ${r.failed}`, ...data.metrics.map((m) => intervalText(r[m],
          r[`${m}_low`], r[`${m}_high`], digitsOf(m), r[`${m}_n`]))])));
    if (data.comparison.length) {
      parts.push(table("Paired comparison",
        `Paired comparison against ${data.baseline} (same scenario, parameters and seed): `
        + "rates: difference [95% Newcombe interval], McNemar exact p; means: difference "
        + `[95% t interval], Wilcoxon signed-rank p; p adjusted (${data.adjust}) for the `
        + `${data.tests} tests shown; * = primary metric`,
        ["algorithm", "scenario", "parameters", "metric", "pairs", "difference", "p",
          "p adjusted", "note"],
        data.comparison.map((r) => [r.algorithm, r.scenario, r.parameters,
          r.metric + (r.primary ? " *" : ""), String(r.pairs),
          intervalText(r.mean_difference, r.ci95_low, r.ci95_high, digitsOf(r.metric),
            r.pairs, "pairs"),
          pText(r.p_value), pText(r.p_adjusted), r.note])));
    }
    if (data.costs.length) {
      parts.push(table("Costs", "Costs (not outcomes): wall and user-code seconds of done runs",
        ["algorithm", "scenario", "parameters", "done", "wall s / run", "user-code s / run"],
        data.costs.map((r) => [r.algorithm, r.scenario, r.parameters, String(r.done),
          r.wall_time_mean === null ? "-" : r.wall_time_mean.toFixed(3),
          r.user_time_mean === null ? "-" : r.user_time_mean.toFixed(3)])));
    }
    if (data.warnings.length) {
      parts.push(lines("Warnings", "warnings", data.warnings.map((w) => `⚠ ${w}`)));
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
