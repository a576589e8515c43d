// The live view of mimics.show(): the frames the kernel draws (the replay's renderer, as
// PNG bytes), Play/Pause/Step/Stop and a speed choice sent back to the kernel.

const SPEEDS = [["0.25", "0.25x"], ["0.5", "0.5x"], ["1", "1x"], ["2", "2x"], ["5", "5x"],
                ["10", "10x"], ["0", "max"]];

function render({ model, el }) {
  el.classList.add("mimics-live");
  const bar = document.createElement("div");
  bar.className = "mimics-live-controls";
  bar.style.cssText = "display:flex;gap:6px;align-items:center;margin:4px 0;font:13px sans-serif";
  const buttons = {};
  for (const [command, label] of [["play", "Play"], ["pause", "Pause"], ["step", "Step"],
                                  ["stop", "Stop"]]) {
    const button = document.createElement("button");
    button.textContent = label;
    button.className = `mimics-${command}`;
    button.addEventListener("click", () => model.send({ command }));
    buttons[command] = button;
    bar.appendChild(button);
  }
  const speed = document.createElement("select");
  speed.className = "mimics-speed";
  speed.title = "simulated seconds per second";
  for (const [value, label] of SPEEDS) speed.add(new Option(label, value));
  speed.addEventListener("change", () => {
    model.set("speed", Number(speed.value));
    model.save_changes();
  });
  const info = document.createElement("span");
  info.className = "mimics-info";
  bar.append(speed, info);
  const image = document.createElement("img");
  image.className = "mimics-frame";
  image.alt = "mimics live view";
  image.style.maxWidth = "100%";
  let url = null;

  function draw() {
    const data = model.get("frame");
    if (!data || !data.byteLength) return;
    const next = URL.createObjectURL(new Blob([data], { type: "image/png" }));
    image.src = next;
    image.dataset.frames = String(model.get("frames"));
    if (url) URL.revokeObjectURL(url);
    url = next;
  }

  function describe() {
    const state = model.get("state");
    const ended = state === "ended";
    info.textContent = `${model.get("title")}  t = ${model.get("time").toFixed(1)} s  ` +
      (ended ? `ended: ${model.get("status")}` : state);
    el.dataset.state = state;
    buttons.play.disabled = ended || state === "playing";
    buttons.pause.disabled = ended || state !== "playing";
    buttons.step.disabled = ended;
    buttons.stop.disabled = ended;
    const chosen = String(model.get("speed"));
    if ([...speed.options].some((o) => o.value === chosen)) speed.value = chosen;
  }

  model.on("change:frame", draw);
  for (const name of ["time", "state", "status", "speed", "title"]) {
    model.on(`change:${name}`, describe);
  }
  el.append(bar, image);
  draw();
  describe();
  return () => { if (url) URL.revokeObjectURL(url); };
}

export default { render };
