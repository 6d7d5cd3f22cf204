"""Controller view (handout Ex. 8): the pad's sticks and buttons, and what the lab's rules make of them.

Seeing the sticks and buttons beside the resulting mode, width, twist and rumble is how students
check their understanding before they write ``teleoperation.py``. :class:`ControllerModel` steps a
:class:`~hri_teleop.core.teleop.TeleopController` at the configured rate, as the node does. The pad
is a real one when plugged in, the gamepad of the browser page (``source="browser"``), else the
virtual pad driven from the widget's sliders and buttons (cross and circle act only while held:
:class:`~hri_teleop.course.widgets.hold_button.HoldButton`); without a display pygame finds no pad.
"""

from __future__ import annotations

import html
import time
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Optional, Set, Tuple

import ipywidgets as widgets

from hri_teleop.core.gamepad import (
    BUTTON_LABELS,
    STICK_AXES,
    Gamepad,
    GamepadError,
    PadState,
    RumbleRequests,
    check_deadzone,
    normalize_analog_input,
)
from hri_teleop.core.limits import DEFAULT_LIMITS, CartesianLimits
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M, Mode, TeleopController, TeleopParams
from hri_teleop.course.widgets._base import (
    Ticker,
    WidgetError,
    lab_teleop_config,
    message_html,
    replace_in_cell,
)
from hri_teleop.course.widgets.hold_button import HoldButton
from hri_teleop.hardware.gamepad import check_pad_rumble, open_gamepad
from hri_teleop.sim.virtual_pad import VirtualPad

__all__ = ["ControllerSnapshot", "ControllerModel", "stick_dot_xy", "button_roles", "pad_svg", "open_pad",
           "rumble_cue", "ControllerView"]

#: Longest stretch of time one advance() catches up on (s): after the kernel was busy for
#: a minute, the controller must not replay a minute of ticks in one go.
MAX_CATCH_UP_S = 0.5

_SYMBOLS = {"south": "\u2715", "east": "\u25cb", "west": "\u25a1", "north": "\u25b3"}


@dataclass(frozen=True)
class ControllerSnapshot:
    """What the view shows after one advance: the pad's state and the controller's output."""

    pad: PadState
    mode: Mode
    gripper_width_m: float
    rumble: float
    twist: Tuple[float, float, float, float, float, float]
    quit: bool
    stopping: bool
    ticks: int  # controller ticks stepped by this advance


class ControllerModel:
    """A pad and a TeleopController, stepped at ``params.rate_hz`` as real time passes."""

    def __init__(self, pad: Gamepad, params: Optional[TeleopParams] = None,
                 limits: CartesianLimits = DEFAULT_LIMITS) -> None:
        self.pad = pad
        self.params = params if params is not None else TeleopParams()
        self.limits = limits
        self.reset()

    def reset(self) -> None:
        """A fresh controller: translation mode, initial width, quit cleared."""
        self.controller = TeleopController(self.params, self.limits)
        self._debt_s = 0.0
        self._last = ControllerSnapshot(PadState.neutral(), self.controller.mode, self.controller.gripper_width_m,
                                        0.0, (0.0,) * 6, False, False, 0)
        self.ticks = 0

    def advance(self, elapsed_s: float, mapped_force: Optional[float] = None,
                force_age_s: float = 0.0) -> ControllerSnapshot:
        """Read the pad once and step the controller for ``elapsed_s`` seconds of its ticks.

        Whole ticks of ``1 / rate_hz`` are stepped; the remainder carries over to the next
        call, so the gripper moves ``k_gripper`` m/s of wall-clock time whatever the
        widget's refresh rate. ``mapped_force`` (0..1) with ``force_age_s`` drives the rumble.
        """
        try:
            state = self.pad.poll()
        except GamepadError:
            state = PadState.neutral(connected=False)
        dt_s = 1.0 / self.params.rate_hz
        self._debt_s = min(self._debt_s + max(0.0, float(elapsed_s)), MAX_CATCH_UP_S)
        count = int(self._debt_s / dt_s + 1e-9)
        self._debt_s -= count * dt_s
        last = self._last
        command = None
        for _ in range(count):
            command = self.controller.step(state, mapped_force, force_age_s, dt_s)
        self.ticks += count
        if command is not None:
            last = ControllerSnapshot(state, command.mode, command.gripper_width_m, command.rumble,
                                      command.twist, command.quit, command.stopping, count)
        else:
            last = ControllerSnapshot(state, last.mode, last.gripper_width_m, last.rumble, last.twist, last.quit,
                                      last.stopping, 0)
        self._last = last
        return last


def stick_dot_xy(center_x: float, center_y: float, radius: float, x: float, y: float) -> Tuple[float, float]:
    """SVG coordinates of a stick at (x, y): right = +x, up = +y (SVG's y grows downwards)."""
    return center_x + radius * x, center_y - radius * y


