"""Judging the nodes students write: ``teleoperation.py`` (Ex. 8, 9); ``mapping_node.py`` (Ex. 5) in compare_mapping.

``teleoperation.py`` is judged by its parts (Ex. 8) and as a node (Ex. 9).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, List, Optional, Sequence, Tuple

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.gamepad import PadState
from hri_teleop.core.teleop import TeleopController, TeleopParams
from hri_teleop.grading.cases.inputs import (
    ExpectedTick,
    TeleopNodeCase,
    TeleopPartsCase,
    reference_params,
    reference_parts,
)
from hri_teleop.grading.judge.compare_common import (
    TELEOP,
    TOLERANCE,
    TWIST_TOLERANCE,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
    process_hints,
)
from hri_teleop.grading.judge.compare_mapping import compare_mapping
from hri_teleop.grading.judge.plots import expected_vs_actual, series_plot
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import (
    NodeFacts,
    PartsCaseResult,
    PartsTick,
    ProcessFacts,
    TeleopNodeObservation,
    TeleopPartsResult,
)
from hri_teleop.grading.run.sandbox import describe_exit

__all__ = ["compare_mapping", "compare_teleop_parts", "compare_teleop_node"]


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
    previous = as_float(got[i - 1].gripper_width) if i > 0 else 0.08
    held = case.ticks[i].buttons
    if value is None:
        hint = "self.gripper_width must stay a number in metres"
    elif value < -1e-12 or value > 0.08 + 1e-12:
        hint = "keep the width within GRIPPER_MIN_WIDTH .. GRIPPER_MAX_WIDTH (0 .. 0.08 m): clip it after the step"
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
    T = TELEOP
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


# -- teleoperation.py as a node (Ex. 9) ---------------------------------------------------------

def _topic_of_type(facts: NodeFacts, kind: str, preferred: str) -> Tuple[str, str]:
    """(topic, type) the node publishes: ``preferred`` if it does, else its first topic of type ``kind``."""
    entries = facts.publications
    for topic, t in entries:
        if topic == preferred:
            return topic, t
    same = [topic for topic, t in entries if t == kind]
    return (same[0], kind) if same else ("", "")


def compare_teleop_node(observation: TeleopNodeObservation, case: TeleopNodeCase,
                        twist_topic: str = DEFAULT_TWIST_TOPIC,
                        plot_dir: Optional[Path] = None) -> List[Part]:
    """The node parts: topics, types, and what came out while a scripted pad drove it."""
    T = TELEOP
    keys = ("node_start", "node_twist_topic", "node_width_topic", "node_twist", "node_width", "node_rumble", "node_quit")
    if observation.session_error:
        return [not_judged_part(T, k, f"the grader could not run the node ({observation.session_error})") for k in keys]
    facts = observation.node
    if not facts.started or (observation.problem and not facts.publications):
        return ([judged_part(T, "node_start", False, explain_process(facts, "teleoperation.py"))]
                + [not_judged_part(T, k, "the node did not start") for k in keys[1:]])
    parts: List[Part] = []
    subs = facts.subscriptions
    force_sub = [t for topic, t in subs if topic == "/force_mapped"]
    if force_sub == ["std_msgs/Float32"]:
        parts.append(judged_part(T, "node_start", True))
    elif force_sub:
        parts.append(judged_part(T, "node_start", False, f"the node subscribes /force_mapped as {force_sub[0]}; "
                                                   "mapping_node publishes std_msgs/Float32"))
    else:
        listed = ", ".join(topic for topic, _ in subs) or "no topic"
        parts.append(judged_part(T, "node_start", False, f"the node subscribes {listed}, not /force_mapped: "
                                                   "rospy.Subscriber('/force_mapped', Float32, self.on_force)"))
    messages = observation.messages
    pubs = facts.publications

    twist_at, twist_type = _topic_of_type(facts, "geometry_msgs/Twist", twist_topic)
    if twist_at == twist_topic and twist_type == "geometry_msgs/Twist":
        parts.append(judged_part(T, "node_twist_topic", True))
    elif twist_at:
        parts.append(judged_part(T, "node_twist_topic", False, f"the Twist goes to {twist_at}; the velocity controller "
                                                         f"listens on {twist_topic}"))
    else:
        found = [f"{topic} ({t})" for topic, t in pubs if topic == twist_topic]
        parts.append(judged_part(T, "node_twist_topic", False,
                           (f"{found[0]} is not geometry_msgs/Twist" if found else f"nothing publishes {twist_topic}")
                           + ": rospy.Publisher('/cartesian_velocity_controller/cmd_vel', Twist, queue_size=1)"))
    width_at, width_type = _topic_of_type(facts, "std_msgs/Float32", "/gripper_width")
    if width_at == "/gripper_width" and width_type == "std_msgs/Float32":
        parts.append(judged_part(T, "node_width_topic", True))
    elif width_at == "/gripper_width":
        parts.append(judged_part(T, "node_width_topic", False, f"/gripper_width is {width_type}; gripper_manager "
                                                         "subscribes std_msgs/Float32"))
    else:
        parts.append(judged_part(T, "node_width_topic", False, "nothing publishes /gripper_width: "
                                                         "rospy.Publisher('/gripper_width', Float32, queue_size=1)"))

    # the twist: each held stick must give its exact value for a while (after the ramp)
    twists = [m for m in messages.get(twist_at, []) if isinstance(m[2], list) and len(m[2]) == 6] if twist_at else []
    rate = case.gains.rate
    need = max(3, int(0.15 * rate))
    if not twists:
        parts.append(not_judged_part(T, "node_twist", "no twist was recorded"))
    else:
        failures = []
        for plateau in case.plateaus:
            hits = sum(1 for _, _, v in twists if abs(v[plateau.component] - plateau.value) <= TOLERANCE)
            if hits < need:
                seen = [v[plateau.component] for _, _, v in twists]
                failures.append(f"{plateau.what} should settle at {plateau.value:.6g} (gains k_trans {case.gains.k_trans:g}, "
                                f"k_rot {case.gains.k_rot:g}, deadzone {case.gains.deadzone:g}); it did in {hits} messages "
                                f"(range seen {min(seen):.4g} .. {max(seen):.4g})")
        plots = []
        if failures and plot_dir is not None:
            names = "v_x v_y v_z w_x w_y w_z".split()
            for plateau in case.plateaus:
                comp = plateau.component
                plots.append(expected_vs_actual(
                    Path(plot_dir) / f"teleop-node-{names[comp]}.png",
                    f"{twist_at}: {names[comp]} must reach {plateau.value:.4g} (dashed) while the stick is held",
                    [t for t, _, _ in twists], [math.nan] * len(twists), [v[comp] for _, _, v in twists],
                    "time since the node started (s)", names[comp], levels=[plateau.value]))
        parts.append(judged_part(T, "node_twist", not failures, "\n".join(failures), plots))

    widths = [m for m in messages.get(width_at, []) if as_float(m[2]) is not None] if width_at else []
    if not widths:
        parts.append(not_judged_part(T, "node_width", "no gripper width was recorded"))
    else:
        step = case.gains.k_gripper / rate
        final = float(widths[-1][2])
        first = float(widths[0][2])
        problems = []
        if abs(first - 0.08) > 1e-6:
            problems.append(f"the first width published was {first:.6g} m; the gripper starts open at 0.08 m")
        if abs(final - case.final_width) > 3 * step + 1e-6:
            problems.append(f"after holding cross for {case.close_s:g} s (k_gripper {case.gains.k_gripper:g} m/s) the "
                            f"width should be {case.final_width:.6g} m (within 3 steps of {step:.4g} m), it ended at "
                            f"{final:.6g} m")
        parts.append(judged_part(T, "node_width", not problems, "\n".join(problems)))

    rumble_topic = next((topic for topic, t in pubs if topic.endswith("/rumble") and t == "std_msgs/Float32"), "")
    rumbles = [float(m[2]) for m in messages.get(rumble_topic, []) if as_float(m[2]) is not None] if rumble_topic else []
    if not rumbles:
        parts.append(judged_part(T, "node_rumble", False, "no ~rumble messages: keep the template's send() and its "
                                                    "rumble publisher"))
    else:
        hits = sum(1 for v in rumbles if abs(v - case.rumble) <= TOLERANCE)
        ok = hits >= len(rumbles) // 2
        parts.append(judged_part(T, "node_rumble", ok, "" if ok else (
            f"with /force_mapped = {case.force:g} arriving every 50 ms the rumble should be {case.rumble:g}; it was "
            f"in {hits} of {len(rumbles)} ticks (values {min(rumbles):.3g} .. {max(rumbles):.3g}): keep the value "
            "in on_force() and compute the rumble from self.force")))

    code = observation.exit_code
    last = twists[-1][2] if twists else None
    if observation.quit_in_time and code == 0 and last is not None and all(v == 0.0 for v in last):
        parts.append(judged_part(T, "node_quit", True))
    else:
        why = []
        if not observation.quit_in_time:
            why.append("the node was still running after square was pressed")
        elif code != 0:
            why.append(f"it {describe_exit(code)} after square")
        if last is not None and any(v != 0.0 for v in last):
            why.append(f"the last twist was {fmt_value(last)}, not zero")
        message = "; ".join(why) or "no twist was recorded"
        hints = process_hints(facts)
        parts.append(judged_part(T, "node_quit", False, message + ("; " + "; ".join(hints) if hints else "")))
    return parts
