"""Judging ``teleoperation.launch`` (Ex. 12-13): as roslaunch's loader sees it, then launched in the simulated lab."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple

from hri_teleop.core.board_rates import HANDOUT_PERIOD_S, MAX_PERIOD_MS, MIN_PERIOD_MS, RECOMMENDED_RATE_HZ
from hri_teleop.core.checks import is_int
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.gripper import width_from_joint_positions_m
from hri_teleop.grading.exercises.teleoperation_launch.cases import LaunchSimCase
from hri_teleop.grading.judge.compare_common import as_float, explain_process, judged_part, not_judged_part
from hri_teleop.grading.judge.compare_launch import (
    EMPTY_CAUSE,
    check_max_param,
    is_empty,
    nodes_by_script,
    parse_parts,
    script_problem,
    supplied_note,
    written,
)
from hri_teleop.grading.judge.plots import timeline
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import LaunchNode, LaunchParseResult, ProcessFacts, TeleopLaunchSimObservation
from hri_teleop.grading.run.workspace import FRANKA_MARKER_PARAM

__all__ = ["PARTS", "compare_teleop_launch", "compare_teleop_launch_sim", "teleop_node_name", "HANDOUT_PORT", "board_rate_note"]

#: Part key -> (name as students read it, points; tests refer to the keys).
PARTS: Dict[str, Tuple[str, float]] = {
    "parse": ("parses with roslaunch", 1),
    "nodes": ("starts teleoperation.py, gripper_manager.py and mapping_node.py", 3),
    "serial": ("starts rosserial_python's serial_node.py with ~port /dev/ttyACM0 (a string)", 2),
    "param": ("sets /max_sensor_force (a count, 0 < value <= 1023)", 2),
    "include": ("includes franka_control's franka_control_cartesian_velocity.launch", 2),
    "sim": ("launched in simulation: the pad moves the arm, closes the hand, and the force reaches /force_mapped", 4),
}


#: Added to a parse error that names franka_control (its launch file lives in franka_ros).
_FRANKA_CONTROL_HINT = (" (the grader provides franka_control: write "
                        "$(find franka_control)/launch/franka_control_cartesian_velocity.launch)")


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
    T = PARTS
    parts, final = parse_parts(T, parsed, parse_facts, ("nodes", "serial", "param", "include"), "Ex. 12-13",
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
    T = PARTS
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


#: What the launch in simulation must show (the grader's scenario: cases.launch_sim_case).
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


def compare_teleop_launch_sim(parsed: LaunchParseResult, observation: Optional[TeleopLaunchSimObservation],
                              case: LaunchSimCase, plot_dir: Optional[Path] = None) -> Part:
    """The launch file run with the simulated lab and the grader's operator (``case``): did it all connect?"""
    T = PARTS
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
    note = supplied_note(observation, "the rest")
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