def button_roles(params: TeleopParams) -> Mapping[str, str]:
    """Positional button -> what it does in the lab ('close', 'open', 'mode', 'quit', 'deadman', 'precision')."""
    roles = {params.close_button: "close", params.open_button: "open", params.toggle_button: "mode",
             params.quit_button: "quit"}
    if params.deadman_button:
        roles[params.deadman_button] = "deadman"
    if params.precision_button:
        roles[params.precision_button] = "precision"
    return roles


def pad_svg(state: PadState, deadzone: float, roles: Mapping[str, str], width_px: int = 440) -> str:
    """The pad as an SVG: sticks as dots (red raw, blue filtered) over their dead zones, buttons lit when held."""
    dz = check_deadzone(deadzone)
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 480 210" width="{int(width_px)}" '
             'class="hri-pad" font-family="sans-serif" font-size="11">',
             '<rect x="2" y="2" width="476" height="206" rx="40" fill="#f4f4f4" stroke="#999"/>']
    radius = 42.0
    for side, cx, cy in (("left", 130.0, 135.0), ("right", 320.0, 135.0)):
        x, y = state.axis(side + "_x"), state.axis(side + "_y")
        fx, fy = normalize_analog_input(x, dz), normalize_analog_input(y, dz)
        rx, ry = stick_dot_xy(cx, cy, radius, x, y)
        bx, by = stick_dot_xy(cx, cy, radius, fx, fy)
        half = radius * dz
        parts += [
            f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="{radius:.1f}" fill="white" stroke="#666"/>',
            f'<rect x="{cx - half:.1f}" y="{cy - radius:.1f}" width="{2 * half:.1f}" height="{2 * radius:.1f}" '
            'fill="orange" fill-opacity="0.2"/>',
            f'<rect x="{cx - radius:.1f}" y="{cy - half:.1f}" width="{2 * radius:.1f}" height="{2 * half:.1f}" '
            'fill="orange" fill-opacity="0.2"/>',
            f'<circle class="stick-{side}-raw" cx="{rx:.1f}" cy="{ry:.1f}" r="7" fill="none" stroke="#d62728" '
            'stroke-width="2"/>',
            f'<circle class="stick-{side}" cx="{bx:.1f}" cy="{by:.1f}" r="5" fill="#1f77b4"/>',
            f'<text x="{cx:.1f}" y="{cy + radius + 14:.1f}" text-anchor="middle">{side} stick '
            f'({x:+.2f}, {y:+.2f})</text>',
        ]
    positions = {"north": (410.0, 36.0), "east": (436.0, 62.0), "south": (410.0, 88.0), "west": (384.0, 62.0)}
    for name, (bx, by) in positions.items():
        held = state.pressed(name)
        role = roles.get(name, "")
        parts += [
            f'<circle class="button-{name}{" held" if held else ""}" cx="{bx}" cy="{by}" r="12" '
            f'fill="{"#2ca02c" if held else "white"}" stroke="#444"/>',
            f'<text x="{bx}" y="{by + 4}" text-anchor="middle" fill="{"white" if held else "#222"}">'
            f'{_SYMBOLS[name]}</text>',
        ]
        if role:
            anchor = {"west": "end", "east": "start"}.get(name, "middle")
            tx = bx + {"west": -16, "east": 16}.get(name, 0)
            ty = by + {"north": -16, "south": 24}.get(name, 4)
            parts.append(f'<text x="{tx}" y="{ty}" text-anchor="{anchor}" fill="#555">{html.escape(role)}</text>')
    for name, x0 in (("l1", 100.0), ("r1", 290.0)):
        held = state.pressed(name)
        role = roles.get(name, "")
        parts.append(f'<rect class="button-{name}{" held" if held else ""}" x="{x0}" y="5" width="60" height="14" '
                     f'rx="5" fill="{"#2ca02c" if held else "white"}" stroke="#444"/>')
        parts.append(f'<text x="{x0 + 30}" y="16" text-anchor="middle" font-size="9">{name.upper()}'
                     f'{" " + html.escape(role) if role else ""}</text>')
    if not state.connected:
        parts.append('<text x="240" y="60" text-anchor="middle" fill="#b00020" font-size="14">pad disconnected</text>')
    parts.append("</svg>")
    return "".join(parts)


