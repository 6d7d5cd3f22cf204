"""The public reference traces as ROS 1 bags under ``grading/traces/`` (``hri-grade traces``).

Bags, so that students and instructors look at them with the lab's own tools (``rosbag info``,
``rqt_bag``, ``rostopic echo -b``) and the inputs reach a node exactly as a recording would. Each
bag holds one graded behaviour's inputs, its parameters (``/grading/params``, JSON in a String) and
the reference outputs, stamped with the input they answer (the topics: grading/README.md). The
cases come from :mod:`hri_teleop.grading.cases.inputs`; ``read_*`` turn a bag back into a case.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List, Mapping, Tuple, Union

import yaml

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gamepad import AXES, BUTTONS
from hri_teleop.core.paths import TRACES
from hri_teleop.core.teleop import TeleopController
from hri_teleop.grading.cases.inputs import (
    MappingCase,
    PadTick,
    TeleopGains,
    TeleopNodeCase,
    TeleopPartsCase,
    public_mapping_case,
    public_teleop_node_case,
    public_teleop_parts_case,
    reference_params,
    reference_parts,
)
from hri_teleop.ros.bags import read_topics, write_bag
from hri_teleop.sim.virtual_pad import ScriptedPad, parse_script

__all__ = ["TraceFileError", "TRACE_DIR", "TRACE_FILES", "write_traces", "read_mapping_trace", "read_parts_trace"]

TRACE_DIR = TRACES
TRACE_FILES = ("mapping_public.bag", "teleop_parts_public.bag", "teleop_node_public.bag")
_T0 = 1.0  # bag time of the first input (s); rosbag refuses time 0 in some tools


class TraceFileError(HriTeleopError, RuntimeError):
    """A trace bag is missing or does not hold what the grader wrote (one line with the fix)."""


def _string(data: Mapping[str, object]) -> Any:
    from std_msgs.msg import String  # noqa: PLC0415 - ROS only to write traces

    return String(data=json.dumps(data, sort_keys=True))


def _mapping_messages(case: MappingCase) -> List[Tuple[str, Any, float]]:
    from std_msgs.msg import Float32, Int16  # noqa: PLC0415 - ROS only to write traces

    out: List[Tuple[str, Any, float]] = [("/grading/params", _string({"max_sensor_force": case.max_sensor_force,
                                                                      "label": case.label}), _T0)]
    for i, (count, expected) in enumerate(zip(case.counts, case.expected)):
        t = _T0 + 0.02 * (i + 1)
        out.append(("/pub_force", Int16(data=count), t))
        out.append(("/force_mapped", Float32(data=expected), t))
    return out


def _twist(values: Any) -> Any:
    from geometry_msgs.msg import Twist  # noqa: PLC0415 - ROS only to write traces

    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = values[0], values[1], values[2]
    msg.angular.x, msg.angular.y, msg.angular.z = values[3], values[4], values[5]
    return msg


def _parts_messages(case: TeleopPartsCase) -> List[Tuple[str, Any, float]]:
    import rospy  # noqa: PLC0415 - ROS only to write traces
    from sensor_msgs.msg import Joy  # noqa: PLC0415 - ROS only to write traces
    from std_msgs.msg import Bool, Float32  # noqa: PLC0415 - ROS only to write traces

    dt = 1.0 / case.gains.rate
    out: List[Tuple[str, Any, float]] = [("/grading/params", _string({**case.gains.as_dict(), "label": case.label}), _T0)]
    for i, (tick, exp) in enumerate(zip(case.ticks, reference_parts(case))):
        t = _T0 + dt * (i + 1)
        axes = dict(tick.axes)
        joy = Joy(axes=[float(axes.get(a, 0.0)) for a in AXES], buttons=[int(b in tick.buttons) for b in BUTTONS])
        joy.header.stamp = rospy.Time.from_sec(t)
        out += [("/grading/pad", joy, t), ("/force_mapped", Float32(data=tick.force), t),
                ("/expected/cartesian_velocity", _twist(exp.cartesian_velocity), t),
                ("/expected/gripper_width", Float32(data=exp.gripper_width), t),
                ("/expected/rotation_mode", Bool(data=exp.rotation_mode), t),
                ("/expected/rumble", Float32(data=exp.rumble), t)]
    return out


def _node_messages(case: TeleopNodeCase) -> List[Tuple[str, Any, float]]:
    from std_msgs.msg import Float32, String  # noqa: PLC0415 - ROS only to write traces

    params = {**case.gains.as_dict(), "force": case.force, "close_s": case.close_s, "final_width": case.final_width,
              "quit_s": case.quit_s, "label": case.label,
              "plateaus": [{"what": p.what, "component": p.component, "value": p.value} for p in case.plateaus]}
    script = [dict(step) for step in case.script]
    out: List[Tuple[str, Any, float]] = [("/grading/params", _string(params), _T0),
                                         ("/grading/pad_script", String(data=yaml.safe_dump(script, sort_keys=True)), _T0)]
    now = [0.0]
    pad = ScriptedPad(parse_script(script), clock=lambda: now[0])
    pad.start(0.0)
    controller = TeleopController(reference_params(case.gains))
    dt = 1.0 / case.gains.rate
    tick = 0
    while tick * dt <= case.quit_s + 5.0 and not controller.finished:
        now[0] = tick * dt
        command = controller.step(pad.poll(), case.force, 0.0, dt)
        t = _T0 + now[0]
        out += [("/force_mapped", Float32(data=case.force), t),
                (DEFAULT_TWIST_TOPIC, _twist(command.twist), t),
                ("/gripper_width", Float32(data=command.gripper_width_m), t),
                ("/teleoperation/rumble", Float32(data=command.rumble), t)]
        tick += 1
    return out


def write_traces(out_dir: Union[str, Path] = TRACE_DIR) -> List[Path]:
    """(Re)write the public trace bags; the same bytes on every run and machine (same ROS messages)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, messages in (("mapping_public.bag", _mapping_messages(public_mapping_case())),
                           ("teleop_parts_public.bag", _parts_messages(public_teleop_parts_case())),
                           ("teleop_node_public.bag", _node_messages(public_teleop_node_case()))):
        ordered = sorted(messages, key=lambda m: m[2])  # stable: same-time messages keep their order
        written.append(write_bag(out / name, ordered, overwrite=True))
    return written


