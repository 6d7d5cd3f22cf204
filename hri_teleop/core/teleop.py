"""The teleoperation rules of handout Ex. 8 as a pure controller: pad in, robot command out.

The same rules run in the lab's node, the notebooks, the grader and the tests, so
:class:`TeleopController` has no clock, no rospy and no pygame: each ``step`` gets the pad's
state, the latest mapped force with its age and the time step, and returns a
:class:`TeleopCommand`. The rules themselves (sticks, mode toggle, gripper steps, quit, limiter,
rumble) are listed in docs/teleoperation.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from enum import Enum
from typing import Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gamepad import AXES, BUTTONS, PadState, normalize_analog_input
from hri_teleop.core.gamepad.rumble import unit_intensity
from hri_teleop.core.gamepad.stale import STALE_INPUT_TIMEOUT_S
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.core.limits import (
    DEFAULT_LIMITS,
    ROBOT_LIMITS,
    CartesianLimits,
    LimitsError,
    Twist,
    TwistLimiter,
    check_command_rate,
)

__all__ = [
    "TeleopError",
    "Mode",
    "AxisAssignment",
    "DEFAULT_AXIS_ASSIGNMENT",
    "GRIPPER_MAX_WIDTH_M",
    "TeleopParams",
    "TeleopCommand",
    "TeleopController",
    "next_tick_s",
    "combined_rumble",
    "motor_rumble",
    "RUMBLE_MOTORS",
    "HANDOUT_BUTTONS",
    "OPTIONAL_BUTTONS",
    "check_extra_button",
    "recovery_refusal",
    "ButtonPress",
]

#: The Franka Hand opens from 0 to 0.08 m (docs/lab-facts.md; the robot profile's gripper.max_width_m).

_ZERO_TWIST: Twist = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
#: How the pad's two rumble motors are used (TeleopParams.rumble_motors; motor_rumble).
RUMBLE_MOTORS = ("split", "combined")
#: The handout's buttons, each always set (TeleopParams fields).
HANDOUT_BUTTONS = ("close_button", "open_button", "toggle_button", "quit_button")
#: The buttons a configuration may leave out ("" = none).
OPTIONAL_BUTTONS = ("deadman_button", "precision_button")


class TeleopError(HriTeleopError, ValueError):
    """A teleoperation parameter is invalid (one line: which, what was found, the fix)."""


class Mode(str, Enum):
    """What the sticks drive: the linear (m/s) or the angular (rad/s) half of the twist."""

    TRANSLATION = "translation"
    ROTATION = "rotation"


def _parse_source(entry: object, where: str) -> Tuple[Optional[str], float]:
    """``"left_y"`` / ``"+left_y"`` -> (left_y, +1), ``"-left_x"`` -> (left_x, -1), ``"none"`` -> (None, 0)."""
    if not isinstance(entry, str):
        raise TeleopError(
            f"{where} must be a stick axis name such as 'left_y' or '-left_x' (or 'none'), got {entry!r}; "
            f"use one of {', '.join(AXES)} with an optional sign"
        )
    text = entry.strip()
    if text.lower() in ("none", "0", ""):
        return None, 0.0
    sign = 1.0
    if text[0] in "+-":
        sign = -1.0 if text[0] == "-" else 1.0
        text = text[1:].strip()
    if text not in AXES:
        raise TeleopError(
            f"{where} names unknown axis {entry!r}; use one of {', '.join(AXES)} with an optional sign, e.g. '-left_x', or 'none'"
        )
    return text, sign


@dataclass(frozen=True)
class AxisAssignment:
    """Which pad axis drives which twist component, per mode.

    Each mode has three entries for (x, y, z): an axis name from
    :data:`hri_teleop.core.gamepad.AXES` with an optional sign (``"-left_x"`` inverts it) or
    ``"none"``.  Sticks read +1 to the right and +1 up.

    The default, with the robot's base frame (x forward away from the base, y to the
    left, z up) and the operator standing behind the robot looking along +x:

    * translation: vx <- left_y (stick up = forward), vy <- -left_x (stick right = to the
      right = -y), vz <- right_y (right stick up = up);
    * rotation: the same sticks turn *about* the axis they move along in translation,
      wx <- left_y, wy <- -left_x, wz <- right_y, so one rule covers both modes.

    Lists from YAML are accepted and stored as tuples.
    """

    translation: Tuple[str, str, str] = ("left_y", "-left_x", "right_y")
    rotation: Tuple[str, str, str] = ("left_y", "-left_x", "right_y")

    def __post_init__(self) -> None:
        for mode in Mode:
            entries = getattr(self, mode.value)
            if isinstance(entries, str) or not hasattr(entries, "__len__") or len(entries) != 3:
                raise TeleopError(
                    f"axes.{mode.value} must list 3 axes for x, y, z, got {entries!r}; "
                    "write e.g. [left_y, -left_x, right_y]"
                )
            for index, entry in enumerate(entries):
                _parse_source(entry, f"axes.{mode.value}[{index}]")
            object.__setattr__(self, mode.value, tuple(entries))

    def sources(self, mode: Mode) -> Tuple[Tuple[Optional[str], float], ...]:
        """((axis or None, sign), ...) for x, y, z of ``mode``."""
        return tuple(_parse_source(e, f"axes.{Mode(mode).value}[{i}]") for i, e in enumerate(getattr(self, Mode(mode).value)))

    def axes_used(self) -> Tuple[str, ...]:
        """The pad axes that drive the twist in either mode, in AXES order."""
        used = {axis for mode in Mode for axis, _sign in self.sources(mode) if axis is not None}
        return tuple(a for a in AXES if a in used)


DEFAULT_AXIS_ASSIGNMENT = AxisAssignment()


@dataclass(frozen=True)
class TeleopParams:
    """Every number of the teleoperation rules, with the lab's defaults (units in the names).

    ``input_timeout_s`` is for the node: it feeds a :class:`~hri_teleop.core.limits.Watchdog`
    with every fresh pad reading and passes ``pad=None`` once the pad has been silent
    this long.  ``force_timeout_s`` is applied here, to the age passed to ``step``.
    """

    rate_hz: float = 50.0
    k_trans: float = 0.1  # m/s at full stick
    k_rot: float = 0.3  # rad/s at full stick
    k_gripper: float = 0.04  # m/s: the width changes by k_gripper / rate_hz per tick while held
    deadzone: float = 0.1  # fraction of full stick travel
    width_min_m: float = 0.0
    width_max_m: float = GRIPPER_MAX_WIDTH_M
    initial_width_m: float = GRIPPER_MAX_WIDTH_M
    input_timeout_s: float = 0.5  # pad silent/lost this long -> ramp to zero
    # A held stick whose readings stay bit for bit the same this long -> the pad counts as lost
    # (a wireless pad that dropped out without a removal event); 0 = off. core.gamepad.stale.
    stale_input_timeout_s: float = STALE_INPUT_TIMEOUT_S
    force_timeout_s: float = 1.0  # mapped force older than this -> rumble 0 (> 3 periods of the handout's 300 ms firmware)
    rumble_threshold: float = 0.01  # mapped force at or below this -> no rumble (above ADC noise at rest: 7 of 700 counts)
    assignment: AxisAssignment = field(default_factory=AxisAssignment)
    close_button: str = "south"
    open_button: str = "east"
    toggle_button: str = "north"
    quit_button: str = "west"
    # Optional dead-man switch (teleop_twist_joy's enable_button): "" = none, as in the
    # handout; e.g. "l1" = the arm moves only while L1 is held. Recommended for wireless
    # pads, which can keep their last reading for seconds when the link drops.
    deadman_button: str = ""
    # Force feedback on (the lab) or off (the control condition of Ex. 14's experiment):
    # off, the pad never rumbles; everything else is the same.
    feedback: bool = True
    # Optional precision button: while held, the gains k_trans and k_rot are scaled by
    # precision_scale (through the limiter: a press ramps, never jumps). "" = none.
    precision_button: str = ""
    precision_scale: float = 0.3
    # Two rumble motors: "split" = the force on the low-frequency (strong, left) motor, the joint
    # warning on the high-frequency (weak, right) one; "combined" = both feel the larger (one motor).
    rumble_motors: str = "split"
    # How wide the robot's hand opens (m): its robot profile's gripper.max_width_m (the Panda's 0.08).
    gripper_max_width_m: float = GRIPPER_MAX_WIDTH_M

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("assignment", "rumble_motors") or f.name.endswith("_button"):
                continue
            if f.name == "feedback":
                if not isinstance(value, bool):
                    raise TeleopError(f"feedback must be true or false, got {value!r}; write feedback: true (rumble on) "
                                      "or feedback: false (the experiment's control condition)")
                continue
            if not is_finite_number(value):
                raise TeleopError(f"{f.name} must be a finite number, got {value!r}; set it in the teleop config")
            object.__setattr__(self, f.name, float(value))
        p = self
        if p.rate_hz <= 0:
            raise TeleopError(f"rate_hz must be > 0 Hz, got {p.rate_hz!r}; the lab runs at 50")
        for name in ("k_trans", "k_rot", "k_gripper"):
            if getattr(p, name) < 0:
                raise TeleopError(f"{name} must be >= 0, got {getattr(p, name)!r}; use the axis assignment to invert a direction")
        if not 0.0 <= p.deadzone < 1.0:
            raise TeleopError(f"deadzone must be in [0, 1), got {p.deadzone!r}; 0.1 ignores the first tenth of stick travel")
        if not p.gripper_max_width_m > 0.0:
            raise TeleopError(f"gripper_max_width_m must be > 0 m, got {p.gripper_max_width_m!r}; the Franka Hand's is 0.08")
        if not 0.0 <= p.width_min_m <= p.width_max_m <= p.gripper_max_width_m:
            raise TeleopError(
                f"gripper widths must satisfy 0 <= width_min_m <= width_max_m <= {p.gripper_max_width_m:g} m, "
                f"got {p.width_min_m!r} .. {p.width_max_m!r}; the robot's hand opens 0 .. {p.gripper_max_width_m:g} m"
            )
        if not p.width_min_m <= p.initial_width_m <= p.width_max_m:
            raise TeleopError(
                f"initial_width_m must lie in {p.width_min_m} .. {p.width_max_m} m, got {p.initial_width_m!r}; e.g. 0.08 (open)"
            )
        for name in ("input_timeout_s", "force_timeout_s"):
            if getattr(p, name) <= 0:
                raise TeleopError(f"{name} must be > 0 s, got {getattr(p, name)!r}; e.g. 0.5")
        if p.stale_input_timeout_s < 0:
            raise TeleopError(f"stale_input_timeout_s must be >= 0 s (0: off), got {p.stale_input_timeout_s!r}; e.g. 1.0")
        if not 0.0 < p.precision_scale <= 1.0:
            raise TeleopError(f"precision_scale must be in (0, 1], got {p.precision_scale!r}; e.g. 0.3 (a third of the gains)")
        if p.rumble_motors not in RUMBLE_MOTORS:
            raise TeleopError(f"rumble_motors must be one of {', '.join(RUMBLE_MOTORS)}, got {p.rumble_motors!r}; "
                              "split for a pad with two motors, combined for one")
        if not 0.0 <= p.rumble_threshold <= 1.0:
            raise TeleopError(f"rumble_threshold must be in [0, 1] (mapped force), got {p.rumble_threshold!r}; e.g. 0.05")
        if not isinstance(p.assignment, AxisAssignment):
            raise TeleopError(f"assignment must be an AxisAssignment, got {type(p.assignment).__name__}; build one with AxisAssignment(...)")
        for name in HANDOUT_BUTTONS:
            if getattr(p, name) not in BUTTONS:
                raise TeleopError(f"{name} must be a positional button name, got {getattr(p, name)!r}; use one of {', '.join(BUTTONS)}")
        for name in OPTIONAL_BUTTONS:
            if getattr(p, name) and getattr(p, name) not in BUTTONS:
                raise TeleopError(f"{name} must be empty or a positional button name, got {getattr(p, name)!r}; "
                                  f"use one of {', '.join(BUTTONS)}, e.g. l1")
        chosen = [getattr(p, name) for name in HANDOUT_BUTTONS + OPTIONAL_BUTTONS if getattr(p, name)]
        if len(set(chosen)) != len(chosen):
            raise TeleopError(f"close, open, toggle, quit (and deadman, precision) need different buttons, got {chosen}; "
                              "change the buttons")

    @property
    def gripper_step_m(self) -> float:
        """Width change per tick while a gripper button is held: ``k_gripper / rate_hz``."""
        return self.k_gripper / self.rate_hz


@dataclass(frozen=True)
class TeleopCommand:
    """One tick's output.

    ``twist`` is (vx, vy, vz) in m/s and (wx, wy, wz) in rad/s in the robot's base frame,
    after the limiter; ``rumble`` is 0..1; ``stopping`` is True while the twist is being
    ramped to zero because the pad is lost or the operator quit.
    """

    twist: Twist
    gripper_width_m: float
    rumble: float
    quit: bool
    mode: Mode
    stopping: bool


class TeleopController:
    """Handout Ex. 8 as a state machine (mode, gripper width, quit) plus the twist limiter."""

    def __init__(self, params: Optional[TeleopParams] = None, limits: CartesianLimits = DEFAULT_LIMITS,
                 hard_limits: CartesianLimits = ROBOT_LIMITS) -> None:
        """``hard_limits``: the robot's (its profile's), which ``limits`` must stay inside."""
        self._params = params if params is not None else TeleopParams()
        if not isinstance(self._params, TeleopParams):
            raise TeleopError(f"params must be a TeleopParams, got {type(self._params).__name__}; build one with TeleopParams(...)")
        try:
            self._limiter = TwistLimiter(limits, hard_limits=hard_limits)
            check_command_rate(self._limiter.limits, self._params.rate_hz, hard=hard_limits)
        except LimitsError as exc:
            raise TeleopError(str(exc)) from None
        self._mode = Mode.TRANSLATION
        self._width_m = self._params.initial_width_m
        self._quit = False
        self._toggle_was_pressed = False
        self._stopping = True  # until the first tick: no rumble before the node has run once

    # -- state ------------------------------------------------------------------------

    @property
    def params(self) -> TeleopParams:
        return self._params

    @property
    def limits(self) -> CartesianLimits:
        return self._limiter.limits

    @property
    def mode(self) -> Mode:
        return self._mode

    @property
    def gripper_width_m(self) -> float:
        return self._width_m

    @property
    def quit(self) -> bool:
        return self._quit

    @property
    def finished(self) -> bool:
        """True once quit was pressed and the twist has ramped to exactly zero: time to exit."""
        return self._quit and all(c == 0.0 for c in self._limiter.velocity) and all(
            c == 0.0 for c in self._limiter.acceleration
        )

    # -- rules ------------------------------------------------------------------------

    def target_twist(self, pad: Optional[PadState]) -> Twist:
        """The operator's wish before limiting: sticks through the dead zone, times the gain.

        Zero for a missing or disconnected pad, and while a configured dead-man button is
        released.  Only the current mode's half is non-zero.
        """
        if pad is None or not pad.connected:
            return _ZERO_TWIST
        if self._params.deadman_button and not pad.pressed(self._params.deadman_button):
            return _ZERO_TWIST
        p = self._params
        gain = p.k_trans if self._mode is Mode.TRANSLATION else p.k_rot
        if p.precision_button and pad.pressed(p.precision_button):
            gain *= p.precision_scale
        values = []
        for axis, sign in p.assignment.sources(self._mode):
            if axis is None:
                values.append(0.0)
                continue
            raw = pad.axis(axis)
            raw = raw if math.isfinite(raw) else 0.0
            values.append(sign * gain * normalize_analog_input(raw, p.deadzone) + 0.0)  # + 0.0: no -0.0
        if self._mode is Mode.TRANSLATION:
            return (values[0], values[1], values[2], 0.0, 0.0, 0.0)
        return (0.0, 0.0, 0.0, values[0], values[1], values[2])

    def rumble_for(self, mapped_force: Optional[float], force_age_s: Optional[float]) -> float:
        """Rumble intensity 0..1 for a mapped force of a given age (s); 0 if missing, stale, below threshold or feedback off."""
        if not self._params.feedback or mapped_force is None or force_age_s is None:
            return 0.0
        try:
            force, age = float(mapped_force), float(force_age_s)
        except (TypeError, ValueError):
            return 0.0
        if math.isnan(force) or math.isnan(age) or age > self._params.force_timeout_s:
            return 0.0
        force = min(1.0, max(0.0, force))
        return force if force > self._params.rumble_threshold else 0.0

    def rumble_between_ticks(self, mapped_force: Optional[float], force_age_s: Optional[float]) -> float:
        """The rumble for a force that arrives between two ticks: :meth:`rumble_for`, or 0 while
        the last tick was stopping (pad lost, quit) or before the first tick.

        Why: the operator should feel a force as it arrives, not up to a tick later, but a
        stopped node must not start rumbling on its own.
        """
        return 0.0 if self._stopping else self.rumble_for(mapped_force, force_age_s)

    def step(
        self,
        pad: Optional[PadState],
        mapped_force: Optional[float],
        force_age_s: float,
        dt_s: float,
    ) -> TeleopCommand:
        """One control tick of ``dt_s`` seconds.

        ``mapped_force`` is the latest ``/force_mapped`` value (None if none arrived yet)
        and ``force_age_s`` its age in seconds.
        """
        if not is_finite_number(dt_s) or dt_s <= 0:
            raise TeleopError(f"dt_s must be a positive finite time step in seconds, got {dt_s!r}; pass 1/rate_hz")
        p = self._params
        connected = pad is not None and pad.connected
        if connected and not self._quit:
            assert pad is not None
            if pad.pressed(p.quit_button):
                self._quit = True
            else:
                toggle = pad.pressed(p.toggle_button)
                if toggle and not self._toggle_was_pressed:
                    self._mode = Mode.ROTATION if self._mode is Mode.TRANSLATION else Mode.TRANSLATION
                self._toggle_was_pressed = toggle
                step_m = p.gripper_step_m
                delta = (step_m if pad.pressed(p.open_button) else 0.0) - (step_m if pad.pressed(p.close_button) else 0.0)
                self._width_m = min(p.width_max_m, max(p.width_min_m, self._width_m + delta))
        stopping = self._stopping = (not connected) or self._quit
        target = _ZERO_TWIST if stopping else self.target_twist(pad)
        twist = self._limiter.step(target, float(dt_s))
        rumble = 0.0 if stopping else self.rumble_for(mapped_force, force_age_s)
        return TeleopCommand(
            twist=twist,
            gripper_width_m=self._width_m,
            rumble=rumble,
            quit=self._quit,
            mode=self._mode,
            stopping=stopping,
        )


def next_tick_s(previous_s: float, now_s: float, period_s: float) -> float:
    """When the next control tick is due (monotonic s), one period after the previous one.

    A loop that fell more than a period behind (the process was starved) starts its
    schedule again from ``now_s`` instead of firing a burst of ticks to catch up: a burst
    would hand the robot several commands at once, which the limiter treats as one step.
    """
    due = previous_s + period_s
    return due if due >= now_s - period_s else now_s


def combined_rumble(force_rumble: float, warning_rumble: float, stopping: bool, feedback: bool = True) -> float:
    """What the pad feels: the larger of the force feedback and the joint-limit warning's pulse.

    The larger, not the sum: a force still shows while the warning pulses (the pad never drops
    below the force), and the pad never goes past 1. Nothing while the controller is stopping
    (pad lost, quit), and nothing with ``feedback`` off: Ex. 14's control condition keeps a silent
    pad (the node still logs the warning). A value that is not a finite number counts as 0.
    """
    if stopping or not feedback:
        return 0.0
    return max(unit_intensity(force_rumble), unit_intensity(warning_rumble))


def motor_rumble(force_rumble: float, warning_rumble: float, stopping: bool, feedback: bool = True,
                 motors: str = "split") -> Tuple[float, float]:
    """(low-frequency, high-frequency) motor strengths 0..1: the two signals kept apart on a two-motor pad.

    ``split``: the force on the strong, low-frequency (left) motor and the joint-limit warning on the
    weak, high-frequency (right) one, so the operator can tell them apart; ``combined``: both motors
    at :func:`combined_rumble` (a pad with one motor). Silent while stopping and with feedback off.
    """
    if motors not in RUMBLE_MOTORS:
        raise TeleopError(f"motors must be one of {', '.join(RUMBLE_MOTORS)}, got {motors!r}; e.g. split")
    if motors == "combined":
        both = combined_rumble(force_rumble, warning_rumble, stopping, feedback)
        return both, both
    if stopping or not feedback:
        return 0.0, 0.0
    return unit_intensity(force_rumble), unit_intensity(warning_rumble)


def recovery_refusal(twist: Sequence[float]) -> Optional[str]:
    """Why error recovery must wait (one line), or None when the node's twist is exactly zero.

    A recovered robot starts from rest: a twist still being commanded would reach it as a step and
    stop it again at once. So the sticks are let go first and the limiter ramps the twist to zero.
    """
    moving = [c for c in twist if c != 0.0]
    if not moving:
        return None
    speed = math.sqrt(sum(c * c for c in twist[:3]))
    turn = math.sqrt(sum(c * c for c in twist[3:]))
    return (f"error recovery waits: the node still commands {speed:.3f} m/s and {turn:.3f} rad/s; let go of the "
            "sticks, then press the recover button again (a recovered robot starts from rest)")


def check_extra_button(params: TeleopParams, button: str, role: str) -> str:
    """``button`` for a node's own ``role`` (e.g. recover), checked: a positional name that none of the
    configured buttons (close, open, toggle, quit, dead-man, precision) already uses."""
    if button not in BUTTONS:
        raise TeleopError(f"{role} must be a positional button name, got {button!r}; use one of {', '.join(BUTTONS)}, "
                          "e.g. start")
    taken = {getattr(params, name): name[: -len("_button")] for name in HANDOUT_BUTTONS + OPTIONAL_BUTTONS
             if getattr(params, name)}
    if button in taken:
        raise TeleopError(f"{role} {button!r} is already the {taken[button]} button; choose another, e.g. start")
    return button


class ButtonPress:
    """One press of a button: :meth:`update` is True on the tick it goes down, once per press.

    A held button is one press; a missing or disconnected pad releases it.
    """

    def __init__(self, button: str) -> None:
        if button not in BUTTONS:
            raise TeleopError(f"button must be a positional button name, got {button!r}; use one of {', '.join(BUTTONS)}")
        self.button = button
        self._was_pressed = False

    def update(self, pad: Optional[PadState]) -> bool:
        pressed = pad is not None and pad.connected and pad.pressed(self.button)
        went_down = pressed and not self._was_pressed
        self._was_pressed = pressed
        return went_down
