// widgets.BrowserPad, the page's side (an anywidget ES module; the kernel's side is browser_pad.py).
// Reads the first gamepad through the browser's Gamepad API every send_period_ms and sends it as it is
// (the W3C mapping's name, axes and buttons) to the kernel, which maps and checks it
// (hri_teleop/core/gamepad/browser.py): no rule of the lab lives here. Plays the kernel's rumble on the
// pad's motors where the browser offers "dual-rumble", and shows it as a bar on screen in any case.

function firstPad() {
  if (typeof navigator.getGamepads !== "function") return null;
  let pads = [];
  try {
    pads = Array.from(navigator.getGamepads() || []);
  } catch (error) {
    return null; // blocked by a permissions policy: the kernel says no gamepad
  }
  return pads.find((pad) => pad && pad.connected) || pads.find((pad) => pad) || null;
}

function canRumble(pad) {
  const actuator = pad && pad.vibrationActuator;
  if (!actuator || typeof actuator.playEffect !== "function") return false;
  return Array.isArray(actuator.effects) ? actuator.effects.includes("dual-rumble") : actuator.type === "dual-rumble";
}

function describe(pad) {
  if (!pad) return null;
  return {
    id: String(pad.id),
    mapping: String(pad.mapping),
    connected: pad.connected !== false,
    axes: Array.from(pad.axes, Number),
    buttons: Array.from(pad.buttons, (button) => [button.pressed === true, Number(button.value)]),
    haptics: canRumble(pad),
  };
}

function median(values) {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted.length ? sorted[Math.floor(sorted.length / 2)] : NaN;
}

function render({ model, el }) {
  el.classList.add("hri-browser-pad");
  el.innerHTML = `
    <div class="hri-bp-status" style="font-family: sans-serif"></div>
    <div class="hri-bp-state" style="font-family: monospace; margin: 4px 0"></div>
    <div style="display: flex; align-items: center; gap: 8px; font-family: sans-serif">
      <span>rumble</span>
      <div style="width: 240px; height: 14px; border: 1px solid #888; background: #fff">
        <div class="hri-bp-bar" style="width: 0%; height: 100%; background: #d62728"></div>
      </div>
      <span class="hri-bp-haptics" style="color: #555"></span>
    </div>
    <div class="hri-bp-page" style="font-family: sans-serif; color: #555"></div>`;
  const statusEl = el.querySelector(".hri-bp-status");
  const stateEl = el.querySelector(".hri-bp-state");
  const bar = el.querySelector(".hri-bp-bar");
  const hapticsEl = el.querySelector(".hri-bp-haptics");
  const pageEl = el.querySelector(".hri-bp-page");
  const roundTrips = [];
  const sent = new Map(); // seq -> performance.now() in ms, for the round trip the kernel echoes
  let seq = 0;
  let barTimer = null;

  function showStatus() {
    statusEl.textContent = model.get("status");
    statusEl.style.color = model.get("status_error") ? "#b00020" : "inherit";
  }

  function showPage(pad) {
    const parts = [];
    if (!window.isSecureContext) {
      parts.push("this page is not served over https or from localhost: browsers may hide the gamepad; " +
                 "open JupyterLab through https or an SSH tunnel");
    }
    if (roundTrips.length) parts.push(`page -> kernel -> page: ${median(roundTrips).toFixed(0)} ms`);
    pageEl.textContent = parts.join("; ");
    hapticsEl.textContent = !pad ? "" : canRumble(pad) ? "(on the pad too)"
      : "(on screen only: this browser cannot rumble this pad)";
  }

  function send() {
    const pad = firstPad();
    seq += 1;
    sent.set(seq, performance.now());
    if (sent.size > 100) sent.delete(sent.keys().next().value);
    model.set("reading", {
      sent_s: performance.now() / 1000,
      visible: document.visibilityState !== "hidden",
      pad: describe(pad),
      seq,
    });
    model.save_changes();
    showPage(pad);
  }

  function onRumble() {
    const rumble = model.get("rumble") || {};
    const strong = Math.min(1, Math.max(0, Number(rumble.strong) || 0));
    const weak = Math.min(1, Math.max(0, Number(rumble.weak) || 0));
    const duration = Math.max(0, Number(rumble.duration_ms) || 0);
    bar.style.width = `${Math.round(100 * Math.max(strong, weak))}%`;
    clearTimeout(barTimer);
    if (duration > 0) barTimer = setTimeout(() => { bar.style.width = "0%"; }, duration);
    const pad = firstPad();
    if (!canRumble(pad)) return;
    try {
      const actuator = pad.vibrationActuator;
      const done = strong > 0 || weak > 0
        ? actuator.playEffect("dual-rumble", { startDelay: 0, duration, strongMagnitude: strong, weakMagnitude: weak })
        : (typeof actuator.reset === "function" ? actuator.reset()
          : actuator.playEffect("dual-rumble", { startDelay: 0, duration: 0, strongMagnitude: 0, weakMagnitude: 0 }));
      if (done && typeof done.catch === "function") done.catch(() => {}); // "preempted" by the next request
    } catch (error) {
      hapticsEl.textContent = `(on screen only: ${error})`;
    }
  }

  function onEcho() {
    const started = sent.get(model.get("echo_seq"));
    if (started === undefined) return;
    roundTrips.push(performance.now() - started);
    if (roundTrips.length > 20) roundTrips.shift();
    el.dataset.roundTripMs = median(roundTrips).toFixed(1);
  }

  function onState() {
    stateEl.textContent = model.get("pad_line");
  }

  const handlers = [["change:status", showStatus], ["change:status_error", showStatus], ["change:rumble", onRumble],
                    ["change:echo_seq", onEcho], ["change:pad_line", onState]];
  handlers.forEach(([event, handler]) => model.on(event, handler));
  document.addEventListener("visibilitychange", send);
  showStatus();
  onState();
  const timer = setInterval(send, Math.max(10, model.get("send_period_ms")));
  send();
  return () => {
    clearInterval(timer);
    clearTimeout(barTimer);
    document.removeEventListener("visibilitychange", send);
    handlers.forEach(([event, handler]) => model.off(event, handler));
  };
}

export default { render };