def open_pad(source: Any = "auto", layout: Any = None) -> Tuple[Gamepad, str]:
    """(pad, one line about it) for ``source`` 'auto' | 'pygame' | 'virtual' | 'browser' | a Gamepad object.

    'auto' opens the first real pad and falls back to the virtual pad when none is
    plugged in (or pygame cannot start); 'pygame' raises GamepadError instead; 'browser'
    reads the gamepad of the notebook's page (its widget: the pad's ``widget``).
    """
    choices = "'auto', 'pygame', 'virtual', 'browser' or a gamepad"
    if not isinstance(source, str):
        if not hasattr(source, "poll"):
            raise WidgetError(f"source must be {choices}, got {source!r}")
        return source, f"pad: {getattr(source, 'name', type(source).__name__)}"
    if source == "virtual":
        return VirtualPad(layout), "virtual pad: drive it with the sliders and buttons below"
    if source == "browser":
        from hri_teleop.course.widgets.browser_pad import BrowserGamepad  # noqa: PLC0415 - anywidget's page

        return BrowserGamepad(layout), "the gamepad of this browser page: press a button on it"
    if source not in ("auto", "pygame"):
        raise WidgetError(f"source must be {choices}, got {source!r}")
    try:
        pad = open_gamepad("pygame", layout)
    except GamepadError as exc:
        if source == "pygame":
            raise
        reason = str(exc).split(":")[0]
        return VirtualPad(layout), (f"{reason}: using the virtual pad (drive it below); plug a pad in and run "
                                    "the cell again to use it")
    reason = getattr(pad, "layout_reason", "")
    return pad, (f"gamepad {getattr(pad, 'name', '')!r}, layout {pad.layout.name}" + (f" ({reason})" if reason else "")
                 + " (move the sticks, press the buttons)")


def rumble_cue(pad: Any, feedback: bool = True) -> str:
    """The start check of a real pad's rumble, as the node runs it: '' if accepted (or not checkable), else why."""
    return check_pad_rumble(pad, feedback) or ""


