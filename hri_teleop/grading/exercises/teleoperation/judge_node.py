"""Judging ``teleoperation.py`` as a node (Ex. 9): topics, types, and what it published for a scripted pad.

A mistake is named by its cause where the run shows one: a loop that does not keep ``~rate`` (the
interval of its twists on the grader's clock), a topic the node used instead of the lab's (from the
master's records of the run), a crash (its traceback in the student's files). The parts that only
show the cause's symptoms are then not judged (docs/instructors.md, "How the parts of a node check
depend on each other").
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import List, Optional, Sequence, Tuple

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.grading.exercises.teleoperation.cases import TeleopNodeCase
from hri_teleop.grading.exercises.teleoperation.parts import PARTS
from hri_teleop.grading.exercises.teleoperation.session import TeleopNodeObservation
from hri_teleop.grading.judge.compare_common import (
    TOLERANCE,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
    process_hints,
    with_box_hints,
)
from hri_teleop.grading.judge.plots import expected_vs_actual
from hri_teleop.grading.judge.tracebacks import NOT_JUDGED_CRASH, Crash, crash_text, find_crash
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import Message, NodeFacts
from hri_teleop.grading.run.sandbox import describe_exit

__all__ = ["compare_teleop_node", "loop_rate_hz", "keeps_rate", "real_time_note", "RATE_TOLERANCE"]

NODE = "teleoperation.py"
#: A loop keeps ``~rate`` when the rate of its twists is within this fraction of it (on the grader's
#: clock the twists come on its ticks; in real time a loaded machine delays some of them).
RATE_TOLERANCE = 0.1
#: Fewer distinct instants than this tell no rate.
_MIN_TICKS = 10
#: A node whose twists went on until this long before square ran the whole script (a crash came as it ended).
_LATE_S = 0.5
NOT_JUDGED_RATE = "the loop does not keep ~rate (see the gripper width part)"


def loop_rate_hz(messages: Sequence[Message]) -> Optional[float]:
    """Ticks per second of the node's loop from one topic's messages: distinct instants over their span
    (None for fewer than ``_MIN_TICKS`` instants). Messages of one tick share an instant on the grader's clock."""
    instants = sorted({round(m.t_s, 4) for m in messages})
    if len(instants) < _MIN_TICKS or instants[-1] <= instants[0]:
        return None
    return (len(instants) - 1) / (instants[-1] - instants[0])


def keeps_rate(measured_hz: Optional[float], rate_hz: float) -> bool:
    """Whether a loop measured at ``measured_hz`` keeps ``rate_hz`` (True when nothing was measured)."""
    if measured_hz is None or rate_hz <= 0.0:
        return True
    return abs(measured_hz / rate_hz - 1.0) <= RATE_TOLERANCE


def _topic_of_type(facts: NodeFacts, kind: str, preferred: str) -> Tuple[str, str]:
    """(topic, type) the node publishes: ``preferred`` if it does, else its first other topic of type ``kind``
    (its ~rumble left out)."""
    entries = facts.publications
    for topic, t in entries:
        if topic == preferred:
            return topic, t
    same = [topic for topic, t in entries if t == kind and not topic.endswith("/rumble")]
    return (same[0], kind) if same else ("", "")


def _twists(observation: TeleopNodeObservation, topic: str) -> List[Message]:
    return [m for m in observation.messages.get(topic, []) if isinstance(m[2], list) and len(m[2]) == 6] if topic else []


def real_time_note(observation: TeleopNodeObservation, case: TeleopNodeCase, twist_topic: str = DEFAULT_TWIST_TOPIC
                   ) -> str:
    """Why a run the grader meant to hold on its /clock went on in real time, as far as the run shows it."""
    twist_at, _ = _topic_of_type(observation.node, "geometry_msgs/Twist", twist_topic)
    measured = loop_rate_hz(_twists(observation, twist_at))
    if not keeps_rate(measured, case.gains.rate):
        return ("the node's loop did not keep ~rate, so the grader's /clock could not step with it: it was run in "
                "real time")
    return ("the node did not publish its twist and gripper width at every tick of the grader's /clock (a loop kept "
            "by rospy.Rate at ~rate that publishes both each tick does), so it was run in real time")


def _fed(observation: TeleopNodeObservation) -> str:
    """What the grader did to judge the rest when the node's force subscriber was not /force_mapped's."""
    if not observation.fed_force:
        return ""
    topic, kind = observation.fed_force[0]
    return f" (the grader sent the force to {topic} as {kind} to judge the rumble)"


