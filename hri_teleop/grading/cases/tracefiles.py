"""The public reference traces as ROS 1 bags under ``grading/traces/`` (``hri-grade traces``).

Bags, so that students and instructors look at them with the lab's own tools (``rosbag info``,
``rqt_bag``, ``rostopic echo -b``) and the inputs reach a node exactly as a recording would. Each
bag holds one graded behaviour's inputs, its parameters (``/grading/params``, JSON in a String) and
the reference outputs, stamped with the input they answer (the topics: grading/README.md). Each
exercise's ``traces`` module builds its bags' messages from its cases and reads them back.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple, Union

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import TRACES
from hri_teleop.ros.bags import write_bag

__all__ = ["TraceFileError", "TRACE_DIR", "T0", "json_string", "twist", "trace_params", "write_traces"]

TRACE_DIR = TRACES
T0 = 1.0  # bag time of the first input (s); rosbag refuses time 0 in some tools


class TraceFileError(HriTeleopError, RuntimeError):
    """A trace bag is missing or does not hold what the grader wrote (one line with the fix)."""


def json_string(data: Mapping[str, object]) -> Any:
    from std_msgs.msg import String  # noqa: PLC0415 - ROS only to write traces

    return String(data=json.dumps(data, sort_keys=True))


def twist(values: Any) -> Any:
    from geometry_msgs.msg import Twist  # noqa: PLC0415 - ROS only to write traces

    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = values[0], values[1], values[2]
    msg.angular.x, msg.angular.y, msg.angular.z = values[3], values[4], values[5]
    return msg


def write_traces(out_dir: Union[str, Path] = TRACE_DIR,
                 traces: Optional[Mapping[str, Callable[[], List[Tuple[str, Any, float]]]]] = None) -> List[Path]:
    """(Re)write the public trace bags ``traces`` (file -> its messages; each exercise's ``public_traces``);
    the same bytes on every run and machine (same ROS messages)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, build in (traces or {}).items():
        ordered = sorted(build(), key=lambda m: m[2])  # stable: same-time messages keep their order
        written.append(write_bag(out / name, ordered, overwrite=True))
    return written


def trace_params(bag: Dict[str, List[Tuple[float, Any]]], path: Path) -> Dict[str, Any]:
    if not bag.get("/grading/params"):
        raise TraceFileError(f"{path}: no /grading/params message; regenerate it with `hri-grade traces`")
    params = json.loads(bag["/grading/params"][0][1].data)
    if not isinstance(params, dict):
        raise TraceFileError(f"{path}: /grading/params is not a JSON object; regenerate it with `hri-grade traces`")
    return params


