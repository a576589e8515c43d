// The Scenarios page's scenario loading: a file's or a built-in scenario's robots, map, types
// and settings shown for editing; a built-in scenario opened as the start of a new file (not
// saved yet); a map written into the scenario file itself ("inline": a built-in scenario's
// generated map) listed in the map choice.
import { api, element, guarded, mayDiscard, say } from "./api.js";

export const INLINE = "(inline)"; // the map choice of a map written into the scenario file

// A built-in scenario (default parameters) as the start of a new file, not saved yet.
export async function openBuiltin(editor) {
  const name = editor.builtinSelect.value;
  if (!name || !mayDiscard(editor, "this scenario")) return;
  const data = await guarded(() => api.get("/api/scenarios/builtin", { name }));
  if (!data) return;
  let path = `scenarios/${name}.toml`;
  for (let k = 2; (editor.files || []).includes(path); k++) path = `scenarios/${name}-${k}.toml`;
  showScenario(editor, data, path);
  editor.dirty = true;
  editor.ownPath = null;
  say(`opened the built-in scenario ${name} as ${path} (not saved yet): `
    + `${editor.robots.length} robots`);
}

// Show a scenario the server sent (a file's or a built-in's) for editing, to save as `path`.
export function showScenario(editor, data, path) {
  editor.robots = data.robots;
  editor.types = data.custom_types || {};
  for (const [name, type] of Object.entries(data.types)) {
    if (!editor.robotTypes[name]) editor.robotTypes[name] = type;
  }
  editor.map = data.map_data;
  editor.mapRef = data.map || "";
  editor.inlineMap = data.map_inline || null;
  if (editor.mapRef && ![...editor.mapSelect.options].some((o) => o.value === editor.mapRef)) {
    editor.mapSelect.append(element("option", { value: editor.mapRef }, editor.mapRef));
  }
  editor.mapSelect.value = editor.mapRef;
  showInlineMap(editor);
  editor.nameInput.value = data.name;
  editor.pathInput.value = path;
  editor.timeInput.value = String(data.settings.time_limit);
  editor.toleranceInput.value = String(data.settings.goal_tolerance);
  editor.deadlockInput.value = String(data.settings.deadlock_window);
  editor.fault = { robots: [], walls: [] };
  editor.view.fit(editor.map.bounds);
  editor.view.invalidate();
  editor.showInfo();
}

// An inline map is listed in the map choice as what it is, chosen.
export function showInlineMap(editor) {
  [...editor.mapSelect.options].filter((o) => o.value === INLINE).forEach((o) => o.remove());
  if (!editor.inlineMap) return;
  editor.mapSelect.append(element("option", { value: INLINE },
    `${editor.inlineMap.name} (in the scenario file)`));
  editor.mapSelect.value = INLINE;
}
