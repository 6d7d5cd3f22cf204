"""Virtual gamepads: one driven by code (tests, notebooks, a /joy subscriber), one by a script.

Students prepare at home without a pad, the integration tests need a pad that does the
same thing every run, and the grader needs to know what the node asked the pad to do.
``VirtualPad`` keeps a logical state that code changes (``set_axis``, ``press``, ...)
and records every rumble it is given. ``ScriptedPad`` replays a YAML script of timed
steps::

    - {t: 0.5, axis: left_y, value: 0.8}     # push the left stick up
    - {t: 1.0, press: south}                 # hold cross / A ...
    - {t: 2.0, release: south}               # ... and let go
    - {t: 2.5, press: [north, l1]}           # several buttons at once
    - {t: 3.0, disconnect: true}             # pad unplugged
    - {t: 4.0, reconnect: true}
    - {t: 5.0, fail: true}                   # reading the pad fails (poll raises) ...
    - {t: 6.0, recover: true}                # ... until it recovers

``t`` is seconds since the script started (the first ``poll``), never decreasing.
The file may also be a mapping ``{description: ..., steps: [...]}``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

from ..checks import is_number
from ..yamlfile import read_yaml
from .layout import Layout, as_layout
from .state import (AXES, BUTTONS, TRIGGER_AXES, GamepadError, PadState, check_axis_value,
                    clean_duration, clean_intensity, unknown_axis_error, unknown_button_error)

__all__ = ["RumbleRecord", "VirtualPad", "ScriptStep", "ScriptedPad", "load_script", "parse_script"]

Clock = Callable[[], float]


@dataclass(frozen=True)
class RumbleRecord:
    """One rumble request as the pad received it (intensity already clipped to 0..1)."""

    time_s: float
    intensity: float
    duration_s: float


class VirtualPad:
    """A pad whose state is set by code; implements the Gamepad protocol.

    ``layout`` only matters for ``set_raw`` and for the node's /joy message (raw order);
    the logical state does not depend on it.
    """

    def __init__(self, layout: Union[Layout, str, None] = None, name: str = "virtual", *,
                 clock: Clock = time.monotonic) -> None:
        self.name = name
        self._layout = as_layout(layout)
        self._clock = clock
        self._axes: Dict[str, float] = {axis: 0.0 for axis in AXES}
        self._buttons: Dict[str, bool] = {button: False for button in BUTTONS}
        self._connected = True
        self._closed = False
        self._failing = False
        self.rumbles: List[RumbleRecord] = []

    # -- Gamepad protocol ------------------------------------------------------------
    @property
    def layout(self) -> Layout:
        return self._layout

    def poll(self) -> PadState:
        """The current state; a disconnected or closed pad reads neutral with connected=False."""
        if self._failing:
            raise GamepadError("virtual pad: reading failed (simulated by fail_reads); call recover_reads()")
        if not self._connected or self._closed:
            return PadState.neutral(connected=False)
        return PadState(self._axes, self._buttons, True)

    def rumble(self, intensity: float, duration_s: float) -> None:
        """Record the request (time from the pad's clock); intensity is clipped to 0..1."""
        self.rumbles.append(RumbleRecord(float(self._clock()), clean_intensity(intensity),
                                         clean_duration(duration_s)))

    def close(self) -> None:
        self._closed = True

    def __enter__(self) -> "VirtualPad":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- driving it ----------------------------------------------------------------------
    @property
    def connected(self) -> bool:
        return self._connected

    def set_axis(self, name: str, value: float) -> None:
        """Move a stick (-1..1, right/up = +1) or a trigger (0 released .. 1 pulled)."""
        if name not in AXES:
            raise unknown_axis_error(name)
        self._axes[name] = check_axis_value(name, value)

    def press(self, name: str) -> None:
        """Hold a button down (positional name: south = cross/A, ...)."""
        self._buttons[self._button(name)] = True

    def release(self, name: str) -> None:
        self._buttons[self._button(name)] = False

    def reset(self) -> None:
        """Centre the sticks, release the triggers and every button."""
        self._axes = {axis: 0.0 for axis in AXES}
        self._buttons = {button: False for button in BUTTONS}

    def set_raw(self, axes: Sequence[float], buttons: Sequence[Union[int, bool]]) -> None:
        """Set the whole state from raw values in the layout's order (e.g. a sensor_msgs/Joy)."""
        state = self._layout.state_from_raw(axes, buttons)
        self._axes.update(state.axes)
        self._buttons.update(state.buttons)

    def disconnect(self) -> None:
        """Pretend the pad was unplugged: poll() reports connected=False until reconnect()."""
        self._connected = False

    def reconnect(self) -> None:
        self._connected = True

    def fail_reads(self) -> None:
        """Make poll() raise GamepadError, as a pad whose device cannot be read does."""
        self._failing = True

    def recover_reads(self) -> None:
        self._failing = False

    @staticmethod
    def _button(name: str) -> str:
        if name not in BUTTONS:
            raise unknown_button_error(name)
        return name


# --------------------------------------------------------------------------- scripts

@dataclass(frozen=True)
class ScriptStep:
    """One timed action: ``action`` is axis, press, release, disconnect or reconnect."""

    t: float
    action: str
    target: Tuple[str, ...] = ()   # axis name, or button names
    value: float = 0.0             # axis value


_ACTIONS = ("axis", "press", "release", "disconnect", "reconnect", "fail", "recover")
_STEP_KEYS = ("t", "value") + _ACTIONS
_EXAMPLE = "e.g. '- {t: 1.0, press: south}'"


def _number(value: Any) -> Optional[float]:
    return float(value) if is_number(value, numpy=True) else None


def parse_script(data: Any, source: str = "<script>") -> List[ScriptStep]:
    """Check parsed YAML and turn it into steps; each problem is one line naming source and step."""
    if isinstance(data, dict) and "steps" in data:
        extra = [k for k in data if k not in ("steps", "description")]
        if extra:
            raise GamepadError("%s: unknown key %r; a script mapping has only 'description' and "
                               "'steps'" % (source, extra[0]))
        data = data["steps"]
    if not isinstance(data, list) or not data:
        raise GamepadError("%s: expected a non-empty list of steps; write one step per line, %s"
                           % (source, _EXAMPLE))
    steps: List[ScriptStep] = []
    previous_t = 0.0
    for number, raw in enumerate(data, start=1):
        def fail(problem: str, fix: str) -> GamepadError:
            return GamepadError("%s: step %d: %s; %s" % (source, number, problem, fix))

        if not isinstance(raw, dict):
            raise fail("expected a mapping, found %r" % (raw,), "write it as {t: 1.0, press: south}")
        unknown = [k for k in raw if k not in _STEP_KEYS]
        if unknown:
            raise fail("unknown key %r" % (unknown[0],), "use t plus one of %s" % ", ".join(_ACTIONS))
        t = _number(raw.get("t"))
        if t is None or not 0.0 <= t < float("inf"):
            raise fail("t is %r" % (raw.get("t"),), "give the time in seconds since the start, a number >= 0")
        if t < previous_t:
            raise fail("t=%g comes before the previous step's t=%g" % (t, previous_t),
                       "sort the steps by time")
        previous_t = t
        actions = [k for k in _ACTIONS if k in raw]
        if len(actions) != 1:
            raise fail("found %s" % (" and ".join(actions) if actions else "no action"),
                       "give exactly one of %s per step" % ", ".join(_ACTIONS))
        action = actions[0]
        if "value" in raw and action != "axis":
            raise fail("'value' belongs to an axis step", "remove it or write {t: ..., axis: left_y, value: 0.5}")
        if action == "axis":
            name = raw["axis"]
            if name not in AXES:
                raise fail("unknown axis %r" % (name,), "use one of %s" % ", ".join(AXES))
            value = _number(raw.get("value"))
            low = 0.0 if name in TRIGGER_AXES else -1.0
            if value is None or not low <= value <= 1.0:
                raise fail("axis %s value is %r" % (name, raw.get("value")),
                           "give a number in %g..1 (sticks: right/up = +1)" % low)
            steps.append(ScriptStep(t, "axis", (name,), value))
        elif action in ("press", "release"):
            names = raw[action]
            names = [names] if isinstance(names, str) else names
            if not isinstance(names, list) or not names:
                raise fail("%s is %r" % (action, raw[action]), "give a button name or a list of them")
            for name in names:
                if name not in BUTTONS:
                    raise fail("unknown button %r" % (name,),
                               "use a positional name, one of %s (south = cross/A, east = circle/B, "
                               "west = square/X, north = triangle/Y)" % ", ".join(BUTTONS))
            steps.append(ScriptStep(t, action, tuple(names)))
        else:
            if raw[action] is not True:
                raise fail("%s is %r" % (action, raw[action]), "write '%s: true'" % action)
            steps.append(ScriptStep(t, action))
    return steps


def load_script(path: Union[str, Path]) -> List[ScriptStep]:
    """Read and check a pad script; errors are one line naming the file, the step and the fix."""
    source = str(path)
    data = read_yaml(source, GamepadError, what="pad script",
                     missing_fix="check the path (it is relative to the directory the node was "
                                 "started from)")
    return parse_script(data, source)


class ScriptedPad(VirtualPad):
    """A VirtualPad that replays timed steps; time starts at the first poll() (or advance())."""

    def __init__(self, steps: Union[Sequence[ScriptStep], str, Path],
                 layout: Union[Layout, str, None] = None, name: str = "scripted", *,
                 clock: Clock = time.monotonic) -> None:
        super().__init__(layout, name, clock=clock)
        if isinstance(steps, (str, Path)):
            steps = load_script(steps)
        self.steps: Tuple[ScriptStep, ...] = tuple(steps)
        self._next = 0
        self._start_s: Optional[float] = None

    @property
    def finished(self) -> bool:
        """True once every step has been applied."""
        return self._next >= len(self.steps)

    def start(self, now_s: Optional[float] = None) -> None:
        """Set the script's time zero (default: the clock now); poll() calls it if you do not."""
        self._start_s = float(self._clock() if now_s is None else now_s)

    def advance(self, elapsed_s: float) -> int:
        """Apply every step due at ``elapsed_s`` seconds into the script; returns how many."""
        applied = 0
        while self._next < len(self.steps) and self.steps[self._next].t <= elapsed_s:
            self._apply(self.steps[self._next])
            self._next += 1
            applied += 1
        return applied

    def poll(self) -> PadState:
        if self._start_s is None:
            self.start()
        assert self._start_s is not None
        self.advance(float(self._clock()) - self._start_s)
        return super().poll()

    def _apply(self, step: ScriptStep) -> None:
        if step.action == "axis":
            self.set_axis(step.target[0], step.value)
        elif step.action == "press":
            for name in step.target:
                self.press(name)
        elif step.action == "release":
            for name in step.target:
                self.release(name)
        elif step.action == "disconnect":
            self.disconnect()
        elif step.action == "fail":
            self.fail_reads()
        elif step.action == "recover":
            self.recover_reads()
        else:
            self.reconnect()
