// Plots as thumbnails that open full size: a click on the thumbnail shows the image over the
// page in a dialog (as wide as the window allows); Escape, the Close button or a click on
// the picture closes it. A plot the server refuses shows the server's message instead.
import { element } from "./api.js";

let dialog = null;

function plotDialog() {
  if (dialog) return dialog;
  const image = element("img", { alt: "" });
  dialog = element("dialog", { class: "plot-view", "aria-label": "Plot" },
    element("div", { class: "row" },
      element("button", { type: "button", onclick: () => dialog.close() }, "Close")),
    image);
  image.addEventListener("click", () => dialog.close());
  dialog.image = image;
  document.body.append(dialog);
  return dialog;
}

// Make `img` a thumbnail that opens full size when clicked; returns a node holding it.
export function enlargeable(img) {
  const box = element("figure", { class: "thumbnail" }, img);
  img.title = "Click to enlarge";
  img.addEventListener("click", () => {
    const view = plotDialog();
    view.image.src = img.src;
    view.image.alt = img.alt;
    view.showModal();
  });
  img.addEventListener("error", async () => {
    let reason = "the plot could not be drawn";
    try {
      const answer = await fetch(img.src);
      const body = await answer.json();
      if (body.detail) reason = String(body.detail);
    } catch { /* the generic reason stays */ }
    box.replaceChildren(element("p", { class: "plot-missing", role: "note" },
      `${img.alt}: ${reason}`));
  });
  return box;
}
