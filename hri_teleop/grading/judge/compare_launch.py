"""Judging the launch files (Ex. 6-7, Ex. 12-13) and the launch in the simulated lab.

Ex. 15's graph is judged in :mod:`hri_teleop.grading.judge.compare_graph`.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.board_rates import HANDOUT_PERIOD_S, MAX_PERIOD_MS, MIN_PERIOD_MS, RECOMMENDED_RATE_HZ
from hri_teleop.core.checks import is_int
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.gripper import width_from_joint_positions_m
from hri_teleop.core.mapping import ADC_MAX_COUNT
from hri_teleop.grading.cases.inputs import LaunchSimCase
from hri_teleop.grading.judge.compare_common import (
    SENSOR_LAUNCH,
    STUDENT_PACKAGES,
    TELEOP_LAUNCH,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
)
from hri_teleop.grading.judge.plots import timeline
from hri_teleop.grading.judge.robot_params import TABLE_1
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import (
    LaunchNode,
    LaunchObservation,
    LaunchParseResult,
    ProcessFacts,
    SensorLaunchObservation,
    TeleopLaunchSimObservation,
)
from hri_teleop.grading.run.workspace import FRANKA_MARKER_PARAM

# -- launch files ---------------------------------------------------------------------------

#: Added to a parse error that names franka_control (its launch file lives in franka_ros).
_FRANKA_CONTROL_HINT = (" (the grader provides franka_control: write "
                        "$(find franka_control)/launch/franka_control_cartesian_velocity.launch)")


def _parse_parts(table: Dict[str, Tuple[str, float]], parsed: LaunchParseResult, parse_facts: Optional[ProcessFacts],
                 later: Sequence[str], exercise: str, franka_hint: str = "") -> Tuple[List[Part], bool]:
    """A launch file's "parse" part; when roslaunch cannot load it, also the ``later`` parts it leaves
    unjudged, and True: nothing more to judge."""
    if not parsed.ok:
        reason = parsed.error or explain_process(parse_facts or ProcessFacts(), "parsing")
        if franka_hint and "franka_control" in reason:
            reason += franka_hint
        return ([judged_part(table, "parse", False, f"roslaunch cannot load it: {reason}")]
                + [not_judged_part(table, k, "the file does not parse") for k in later]), True
    if is_empty(parsed):
        return ([judged_part(table, "parse", False, "it parses but starts no node and sets no parameter: write the "
                             f"launch file (handout {exercise})")]
                + [not_judged_part(table, k, EMPTY_CAUSE) for k in later]), True
    return [judged_part(table, "parse", True)], False


#: Why the parts after "parse" are not judged for a launch file that starts and sets nothing.
EMPTY_CAUSE = "the file starts no node and sets no parameter (the parse part)"


def is_empty(parsed: LaunchParseResult) -> bool:
    """A launch file that parses but starts no node and sets no parameter (the template as it is)."""
    return parsed.ok and not parsed.nodes and not parsed.params


#: Characters of one entry of the student's quoted back.
SHOWN_CHARS = 60


def written(value: Any) -> str:
    """An entry of the student's as they wrote it (cut short), to quote back."""
    text = str(value).strip()
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS - 3] + "..."


def _stem(script_type: str) -> str:
    """A node's type= as a file stem to compare loosely: no folder, no extension, lower case."""
    base = script_type.strip().replace("\\", "/").rsplit("/", 1)[-1]
    return (base[:-3] if base.lower().endswith(".py") else base).lower()


def near_miss(parsed: LaunchParseResult, script: str) -> str:
    """Why a <node> that is meant to run ``script`` does not (type= without .py, another case, a folder, or
    the node's name right and its type= another file); '' when no node comes close."""
    want = _stem(script)
    for node in parsed.nodes:
        kind = node.type
        if kind == script:
            continue
        if _stem(kind) == want:
            if "/" in kind or "\\" in kind:
                fix = "the file's name alone, without its folder"
            elif not kind.lower().endswith(".py"):
                fix = "the executable file as it is in scripts/, extension included"
            else:
                fix = "the executable file exactly as it is in scripts/, upper and lower case included"
            return (f'{script}: the <node name="{written(node.name)}"> is there, but its type="{written(kind)}" is not a '
                    f"file roslaunch finds: type= must name {fix}")
        if node.name.lower() == want and _stem(kind) != want:
            return (f'{script}: the <node name="{written(node.name)}"> is there, but its type="{written(kind)}" names '
                    "another file: type= names the script the node runs, as it is in scripts/")
    return ""