def _params(bag: Dict[str, List[Tuple[float, Any]]], path: Path) -> Dict[str, Any]:
    if not bag.get("/grading/params"):
        raise TraceFileError(f"{path}: no /grading/params message; regenerate it with `hri-grade traces`")
    params = json.loads(bag["/grading/params"][0][1].data)
    if not isinstance(params, dict):
        raise TraceFileError(f"{path}: /grading/params is not a JSON object; regenerate it with `hri-grade traces`")
    return params


def read_mapping_trace(path: Union[str, Path] = TRACE_DIR / "mapping_public.bag") -> Tuple[MappingCase, List[float]]:
    """(the case, the expected values as stored) from a mapping trace bag."""
    path = Path(path)
    bag = read_topics(path, ["/grading/params", "/pub_force", "/force_mapped"])
    params = _params(bag, path)
    case = MappingCase(params["label"], int(params["max_sensor_force"]), tuple(int(m.data) for _, m in bag["/pub_force"]))
    return case, [float(m.data) for _, m in bag["/force_mapped"]]


def read_parts_trace(path: Union[str, Path] = TRACE_DIR / "teleop_parts_public.bag") -> TeleopPartsCase:
    """The teleoperation parts case stored in a trace bag."""
    path = Path(path)
    bag = read_topics(path, ["/grading/params", "/grading/pad", "/force_mapped"])
    params = _params(bag, path)
    gains = TeleopGains(**{k: float(params[k]) for k in ("rate", "k_trans", "k_rot", "k_gripper", "deadzone")})
    ticks = []
    for (_, joy), (_, force) in zip(bag["/grading/pad"], bag["/force_mapped"]):
        axes = tuple(sorted((a, float(v)) for a, v in zip(AXES, joy.axes)))
        buttons = frozenset(b for b, v in zip(BUTTONS, joy.buttons) if v)
        ticks.append(PadTick(axes, buttons, float(force.data)))
    return TeleopPartsCase(params["label"], gains, tuple(ticks))
