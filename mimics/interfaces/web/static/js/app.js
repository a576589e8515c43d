// The workbench's router: one page per hash (#/maps, #/scenarios, #/batteries, #/runs,
// #/live/ID for a live run).
import { BatteryPage } from "./batteries.js";
import { LivePage } from "./live.js";
import { MapEditor } from "./maps.js";
import { RunPage } from "./runs.js";
import { ScenarioEditor } from "./scenarios.js";

const PAGES = { maps: MapEditor, scenarios: ScenarioEditor, batteries: BatteryPage, runs: RunPage,
  live: LivePage };
const instances = {};
let shown = null;

function route() {
  const [path, query = ""] = window.location.hash.replace(/^#\/?/, "").split("?");
  const [name, id] = path.split("/"); // #/live/3: the live page of live run 3
  const page = PAGES[name] ? name : "maps";
  const params = new URLSearchParams(query);
  if (id) params.set("id", id);
  for (const key of Object.keys(PAGES)) {
    document.getElementById(`page-${key}`).hidden = key !== page;
  }
  document.querySelectorAll("nav a").forEach((a) => {
    if (a.dataset.page === page) a.setAttribute("aria-current", "page");
    else a.removeAttribute("aria-current");
  });
  if (shown && shown !== instances[page] && shown.leave) shown.leave();
  if (!instances[page]) instances[page] = new PAGES[page](document.getElementById(`page-${page}`));
  shown = instances[page];
  shown.refresh();
  if (shown.enter) shown.enter(params);
}

window.workbench = instances; // for tests and the console: the page objects
window.addEventListener("hashchange", route);
// Closing or reloading the tab loses the editors' unsaved edits: the browser asks first.
// (Moving between pages keeps every page's edits: nothing to ask there.)
window.addEventListener("beforeunload", (event) => {
  if (!Object.values(instances).some((page) => page.dirty)) return;
  event.preventDefault();
  event.returnValue = ""; // older browsers ask only when this is set
});
route();