def script_problem(parsed: LaunchParseResult, script: str, packages: Sequence[str], where: str, exercise: str) -> str:
    """Why no <node> runs ``script`` of one of ``packages`` ('' if one does)."""
    found = nodes_by_script(parsed).get(script, [])
    if any(n.package in packages for n in found):
        return ""
    if found:
        return f"{script} is started from package {found[0].package!r}; {where} it is in {packages[0]}"
    return near_miss(parsed, script) or (f"no node runs {script} of {packages[0]}: start it with a <node> element "
                                         f"(handout {exercise})")


def nodes_by_script(parsed: LaunchParseResult) -> Dict[str, List[LaunchNode]]:
    out: Dict[str, List[LaunchNode]] = {}
    for node in parsed.nodes:
        out.setdefault(node.type, []).append(node)
    return out


def check_max_param(params: Mapping[str, object]) -> Tuple[bool, str]:
    value = params.get("/max_sensor_force")
    if "/max_sensor_force" not in params:
        private = [k for k in params if k.endswith("/max_sensor_force")]
        if private:
            return False, (f"max_sensor_force is set as {private[0]} (inside a node: private); mapping_node reads the "
                           "global /max_sensor_force: put its <param> outside the <node> elements")
        return False, ("the launch file does not set /max_sensor_force: set it with a <param> element outside "
                       "the <node> elements (handout Ex. 6)")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        count = written(value) if isinstance(value, str) and value.strip().isdigit() else "<the count>"
        return False, (f"/max_sensor_force is {value!r} ({type(value).__name__}); it must be a number of counts: "
                       f"write value=\"{count}\" without type=\"str\"")
    if not 0 < value <= ADC_MAX_COUNT:
        return False, f"/max_sensor_force is {value!r}; it must be a count 0 < value <= {ADC_MAX_COUNT} (about 700)"
    return True, ""


def compare_sensor_launch(parsed: LaunchParseResult, observation: Optional[SensorLaunchObservation],
                          parse_facts: Optional[ProcessFacts] = None) -> List[Part]:
    """sensor.launch: what roslaunch's loader makes of it, then what flowed when it ran."""
    T = SENSOR_LAUNCH
    parts, final = _parse_parts(T, parsed, parse_facts, ("nodes", "param", "yaml", "flow"), "Ex. 6")
    if final:
        return parts
    missing = [m for m in (script_problem(parsed, s, STUDENT_PACKAGES, "at home and in the lab", "Ex. 6")
                           for s in ("FSR_sensor.py", "mapping_node.py")) if m]
    parts.append(judged_part(T, "nodes", not missing, "\n".join(missing)))
    ok, message = check_max_param(parsed.params)
    parts.append(judged_part(T, "param", ok, message))
    keys = [k for k in TABLE_1 if f"/{k}" in parsed.params or any(p.startswith(f"/{k}/") for p in parsed.params)]
    parts.append(judged_part(T, "yaml", True, note=("Ex. 7 done: robot_params.yaml is loaded" if keys else
                                              "Ex. 7 (voluntary) not done: robot_params.yaml is not loaded")))
    if observation is None or observation.session_error:
        reason = observation.session_error if observation is not None else "it was not launched"
        parts.append(not_judged_part(T, "flow", f"the grader could not launch it ({reason})"))
        return parts
    values = observation.force_mapped
    kinds = {k for _, k, _ in values}
    numbers = [as_float(v) for _, _, v in values]
    problems = []
    note = _supplied_note(observation, "the flow")
    if {"FSR_sensor.py", "mapping_node.py"} <= set(observation.supplied):
        parts.append(not_judged_part(T, "flow", "the file starts neither node (the nodes part): the grader started "
                                               "both, so nothing that flowed came from your launch file"))
        return parts
    if not values:
        launch = dataclasses.replace(observation.launch, problem=observation.problem)
        problems.append("nothing arrived on /force_mapped while the launch file ran: "
                        + explain_process(launch, "roslaunch"))
    else:
        if kinds != {"std_msgs/Float32"}:
            problems.append(f"/force_mapped is {', '.join(sorted(kinds))}, not std_msgs/Float32")
        outside = [v for v in numbers if v is None or not 0.0 <= v <= 1.0]
        if outside:
            problems.append(f"{len(outside)} of {len(values)} values on /force_mapped were outside [0, 1] "
                            f"(e.g. {fmt_value(outside[0])}): check mapping_node.py's range and clipping")
        if len(values) < 3:
            problems.append(f"only {len(values)} messages on /force_mapped in the recording: the sensor publishes "
                            "10 per second")
    parts.append(judged_part(T, "flow", not problems, "\n".join(problems), note=note))
    return parts