def _start_failure(facts: NodeFacts, crash: Optional[Crash]) -> str:
    return with_box_hints(crash_text(crash, NODE), facts, NODE) if crash is not None else explain_process(facts, NODE)


def compare_teleop_node(observation: TeleopNodeObservation, case: TeleopNodeCase,
                        twist_topic: str = DEFAULT_TWIST_TOPIC,
                        plot_dir: Optional[Path] = None, package_dir: str = "") -> List[Part]:
    """The node parts: topics, types, and what came out while a scripted pad drove it.

    ``package_dir``: the student's package as the node saw it (a traceback is named relative to it).
    """
    T = PARTS
    keys = ("node_start", "node_twist_topic", "node_width_topic", "node_twist", "node_width", "node_rumble", "node_quit")
    if observation.session_error:
        return [not_judged_part(T, k, f"the grader could not run the node ({observation.session_error})") for k in keys]
    facts = observation.node
    crash = find_crash(facts.output_tail, package_dir)
    if not facts.started or (observation.problem and not facts.publications):
        return ([judged_part(T, "node_start", False, _start_failure(facts, crash))]
                + [not_judged_part(T, k, NOT_JUDGED_CRASH if crash is not None else "the node did not start")
                   for k in keys[1:]])
    parts: List[Part] = []
    subs = facts.subscriptions
    force_sub = [t for topic, t in subs if topic == "/force_mapped"]
    ran = len(_twists(observation, _topic_of_type(facts, "geometry_msgs/Twist", twist_topic)[0])) >= _MIN_TICKS
    unconnected = force_sub == ["std_msgs/Float32"] and not observation.force_connected and ran
    if unconnected:  # the master shows the grader's type for the topic; the node's subscriber had another
        parts.append(judged_part(T, "node_start", False, (
            "the node subscribes /force_mapped, but its subscriber took no connection from the grader's publisher of "
            "/force_mapped (the type mapping_node publishes) in the whole run: rospy connects a subscriber only to "
            "publishers of its own type; `rostopic info /force_mapped` with mapping_node running shows both ends' "
            "types")))
    elif force_sub == ["std_msgs/Float32"]:
        parts.append(judged_part(T, "node_start", True))
    elif force_sub:
        parts.append(judged_part(T, "node_start", False, f"the node subscribes /force_mapped as {force_sub[0]}, which "
                                                         "is not the type mapping_node publishes on it: `rostopic info "
                                                         "/force_mapped` shows both ends' types" + _fed(observation)))
    else:
        listed = ", ".join(topic for topic, _ in subs if topic != "/clock") or "no topic"  # /clock: the grader's
        parts.append(judged_part(T, "node_start", False, f"the node subscribes {listed}, not /force_mapped: "
                                                         "rospy.Subscriber('/force_mapped', ..., self.on_force)"
                                                         + _fed(observation)))
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
        parts.append(judged_part(T, "node_width_topic", False, f"/gripper_width is {width_type}, which is not the type "
                                                               "gripper_manager subscribes: `rostopic info "
                                                               "/gripper_width` with both nodes running shows both ends"))
    elif width_at:
        parts.append(judged_part(T, "node_width_topic", False, f"the gripper width goes to {width_at}; gripper_manager "
                                                               "listens on /gripper_width (the width was judged on "
                                                               "your topic)"))
    else:
        parts.append(judged_part(T, "node_width_topic", False, "nothing publishes /gripper_width: "
                                                               "rospy.Publisher('/gripper_width', ..., queue_size=1)"))

    twists = _twists(observation, twist_at)
    rate = case.gains.rate
    measured = loop_rate_hz(twists)
    rate_ok = keeps_rate(measured, rate)
    symptoms: List[Part] = []  # parts whose failure the loop's rate explains

    # the twist: each held stick must give its exact value for a while (after the ramp)
    need = max(3, int(0.15 * rate))
    if not twists:
        symptoms.append(not_judged_part(T, "node_twist", "no twist was recorded"))
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
        if failures and plot_dir is not None and rate_ok:
            names = "v_x v_y v_z w_x w_y w_z".split()
            for plateau in case.plateaus:
                comp = plateau.component
                plots.append(expected_vs_actual(
                    Path(plot_dir) / f"teleop-node-{names[comp]}.png",
                    f"{twist_at}: {names[comp]} must reach {plateau.value:.4g} (dashed) while the stick is held",
                    [t for t, _, _ in twists], [math.nan] * len(twists), [v[comp] for _, _, v in twists],
                    "time since the node started (s)", names[comp], levels=[plateau.value]))
        symptoms.append(judged_part(T, "node_twist", not failures, "\n".join(failures), plots))

    widths = [m for m in messages.get(width_at, []) if as_float(m[2]) is not None] if width_at else []
    if not rate_ok:
        assert measured is not None
        width_part = judged_part(T, "node_width", False, (
            f"the node published {measured:.3g} twists per second of ROS time while the grader set ~rate to {rate:g} "
            "Hz: its loop does not keep ~rate. Keep the loop at the rate the node was given (Teleoperation's "
            "self.rate, read from ~rate), not at a number of its own"))
    elif not widths:
        width_part = not_judged_part(T, "node_width", "no gripper width was recorded")
    else:
        step = case.gains.k_gripper / rate
        final = float(widths[-1][2])
        first = float(widths[0][2])
        problems = []
        if abs(first - GRIPPER_MAX_WIDTH_M) > 1e-6:
            problems.append(f"the first width published was {first:.6g} m; the gripper starts open at "
                            f"{GRIPPER_MAX_WIDTH_M:g} m")
        if abs(final - case.final_width) > 3 * step + 1e-6:
            problems.append(f"after holding cross for {case.close_s:g} s (k_gripper {case.gains.k_gripper:g} m/s) the "
                            f"width should be {case.final_width:.6g} m (within 3 steps of {step:.4g} m), it ended at "
                            f"{final:.6g} m")
        width_part = judged_part(T, "node_width", not problems, "\n".join(problems))

    rumble_topic = next((topic for topic, t in pubs if topic.endswith("/rumble") and t == "std_msgs/Float32"), "")
    rumbles = [float(m[2]) for m in messages.get(rumble_topic, []) if as_float(m[2]) is not None] if rumble_topic else []
    if not rumbles:
        rumble_part = judged_part(T, "node_rumble", False, "no ~rumble messages: keep the template's send() and its "
                                                           "rumble publisher")
    else:
        hits = sum(1 for v in rumbles if abs(v - case.rumble) <= TOLERANCE)
        ok = hits >= len(rumbles) // 2
        message = "" if ok else (
            f"with /force_mapped = {case.force:g} arriving every 50 ms the rumble should be {case.rumble:g}; it was "
            f"in {hits} of {len(rumbles)} ticks (values {min(rumbles):.3g} .. {max(rumbles):.3g}): keep the value "
            "in on_force() and compute the rumble from self.force")
        if not ok and crash is not None and crash.callback:
            message = crash_text(crash, NODE)
        rumble_part = judged_part(T, "node_rumble", ok, message)
        if not ok and unconnected:
            rumble_part = not_judged_part(T, "node_rumble", "the node's force subscriber got nothing (see the start part)")

    code = observation.exit_code
    last = twists[-1][2] if twists else None
    if observation.quit_in_time and code == 0 and last is not None and all(v == 0.0 for v in last):
        quit_part = judged_part(T, "node_quit", True)
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
        quit_part = judged_part(T, "node_quit", False, message + ("; " + "; ".join(hints) if hints else ""))
    symptoms += [width_part, rumble_part, quit_part]
    judged = ("node_twist", "node_width", "node_rumble", "node_quit")
    if crash is not None and not crash.callback and code not in (0, None):
        if twists and twists[-1].t_s >= case.quit_s - _LATE_S:  # it ran until square: the crash came as it ended
            return parts + [judged_part(T, "node_quit", False, crash_text(crash, NODE)) if key == "node_quit"
                            and not p.passed else p for key, p in zip(judged, symptoms)]
        return parts + _one_crash(judged, symptoms, crash)
    if not rate_ok:  # the rate is judged in the width part: what it explains is not judged again
        symptoms = [not_judged_part(T, key, NOT_JUDGED_RATE) if not p.passed and key in ("node_twist", "node_quit")
                    else p for key, p in zip(judged, symptoms)]
    return parts + symptoms


def _one_crash(keys: Sequence[str], parts: Sequence[Part], crash: Crash) -> List[Part]:
    """The node crashed while it ran: the first part it failed shows the crash, the others it failed are not judged."""
    out: List[Part] = []
    shown = False
    for key, part in zip(keys, parts):
        if part.passed:
            out.append(part)
        elif not shown:
            out.append(judged_part(PARTS, key, False, crash_text(crash, NODE)))
            shown = True
        else:
            out.append(not_judged_part(PARTS, key, NOT_JUDGED_CRASH))
    return out
