"""Judging the methods students write in ``teleoperation.py`` (Ex. 8) against pad-event traces.

The node (Ex. 9) is judged in :mod:`.judge_node`.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, List, Optional, Sequence, Tuple

from hri_teleop.core.gamepad import PadState
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.core.teleop import TeleopController, TeleopParams
from hri_teleop.grading.exercises.teleoperation.cases import (
    ExpectedTick,
    TeleopPartsCase,
    reference_params,
    reference_parts,
)
from hri_teleop.grading.exercises.teleoperation.parts import PARTS
from hri_teleop.grading.judge.compare_common import (
    TWIST_TOLERANCE,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
)
from hri_teleop.grading.judge.plots import series_plot
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import (
    PartsCaseResult,
    PartsTick,
    ProcessFacts,
    TeleopPartsResult,
)

__all__ = ["compare_teleop_parts"]


# -- teleoperation.py: the student's parts (Ex. 8) ------------------------------------------

_BUTTON_WORDS = {"south": "cross", "east": "circle", "north": "triangle", "west": "square"}


def _pad_context(case: TeleopPartsCase, index: int) -> str:
    tick = case.ticks[index]
    sticks = ", ".join(f"{a} = {v:+.3g}" for a, v in tick.axes if v != 0.0) or "sticks centred"
    held = ", ".join(_BUTTON_WORDS.get(b, b) for b in sorted(tick.buttons)) or "no button held"
    return f"{sticks}; {held}"


def _case_where(case: TeleopPartsCase, index: int) -> str:
    g = case.gains
    return (f"{case.label} trace (rate {g.rate:g} Hz, k_trans {g.k_trans:g}, k_rot {g.k_rot:g}, "
            f"k_gripper {g.k_gripper:g}, deadzone {g.deadzone:g}), tick {index}")


def _method_error(result: PartsCaseResult, method: str) -> Optional[str]:
    if method in result.errors:
        return f"{method}() raised {result.errors[method]} (first at tick {result.error_ticks.get(method)})"
    return None


def _differs(value: Any, want: float, tolerance: float) -> bool:
    """The student's value is no number, or further than ``tolerance`` from ``want``."""
    number = as_float(value)
    return number is None or abs(number - want) > tolerance


def _judge_gripper(case: TeleopPartsCase, exp: List[ExpectedTick], got: List[PartsTick]) -> Tuple[bool, str, List[int]]:
    step = case.gains.k_gripper / case.gains.rate
    bad = [i for i, (e, g) in enumerate(zip(exp, got)) if _differs(g.gripper_width, e.gripper_width, 1e-9)]
    if not bad:
        return True, "", []
    i = bad[0]
    value = as_float(got[i].gripper_width)
    previous = as_float(got[i - 1].gripper_width) if i > 0 else GRIPPER_MAX_WIDTH_M
    held = case.ticks[i].buttons
    if value is None:
        hint = "self.gripper_width must stay a number in metres"
    elif value < -1e-12 or value > GRIPPER_MAX_WIDTH_M + 1e-12:
        hint = (f"keep the width within GRIPPER_MIN_WIDTH .. GRIPPER_MAX_WIDTH (0 .. {GRIPPER_MAX_WIDTH_M:g} m): "
                "clip it after the step")
    elif previous is not None and abs(abs(value - previous) - case.gains.k_gripper) <= 1e-9:
        hint = f"the width changed by k_gripper per tick; it must change by k_gripper / rate = {step:.6g} m"
    elif previous is not None and "south" in held and "east" not in held and value > previous:
        hint = "cross closes (the width gets smaller) and circle opens"
    elif previous is not None and not ({"south", "east"} & held) and value != previous:
        hint = "the width changed with no gripper button held: step only while a button is held"
    else:
        hint = f"while a button is held the width changes by k_gripper / rate = {step:.6g} m per tick"
    message = (f"{_case_where(case, i)} ({_pad_context(case, i)}): gripper_width expected {exp[i].gripper_width:.6g} m, "
               f"got {fmt_value(got[i].gripper_width)}; {len(bad)} of {len(exp)} ticks differ\nhint: {hint}")
    return False, message, bad


def _no_deadzone(gains_params: TeleopParams, mode_rotation: bool) -> TeleopController:
    params = TeleopParams(**{**{f: getattr(gains_params, f) for f in ("rate_hz", "k_trans", "k_rot", "k_gripper")},
                             "deadzone": 0.0, "rumble_threshold": 0.0})
    controller = TeleopController(params)
    if mode_rotation:
        controller.step(PadState({}, {"north": True}), None, 0.0, 1.0 / params.rate_hz)
        controller.step(PadState({}, {}), None, 0.0, 1.0 / params.rate_hz)
    return controller