def _hz(rate_hz: float) -> str:
    return f"{rate_hz:.1f}".rstrip("0").rstrip(".")


def board_rate_note(period_ms: object) -> str:
    """What serial_node's ``~publish_period_ms`` (None: not set) makes the lab's rosserial sketch send.

    A note, never points: the handout's Ex. 12 f) asks for the port only, and the parameter is
    read by the lab's corrected sketch (firmware/arduino_code_force_node), so the serial part's
    2 points and every total stay as they were; the feedback says what the file gives the board.
    """
    handout_ms = round(HANDOUT_PERIOD_S * 1000)
    recommended_ms = round(1000 / RECOMMENDED_RATE_HZ)
    fix = (f"set serial_node's publish_period_ms to {recommended_ms} for {_hz(RECOMMENDED_RATE_HZ)} Hz "
           "(an int parameter of its node; no points depend on it)")
    handout = f"every {handout_ms} ms, {_hz(1 / HANDOUT_PERIOD_S)} Hz"
    if period_ms is None:
        return f"the board sends {handout} (the handout's delay({handout_ms}), publish_period_ms not set): {fix}"
    if not is_int(period_ms) or not MIN_PERIOD_MS <= period_ms <= MAX_PERIOD_MS:
        kind = "" if is_int(period_ms) else f" ({type(period_ms).__name__})"
        return (f"serial_node's publish_period_ms is {period_ms!r}{kind}, which the board ignores (it takes an int "
                f"in {MIN_PERIOD_MS}..{MAX_PERIOD_MS} ms): it sends {handout}; {fix}")
    note = f"the board sends every {period_ms} ms, {_hz(1000 / period_ms)} Hz (serial_node's publish_period_ms)"
    if period_ms != recommended_ms:
        note += f"; {recommended_ms} ms gives the {_hz(RECOMMENDED_RATE_HZ)} Hz the lab uses"
    return note


def compare_teleop_launch(parsed: LaunchParseResult, parse_facts: Optional[ProcessFacts] = None) -> List[Part]:
    """teleoperation.launch as roslaunch's loader sees it (with a stand-in franka_control)."""
    T = TELEOP_LAUNCH
    parts, final = _parse_parts(T, parsed, parse_facts, ("nodes", "serial", "param", "include"), "Ex. 12-13",
                                _FRANKA_CONTROL_HINT)
    if final:
        return parts
    scripts = nodes_by_script(parsed)
    problems = [m for m in (script_problem(parsed, s, ("hri_lab",), "in the lab", "Ex. 12 e)")
                            for s in ("teleoperation.py", "gripper_manager.py", "mapping_node.py")) if m]
    parts.append(judged_part(T, "nodes", not problems, "\n".join(problems)))
    params = parsed.params
    serial = [n for n in scripts.get("serial_node.py", []) if n.package == "rosserial_python"]
    if not serial:
        why = script_problem(parsed, "serial_node.py", ("rosserial_python",), "in the lab", "Ex. 12 f)")
        parts.append(judged_part(T, "serial", False, why if not why.startswith("no node runs") else
                                 "no node runs rosserial_python's serial_node.py: the Arduino's node of Ex. 12 f)"))
    else:
        parts.append(_serial_part(serial[0], params))
    ok, message = check_max_param(params)
    parts.append(judged_part(T, "param", ok, message))
    included = FRANKA_MARKER_PARAM in params
    parts.append(judged_part(T, "include", included, "" if included else (
        "franka_control_cartesian_velocity.launch of franka_control is not included: the robot's launch file "
        "of Ex. 13, with an <include> element")))
    return parts


#: The Arduino's port as the handout gives it (Ex. 11 and Ex. 12 f): the one value the serial part accepts.
HANDOUT_PORT = "/dev/ttyACM0"


