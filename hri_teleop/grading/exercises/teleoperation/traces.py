"""Ex. 8-9's public traces as ROS bags (``hri-grade traces``): the pad and force in, the reference's commands out."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Dict, List, Tuple, Union

import yaml

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.gamepad import AXES, BUTTONS
from hri_teleop.core.teleop import TeleopController
from hri_teleop.grading.cases.tracefiles import T0, TRACE_DIR, json_string, trace_params, twist
from hri_teleop.grading.exercises.teleoperation.cases import (
    PadTick,
    TeleopNodeCase,
    TeleopPartsCase,
    public_teleop_node_case,
    public_teleop_parts_case,
    reference_params,
    reference_parts,
)
from hri_teleop.grading.run.gains import TeleopGains
from hri_teleop.ros.bags import read_topics
from hri_teleop.sim.virtual_pad import ScriptedPad, parse_script

__all__ = ["PUBLIC_TRACES", "read_parts_trace"]


def _parts_messages(case: TeleopPartsCase) -> List[Tuple[str, Any, float]]:
    import rospy  # noqa: PLC0415 - ROS only to write traces
    from sensor_msgs.msg import Joy  # noqa: PLC0415 - ROS only to write traces
    from std_msgs.msg import Bool, Float32  # noqa: PLC0415 - ROS only to write traces

    dt = 1.0 / case.gains.rate
    out: List[Tuple[str, Any, float]] = [("/grading/params", json_string({**case.gains.as_dict(), "label": case.label}), T0)]
    for i, (tick, exp) in enumerate(zip(case.ticks, reference_parts(case))):
        t = T0 + dt * (i + 1)
        axes = dict(tick.axes)
        joy = Joy(axes=[float(axes.get(a, 0.0)) for a in AXES], buttons=[int(b in tick.buttons) for b in BUTTONS])
        joy.header.stamp = rospy.Time.from_sec(t)
        out += [("/grading/pad", joy, t), ("/force_mapped", Float32(data=tick.force), t),
                ("/expected/cartesian_velocity", twist(exp.cartesian_velocity), t),
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
    out: List[Tuple[str, Any, float]] = [("/grading/params", json_string(params), T0),
                                         ("/grading/pad_script", String(data=yaml.safe_dump(script, sort_keys=True)), T0)]
    now = [0.0]
    pad = ScriptedPad(parse_script(script), clock=lambda: now[0])
    pad.start(0.0)
    controller = TeleopController(reference_params(case.gains))
    dt = 1.0 / case.gains.rate
    tick = 0
    while tick * dt <= case.quit_s + 5.0 and not controller.finished:
        now[0] = tick * dt
        command = controller.step(pad.poll(), case.force, 0.0, dt)
        t = T0 + now[0]
        out += [("/force_mapped", Float32(data=case.force), t),
                (DEFAULT_TWIST_TOPIC, twist(command.twist), t),
                ("/gripper_width", Float32(data=command.gripper_width_m), t),
                ("/teleoperation/rumble", Float32(data=command.rumble), t)]
        tick += 1
    return out


def read_parts_trace(path: Union[str, Path] = TRACE_DIR / "teleop_parts_public.bag") -> TeleopPartsCase:
    """The teleoperation parts case stored in a trace bag."""
    path = Path(path)
    bag = read_topics(path, ["/grading/params", "/grading/pad", "/force_mapped"])
    params = trace_params(bag, path)
    gains = TeleopGains(**{k: float(params[k]) for k in ("rate", "k_trans", "k_rot", "k_gripper", "deadzone")})
    ticks = []
    for (_, joy), (_, force) in zip(bag["/grading/pad"], bag["/force_mapped"]):
        axes = tuple(sorted((a, float(v)) for a, v in zip(AXES, joy.axes)))
        buttons = frozenset(b for b, v in zip(BUTTONS, joy.buttons) if v)
        ticks.append(PadTick(axes, buttons, float(force.data)))
    return TeleopPartsCase(params["label"], gains, tuple(ticks))


#: bag file -> what its messages are built from, when ``hri-grade traces`` writes it
PUBLIC_TRACES: Dict[str, Callable[[], List[Tuple[str, Any, float]]]] = {
    "teleop_parts_public.bag": lambda: _parts_messages(public_teleop_parts_case()),
    "teleop_node_public.bag": lambda: _node_messages(public_teleop_node_case())}