def _judge_twist(case: TeleopPartsCase, exp: List[ExpectedTick], got: List[PartsTick]) -> Tuple[bool, str, List[int]]:
    bad = []
    for i, (e, g) in enumerate(zip(exp, got)):
        velocity = g.cartesian_velocity
        rotation = g.rotation_mode is True
        want = e.velocity_if_rotation if rotation else e.velocity_if_translation
        if not isinstance(velocity, list) or len(velocity) != 6 \
                or any(_differs(v, w, TWIST_TOLERANCE) for v, w in zip(velocity, want)):
            bad.append(i)
    if not bad:
        return True, "", []
    i = bad[0]
    velocity = got[i].cartesian_velocity
    rotation = got[i].rotation_mode is True
    want = exp[i].velocity_if_rotation if rotation else exp[i].velocity_if_translation
    values = [as_float(v) for v in velocity] if isinstance(velocity, list) else []
    numbers = [v for v in values if v is not None]
    mode = "rotation" if rotation else "translation"
    if len(values) != 6 or len(numbers) != 6:
        hint = "self.cartesian_velocity must be a list of 6 numbers [v_x, v_y, v_z, w_x, w_y, w_z]"
    else:
        raw = _no_deadzone(reference_params(case.gains), rotation).target_twist(case.ticks[i].state())
        active = range(3, 6) if rotation else range(0, 3)
        other = range(0, 3) if rotation else range(3, 6)
        if all(abs(v - r) <= TWIST_TOLERANCE for v, r in zip(numbers, raw)) and raw != tuple(want):
            hint = "pass every stick through self.normalize_analog_input() before the gain (the dead zone, Figure 8)"
        elif any(abs(numbers[k]) > TWIST_TOLERANCE for k in other):
            hint = f"in {mode} mode only the {mode} half of the velocity may be non-zero"
        elif all(abs(numbers[k] + want[k]) <= TWIST_TOLERANCE for k in active) and any(want[k] for k in active):
            hint = "the signs are reversed: check the controller assignment in the file's docstring"
        elif any(abs(numbers[k] + want[k]) <= TWIST_TOLERANCE and want[k] != 0 for k in active):
            wrong = [("v_x v_y v_z w_x w_y w_z".split())[k] for k in active
                     if want[k] != 0 and abs(numbers[k] + want[k]) <= TWIST_TOLERANCE]
            hint = f"{', '.join(wrong)} has the wrong sign: check the controller assignment in the file's docstring"
        else:
            gain = case.gains.k_rot if rotation else case.gains.k_trans
            other_gain = case.gains.k_trans if rotation else case.gains.k_rot
            ratios = [numbers[k] / want[k] for k in active if want[k] != 0]
            if ratios and all(abs(r - other_gain / gain) <= 1e-6 for r in ratios):
                hint = f"use k_rot in rotation mode and k_trans in translation mode (this is {mode} mode)"
            else:
                hint = ("v_x <- left stick up/down, v_y <- left stick left/right (left = +y), v_z <- right stick "
                        "up/down, each normalized and times the mode's gain")
    message = (f"{_case_where(case, i)} ({_pad_context(case, i)}, your rotation_mode = {rotation}): "
               f"cartesian_velocity expected {fmt_value(list(want))}, got {fmt_value(velocity)}; "
               f"{len(bad)} of {len(exp)} ticks differ\nhint: {hint}")
    return False, message, bad


def _judge_toggle(case: TeleopPartsCase, exp: List[ExpectedTick], got: List[PartsTick]) -> Tuple[bool, str, List[int]]:
    bad = [i for i, (e, g) in enumerate(zip(exp, got)) if g.rotation_mode is not e.rotation_mode]
    if not bad:
        return True, "", []
    i = bad[0]
    value = got[i].rotation_mode
    presses = sum(1 for k in range(i + 1) if "north" in case.ticks[k].buttons and
                  (k == 0 or "north" not in case.ticks[k - 1].buttons))
    if not isinstance(value, bool):
        hint = "self.rotation_mode must stay True or False"
    elif all(g.rotation_mode is False for g in got):
        hint = ("toggle_mode() never changed self.rotation_mode: each call must switch it from translation to "
                "rotation mode and back")
    else:
        hint = "switch once per press of triangle: toggle_mode() is called once for each JOYBUTTONDOWN"
    message = (f"{_case_where(case, i)}: after {presses} press(es) of triangle rotation_mode should be "
               f"{exp[i].rotation_mode}, got {fmt_value(value)}; {len(bad)} of {len(exp)} ticks differ\nhint: {hint}")
    return False, message, bad