def _serial_part(serial: LaunchNode, params: Mapping[str, object]) -> Part:
    """serial_node's ~port: the handout's port, a string (judged); its ~publish_period_ms: a note."""
    T = TELEOP_LAUNCH
    key = f"{serial.full_name}/port"
    port = params.get(key)
    if port is None:
        return judged_part(T, "serial", False, f"serial_node has no private parameter port ({key}): give it the Arduino's "
                                               "serial port (Ex. 11), a string <param> inside its <node>")
    if port != HANDOUT_PORT:
        shown = repr(port) if not isinstance(port, str) else f'"{written(port)}"'
        kind = "" if isinstance(port, str) else f" ({type(port).__name__}, not a string)"
        hint = ("; if a station's board is on another port, make it a roslaunch <arg> whose default is the "
                "handout's" if isinstance(port, str) and port.startswith("/dev/tty") else "")
        return judged_part(T, "serial", False, f"{key} is {shown}{kind}: the Arduino's port is the one the handout's "
                                               f"Ex. 11 and Ex. 12 f) give, {HANDOUT_PORT} (last digit zero){hint}")
    rate_note = board_rate_note(params.get(f"{serial.full_name}/publish_period_ms"))
    return judged_part(T, "serial", True, note=rate_note)


#: What the launch in simulation must show (the grader's scenario: hri_teleop.grading.cases.inputs.launch_sim_case).
SIM_MIN_RISE_M = 0.02          # the arm rises at 5 cm/s for 1 s: at least 2 cm
SIM_MAX_CLOSED_WIDTH_M = 0.06  # the hand opens 0.08 m; cross closes it past 0.06 m
SIM_MIN_FORCE = 0.3            # the egg squeezed until strong rumble: /force_mapped well above 0


def _series(observation: TeleopLaunchSimObservation, topic: str) -> List[Tuple[float, Any]]:
    return [(float(t), v) for t, _kind, v in observation.messages.get(topic, [])]


def _width_m(positions: Any) -> Optional[float]:
    return width_from_joint_positions_m(positions) if isinstance(positions, list) else None


def _sim_plot(plot_dir: Optional[Path], observation: TeleopLaunchSimObservation, teleop: str) -> List[str]:
    if plot_dir is None:
        return []

    twist = [(t, v[2]) for t, v in _series(observation, DEFAULT_TWIST_TOPIC) if isinstance(v, list)]
    z = [(t, v[2]) for t, v in _series(observation, "/lab_sim/ee_pose") if isinstance(v, list)]
    width = [(t, _width_m(v)) for t, v in _series(observation, "/franka_gripper/joint_states")]
    target = [(t, as_float(v)) for t, v in _series(observation, "/gripper_width")]
    force = [(t, as_float(v)) for t, v in _series(observation, "/force_mapped")]
    rumble = [(t, as_float(v)) for t, v in _series(observation, f"{teleop}/rumble")]
    panels = [("twist v_z (m/s)", [("command", twist)]), ("end effector z (m)", [("simulated arm", z)]),
              ("gripper width (m)", [("hand", width), ("/gripper_width", target)]),
              ("force", [("/force_mapped", force), ("rumble", rumble)])]
    return [timeline(Path(plot_dir) / "teleoperation-launch-sim.png",
                     "teleoperation.launch in simulation: what the grader saw", panels)]


def teleop_node_name(parsed: LaunchParseResult) -> Optional[str]:
    """The full name (``/ns/name``) of the launch file's teleoperation.py node of hri_lab, if it has one."""
    for node in nodes_by_script(parsed).get("teleoperation.py", []):
        if node.package == "hri_lab":
            return node.full_name
    return None


def _supplied_note(observation: LaunchObservation, what: str) -> str:
    """What the grader started or set in place of the launch file, to judge ``what`` ('' if nothing)."""
    if not observation.supplied:
        return ""
    return f"to judge {what} the grader supplied what the launch file lacks: " + ", ".join(observation.supplied)