class ControllerView(widgets.VBox):
    """The pad (sticks, buttons) and the controller's mode, gripper width, twist and rumble, live.

    ``source``: 'auto' (a real pad if one is plugged in, else the virtual pad), 'pygame',
    'virtual', 'browser' (the gamepad of this page, e.g. in the container), or a Gamepad.
    ``config``: a TeleopConfig or a teleop YAML path (default: the lab's). The ``force`` slider
    stands for ``/force_mapped`` (the piston) and drives the rumble. Call :meth:`close` to stop it
    (a real pad is released). ``clock``: the monotonic clock of the ticks and buttons (tests).
    """

    def __init__(self, source: Any = "auto", *, config: Any = None, layout: Any = None, interval_s: float = 0.05,
                 autostart: bool = True, clock: Callable[[], float] = time.monotonic) -> None:
        cfg = lab_teleop_config(config)
        self.params = cfg.params
        self.pad, note = open_pad(source, layout if layout is not None else cfg.layout)
        self.virtual = isinstance(self.pad, VirtualPad)
        self.model = ControllerModel(self.pad, cfg.params, cfg.limits)
        self._rumble = RumbleRequests()
        self._roles = button_roles(cfg.params)
        self._taps: Set[str] = set()
        self._clock = clock
        self._last_s = clock()

        style = {"description_width": "60px"}
        self.sticks = {axis: widgets.FloatSlider(value=0.0, min=-1.0, max=1.0, step=0.01, description=axis,
                                                 disabled=not self.virtual, continuous_update=True, style=style,
                                                 layout=widgets.Layout(width="260px"))
                       for axis in STICK_AXES}
        p = cfg.params
        # Held only while the pointer holds them (a toggle latched: the gripper closed to 0 mm).
        self.hold_buttons = {name: HoldButton(f"{_SYMBOLS.get(name, name)} {role} (hold)", disabled=not self.virtual,
                                              tooltip=BUTTON_LABELS[name], clock=clock)
                             for name, role in ((p.close_button, "close"), (p.open_button, "open"))}
        self.tap_buttons = {name: widgets.Button(description=f"{_SYMBOLS.get(name, name)} {role}",
                                                 disabled=not self.virtual, tooltip=BUTTON_LABELS[name])
                            for name, role in ((p.toggle_button, "mode"), (p.quit_button, "quit"))}
        self.force = widgets.FloatSlider(value=0.0, min=0.0, max=1.0, step=0.01, description="/force_mapped",
                                         style={"description_width": "100px"}, layout=widgets.Layout(width="360px"))
        self.reset_button = widgets.Button(description="reset controller", button_style="warning")
        self.svg = widgets.HTML()
        self.mode_label = widgets.HTML()
        self.width_bar = widgets.FloatProgress(min=0.0, max=GRIPPER_MAX_WIDTH_M, description="gripper",
                                               style={"description_width": "60px"})
        self.width_label = widgets.Label()
        self.rumble_bar = widgets.FloatProgress(min=0.0, max=1.0, description="rumble", bar_style="danger",
                                                style={"description_width": "60px"})
        self.rumble_label = widgets.Label()
        self.twist_label = widgets.HTML()
        cue = rumble_cue(self.pad, cfg.params.feedback)  # a pad that refuses rumble: said in red, at once
        self.status = widgets.HTML(message_html(note) + ("<br>" + message_html(cue, error=True) if cue else ""))

        for axis, slider in self.sticks.items():
            slider.observe(self._stick_moved(axis), names="value")
        for name, button in self.tap_buttons.items():
            button.on_click(self._tapped(name))
        self.reset_button.on_click(lambda _b: self.reset())

        state_box = widgets.VBox([self.mode_label, widgets.HBox([self.width_bar, self.width_label]),
                                  widgets.HBox([self.rumble_bar, self.rumble_label]), self.twist_label])
        drive = widgets.VBox([
            widgets.HBox([self.sticks["left_x"], self.sticks["left_y"]]),
            widgets.HBox([self.sticks["right_x"], self.sticks["right_y"]]),
            widgets.HBox(list(self.hold_buttons.values()) + list(self.tap_buttons.values())),
            widgets.HBox([self.force, self.reset_button]),
        ])
        page_pad = getattr(self.pad, "widget", None)  # the browser's gamepad: its page part reads the pad
        super().__init__([self.status] + ([page_pad] if page_pad is not None else [])
                         + [widgets.HBox([self.svg, state_box]), drive])
        replace_in_cell(self)
        self.ticker = Ticker(self.tick, interval_s, name="controller view")
        self.tick()
        if autostart:
            self.ticker.start()

    # -- driving the virtual pad ----------------------------------------------------------
    def _stick_moved(self, axis: str) -> Any:
        def changed(change: Any) -> None:
            if self.virtual:
                self.pad.set_axis(axis, change["new"])  # type: ignore[attr-defined]
        return changed

    def _tapped(self, name: str) -> Any:
        def clicked(_button: Any) -> None:
            if self.virtual:
                self.pad.press(name)  # type: ignore[attr-defined]
                self._taps.add(name)  # released once the controller has seen it (next tick)
        return clicked

    # -- the loop -------------------------------------------------------------------------
    def tick(self) -> ControllerSnapshot:
        """Advance the controller by the time since the last tick and show the result."""
        now = self._clock()
        if self.virtual:
            for name, button in self.hold_buttons.items():
                if name not in self._taps:  # a tap of the same button waits for its tick
                    (self.pad.press if button.take_press(now) else self.pad.release)(name)  # type: ignore[attr-defined]
        snap = self.model.advance(now - self._last_s, self.force.value, 0.0)
        self._last_s = now
        if snap.ticks and self._taps and self.virtual:
            for name in self._taps:
                self.pad.release(name)  # type: ignore[attr-defined]
            self._taps.clear()
        if not self.virtual:
            request = self._rumble.update(snap.rumble, now)
            if request is not None:
                self.pad.rumble(*request)
            for axis, slider in self.sticks.items():
                slider.value = round(snap.pad.axis(axis), 2)
            for name, button in self.hold_buttons.items():
                button.lit = snap.pad.pressed(name)
        self._show(snap)
        return snap

    def _show(self, snap: ControllerSnapshot) -> None:
        self.svg.value = pad_svg(snap.pad, self.params.deadzone, self._roles)
        toggle = _SYMBOLS.get(self.params.toggle_button, self.params.toggle_button)
        self.mode_label.value = (f"<b>mode: {snap.mode.value}</b> ({toggle} switches)"
                                 + (" &mdash; <b>quit</b>: ramping to rest; reset to start again" if snap.quit else ""))
        self.width_bar.value = snap.gripper_width_m
        self.width_label.value = f"{snap.gripper_width_m * 1000:.1f} mm"
        self.rumble_bar.value = snap.rumble
        self.rumble_label.value = f"{snap.rumble:.2f}"
        v, w = snap.twist[:3], snap.twist[3:]
        self.twist_label.value = ("<code>v = (" + ", ".join(f"{c:+.3f}" for c in v) + ") m/s<br>w = ("
                                  + ", ".join(f"{c:+.3f}" for c in w) + ") rad/s</code>")

    def reset(self) -> None:
        """A fresh controller (translation, open gripper, quit cleared); the virtual pad is released."""
        if self.virtual:
            self.pad.reset()  # type: ignore[attr-defined]
            for slider in self.sticks.values():
                slider.value = 0.0
            for button in self.hold_buttons.values():
                button.release()
        self.model.reset()
        self._show(self.model.advance(0.0))

    def close(self) -> None:
        """Stop the loop and release the pad (and the hold buttons' page parts)."""
        self.ticker.stop()
        try:
            self.pad.close()
        finally:
            for button in self.hold_buttons.values():
                button.close()
            super().close()
