// The JSON API and the message line, shared by the pages.

// The message line shows one line (a long message ends in "..."; its whole text is the
// tooltip), so that the header never wraps.
export function say(text, isError = false) {
  const line = document.getElementById("message");
  line.textContent = text;
  line.title = text;
  line.classList.toggle("error", isError);
}

// Numbers typed as "a, b, c": the list when it holds one of the counts allowed, each a plain
// decimal number, else undefined ("abc", "14 0" and "1, 2, 3" for two are refused).
export function parseNumbers(text, ...counts) {
  const parts = text.split(",").map((p) => p.trim());
  const numbers = parts.map((p) => (/^[-+]?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?$/i.test(p)
    ? Number(p) : NaN));
  if (!counts.includes(numbers.length) || !numbers.every(Number.isFinite)) return undefined;
  return numbers;
}

// The error the message line shows, or "" when it shows none.
export function shownError() {
  const line = document.getElementById("message");
  return line.classList.contains("error") ? line.textContent : "";
}

// An error shown for an earlier action goes once the next action succeeds.
export function clearError() {
  const line = document.getElementById("message");
  if (line.classList.contains("error")) say("");
}

async function send(method, url, body, raw = false) {
  const options = { method, headers: {} };
  if (body instanceof Blob || body instanceof ArrayBuffer) {
    options.body = body;
    options.headers["Content-Type"] = "application/octet-stream";
  } else if (body !== undefined) {
    options.body = JSON.stringify(body);
    options.headers["Content-Type"] = "application/json";
  }
  const response = await fetch(url, options);
  if (!response.ok) {
    let detail = `${response.status} ${response.statusText}`;
    try {
      const data = await response.json();
      if (data.detail) {
        detail = typeof data.detail === "string" ? data.detail
          : data.detail.map((d) => `${(d.loc || []).slice(1).join(".")}: ${d.msg}`).join("; ");
      }
    } catch (_) { /* not JSON: keep the status line */ }
    const error = new Error(detail);
    error.status = response.status;
    throw error;
  }
  return raw ? response.arrayBuffer() : response.json();
}

export const api = {
  get: (url, params) => send("GET", params ? `${url}?${new URLSearchParams(params)}` : url),
  binary: (url, params) => send("GET", `${url}?${new URLSearchParams(params)}`, undefined, true),
  post: (url, body, params) =>
    send("POST", params ? `${url}?${new URLSearchParams(params)}` : url, body),
  put: (url, body) => send("PUT", url, body),
};

// Run an async action; show its error (one line) in the message line instead of throwing.
export async function guarded(action) {
  try {
    const result = await action();
    clearError();
    return result;
  } catch (error) {
    say(error.message, true);
    return undefined;
  }
}

// Save a file with PUT: over the file this editor opened or last saved it is replaced at once;
// over another existing file (in the page's list, else the server's 409) the user is asked.
// Returns the server's answer, or undefined when not saved (the reason is in the message line).
export async function saveFile(url, body, ownPath, knownFiles = []) {
  const ask = () => {
    if (window.confirm(`${body.path} exists already. Replace it?`)) return true;
    say(`not saved: ${body.path} exists already (choose another file name)`, true);
    return false;
  };
  const own = body.path === ownPath;
  if (!own && knownFiles.includes(body.path)) {
    if (!ask()) return undefined;
    return guarded(() => api.put(url, { ...body, overwrite: true }));
  }
  try {
    return await api.put(url, { ...body, overwrite: own });
  } catch (error) {
    if (error.status !== 409) { say(error.message, true); return undefined; }
    if (!ask()) return undefined;
    return guarded(() => api.put(url, { ...body, overwrite: true }));
  }
}

// Before edits are replaced (opening another file, a new map): true when there are none
// unsaved, or the user agrees to drop them.
export function mayDiscard(editor, what) {
  return !editor.dirty || window.confirm(`Unsaved edits to ${what} will be lost. Continue?`);
}

// Poll a background job until it ends; onProgress(job) after each poll.
export async function waitJob(id, onProgress) {
  for (;;) {
    const job = await api.get(`/api/jobs/${id}`);
    if (onProgress) onProgress(job);
    if (job.state !== "running") return job;
    await new Promise((resolve) => setTimeout(resolve, 300));
  }
}

export function element(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (key.startsWith("on")) node.addEventListener(key.slice(2), value);
    else if (value !== undefined && value !== null && value !== false) node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

export function fileList(list, paths, onOpen) {
  list.replaceChildren(...paths.map((path) => element("li", {},
    element("button", { type: "button", onclick: () => onOpen(path) }, path))));
}