def compare_teleop_launch_sim(parsed: LaunchParseResult, observation: Optional[TeleopLaunchSimObservation],
                              case: LaunchSimCase, plot_dir: Optional[Path] = None) -> Part:
    """The launch file run with the simulated lab and the grader's operator (``case``): did it all connect?"""
    T = TELEOP_LAUNCH
    if not parsed.ok:
        return not_judged_part(T, "sim", "the file does not parse")
    if is_empty(parsed):
        return not_judged_part(T, "sim", EMPTY_CAUSE)
    if observation is None:
        why = script_problem(parsed, "teleoperation.py", ("hri_lab",), "in the lab", "Ex. 12 e)")
        return not_judged_part(T, "sim", "the file starts no teleoperation.py of hri_lab (the nodes part: "
                               f"{why}), so there is no operator to run" if why else
                               "the grader found no teleoperation node to run")
    if observation.session_error:
        return not_judged_part(T, "sim", f"the grader could not run the simulation ({observation.session_error})")
    note = _supplied_note(observation, "the rest")
    teleop = teleop_node_name(parsed) or "/teleoperation"
    if observation.problem:
        launch = dataclasses.replace(observation.launch, problem=observation.problem)
        return judged_part(T, "sim", False, explain_process(launch, "roslaunch"), note=note)
    twist_topic = DEFAULT_TWIST_TOPIC
    problems: List[str] = []
    twists = [v for _, v in _series(observation, twist_topic)]
    if not twists:
        others = sorted(t for t, k in observation.teleop_publications if k == "geometry_msgs/Twist")
        problems.append(f"nothing arrived on {twist_topic}, where the robot listens"
                        + (f"; {teleop} publishes its twist on {', '.join(others)}: a <remap> in the launch file?"
                           if others else f": did {teleop} start and stay up?"))
    z = [v[2] for _, v in _series(observation, "/lab_sim/ee_pose") if isinstance(v, list)]
    rise = (max(z) - z[0]) if z else 0.0
    if twists and rise < SIM_MIN_RISE_M:
        problems.append(f"the arm rose {rise * 100:.1f} cm while the right stick was held up for "
                        f"{case.lift_to_s - case.lift_from_s:.0f} s (at least {SIM_MIN_RISE_M * 100:.0f} cm expected)")
    widths = [w for w in (_width_m(v) for _, v in _series(observation, "/franka_gripper/joint_states")) if w is not None]
    if not widths or min(widths) > SIM_MAX_CLOSED_WIDTH_M:
        seen = f"it stayed at {min(widths):.3f} m or more" if widths else "no joint_states arrived"
        targets = _series(observation, "/gripper_width")
        why = ("gripper_manager got no /gripper_width" if not targets else
               "/gripper_width came but the hand did not move: is gripper_manager.py started?")
        problems.append(f"the hand did not close while cross was held ({seen}); {why}")
    pub_force = _series(observation, "/pub_force")
    force = [as_float(v) for _, v in _series(observation, "/force_mapped")]
    if not pub_force:
        problems.append("no sensor counts on /pub_force: the board's counts reach ROS through rosserial_python's "
                        "serial_node.py (the grader's stand-in forwards the simulated board)")
    elif not force:
        problems.append("the board's counts arrived on /pub_force but nothing on /force_mapped: is mapping_node.py "
                        "started?")
    else:
        numbers = [v for v in force if v is not None and 0.0 <= v <= 1.0]
        if len(numbers) < len(force):
            problems.append(f"{len(force) - len(numbers)} of {len(force)} values on /force_mapped were outside [0, 1]")
        elif max(numbers) < SIM_MIN_FORCE:
            problems.append(f"/force_mapped stayed below {SIM_MIN_FORCE} (max {max(numbers):.3f}) while the hand "
                            "squeezed the sponge: is /max_sensor_force the calibrated count?")
    facts = []
    rumble = [r for r in (as_float(v) for _, v in _series(observation, f"{teleop}/rumble")) if r is not None]
    if rumble:
        facts.append(f"the pad rumbled up to {max(rumble):.2f}")
    status = [v for _, v in _series(observation, "/lab_sim/object") if isinstance(v, dict)]
    if status:
        last = status[-1]
        facts.append(f"the {last.get('name', 'object')} was " + ("crushed" if last.get("crushed") == "true" else
                                       "lifted" if last.get("ever_lifted") == "true" else "not lifted"))
    if not observation.quit_in_time:
        facts.append(f"{teleop} was still running after square was pressed")
    note = "; ".join(x for x in [note] + facts if x)
    plots = _sim_plot(plot_dir, observation, teleop) if problems else []
    return judged_part(T, "sim", not problems, "\n".join(problems), plots, note=note)
