// HoldButton, the page's side (an anywidget ES module; the kernel's side is hold_button.py).
// A button that is held only while the pointer (or the space / enter key) holds it down: pointer up,
// the pointer leaving the button, a cancelled touch, the window losing focus, a hidden tab or the view
// going away all release it. While held it sends a beat every beat_period_ms, so the kernel releases it
// by itself when the page falls silent (a closed tab, a lost link).

function render({ model, el }) {
  const button = document.createElement("button");
  button.type = "button";
  button.className = "hri-hold-button jupyter-widgets jupyter-button widget-button";
  button.style.touchAction = "none";
  button.style.userSelect = "none";
  el.appendChild(button);
  let held = false;
  let beat = 0;
  let beatTimer = null;

  function show() {
    const lit = held || model.get("lit");
    button.textContent = model.get("description");
    button.title = model.get("tooltip");
    button.disabled = model.get("disabled");
    button.classList.toggle("mod-active", lit);
    button.setAttribute("aria-pressed", String(lit));
    button.style.background = lit ? "#2ca02c" : "";
    button.style.color = lit ? "white" : "";
    el.dataset.held = String(held);
  }

  function sendBeat() {
    beat += 1;
    model.set("beat", beat);
    model.save_changes();
  }

  function send(value) {
    if (held === value) return;
    held = value;
    clearInterval(beatTimer);
    beatTimer = null;
    model.set("held", value);
    beat += 1;
    model.set("beat", beat);
    model.save_changes();
    if (value) beatTimer = setInterval(sendBeat, Math.max(20, model.get("beat_period_ms")));
    show();
  }

  const press = (event) => {
    if (event.button !== undefined && event.button !== 0) return; // the primary button (or a touch) only
    if (model.get("disabled")) return;
    event.preventDefault();
    send(true);
  };
  const release = () => send(false);
  const keyDown = (event) => {
    if ((event.key === " " || event.key === "Enter") && !event.repeat && !model.get("disabled")) {
      event.preventDefault();
      send(true);
    }
  };
  const keyUp = (event) => { if (event.key === " " || event.key === "Enter") release(); };
  const hidden = () => { if (document.visibilityState === "hidden") release(); };
  const noMenu = (event) => event.preventDefault(); // a long touch must not open the context menu

  const own = [["pointerdown", press], ["pointerup", release], ["pointerleave", release],
               ["pointercancel", release], ["lostpointercapture", release], ["blur", release],
               ["keydown", keyDown], ["keyup", keyUp], ["contextmenu", noMenu]];
  own.forEach(([name, handler]) => button.addEventListener(name, handler));
  window.addEventListener("blur", release);
  document.addEventListener("visibilitychange", hidden);
  const changes = "change:description change:disabled change:tooltip change:lit";
  model.on(changes, show);
  const releasedByKernel = () => {  // a reset in the kernel: stop holding until the next press
    if (model.get("held") || !held) return;
    held = false;
    clearInterval(beatTimer);
    beatTimer = null;
    show();
  };
  model.on("change:held", releasedByKernel);
  show();
  return () => {
    release();
    clearInterval(beatTimer);
    own.forEach(([name, handler]) => button.removeEventListener(name, handler));
    window.removeEventListener("blur", release);
    document.removeEventListener("visibilitychange", hidden);
    model.off(changes, show);
    model.off("change:held", releasedByKernel);
  };
}

export default { render };