def _judge_rumble(case: TeleopPartsCase, exp: List[ExpectedTick], got: List[PartsTick]) -> Tuple[bool, str, List[int]]:
    bad = [i for i, (e, g) in enumerate(zip(exp, got)) if _differs(g.rumble, e.rumble, 1e-9)]
    if not bad:
        return True, "", []
    i = bad[0]
    value = as_float(got[i].rumble)
    force = case.ticks[i].force
    if value is None:
        hint = "self.rumble must be a number 0..1"
    elif value > 1.0:
        hint = "limit the rumble to at most 1.0 (a force above the calibration gives 1.0)"
    elif value < 0.0:
        hint = "limit the rumble to at least 0.0"
    else:
        hint = "the rumble is the mapped force self.force, limited to 0..1"
    message = (f"{_case_where(case, i)}: with self.force = {force:g} rumble expected {exp[i].rumble:g}, got "
               f"{fmt_value(got[i].rumble)}; {len(bad)} of {len(exp)} ticks differ\nhint: {hint}")
    return False, message, bad


def compare_teleop_parts(observation: TeleopPartsResult, cases: Sequence[TeleopPartsCase],
                         plot_dir: Optional[Path] = None, probe_facts: Optional[ProcessFacts] = None) -> List[Part]:
    """The parts of Ex. 8 (gripper, twist, toggle, rumble) from the teleop-parts probe."""
    T = PARTS
    keys = ("gripper", "twist", "toggle", "rumble")
    if not observation.ok:
        reason = observation.error or explain_process(probe_facts or ProcessFacts(), "teleoperation.py")
        return [judged_part(T, "import", False, reason)] + [not_judged_part(T, k, "the file could not be imported") for k in keys]
    results = observation.cases
    errors = [r.construct_error for r in results if r.construct_error]
    if errors:
        return ([judged_part(T, "import", False, f"Teleoperation(rate=..., k_trans=..., k_rot=..., k_gripper=..., "
                                           f"deadzone=...) raised {errors[0]}: keep the template's constructor")]
                + [not_judged_part(T, k, "Teleoperation could not be built") for k in keys])
    parts = [judged_part(T, "import", True)]
    judges = {"gripper": (_judge_gripper, "update_gripper_width", "gripper_width", "gripper_width (m)"),
              "twist": (_judge_twist, "update_cartesian_velocity", "cartesian_velocity", ""),
              "toggle": (_judge_toggle, "toggle_mode", "rotation_mode", "rotation_mode"),
              "rumble": (_judge_rumble, "update_rumble", "rumble", "rumble")}
    expected = [reference_parts(case) for case in cases]
    for key in keys:
        judge, method, attribute, ylabel = judges[key]
        failures: List[str] = []
        plots: List[str] = []
        for case, exp, result in zip(cases, expected, results):
            error = _method_error(result, method)
            if error:
                hint = "; fill in the part marked YOUR CODE HERE" if "NotImplementedError" in error else ""
                failures.append(f"{case.label} trace: {error}{hint}")
                continue
            ticks = result.ticks
            if len(ticks) != len(exp):
                failures.append(f"{case.label} trace: only {len(ticks)} of {len(exp)} ticks ran")
                continue
            ok, message, bad = judge(case, exp, ticks)
            if not ok:
                failures.append(message)
                if key == "twist":
                    component = _first_wrong_component(exp, ticks, bad[0])
                    e_series = [(e.velocity_if_rotation if t.rotation_mode is True else e.velocity_if_translation)[component]
                                for e, t in zip(exp, ticks)]
                    a_series = [t.cartesian_velocity[component] if isinstance(t.cartesian_velocity, list)
                                and len(t.cartesian_velocity) == 6 else None for t in ticks]
                    label = "v_x v_y v_z w_x w_y w_z".split()[component]
                    plots += series_plot(plot_dir, f"teleop-{key}-{_slug(case.label)}.png",
                                          f"cartesian_velocity {label}, {case.label} trace", e_series, a_series, label, bad[:50])
                else:
                    e_series = [float(getattr(e, attribute)) for e in exp]
                    values = [getattr(t, attribute) for t in ticks]
                    a_series = [v if not isinstance(v, bool) else float(v) for v in values]
                    plots += series_plot(plot_dir, f"teleop-{key}-{_slug(case.label)}.png",
                                          f"{attribute}, {case.label} trace", e_series, a_series, ylabel, bad[:50])
        parts.append(judged_part(T, key, not failures, "\n".join(failures), plots))
    return parts


def _first_wrong_component(exp: List[ExpectedTick], ticks: List[PartsTick], index: int) -> int:
    velocity = ticks[index].cartesian_velocity
    want = exp[index].velocity_if_rotation if ticks[index].rotation_mode is True else exp[index].velocity_if_translation
    if isinstance(velocity, list) and len(velocity) == 6:
        for k in range(6):
            v = as_float(velocity[k])
            if v is None or abs(v - want[k]) > TWIST_TOLERANCE:
                return k
    return 0


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower()
