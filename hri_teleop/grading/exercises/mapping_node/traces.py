"""Ex. 5's public trace as a ROS bag (``hri-grade traces``): the counts on /pub_force, the expected /force_mapped."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Dict, List, Tuple, Union

from hri_teleop.grading.cases.tracefiles import T0, TRACE_DIR, json_string, trace_params
from hri_teleop.grading.exercises.mapping_node.cases import MappingCase, public_mapping_case
from hri_teleop.ros.bags import read_topics

__all__ = ["PUBLIC_TRACES", "read_mapping_trace"]


def _mapping_messages(case: MappingCase) -> List[Tuple[str, Any, float]]:
    from std_msgs.msg import Float32, Int16  # noqa: PLC0415 - ROS only to write traces

    out: List[Tuple[str, Any, float]] = [("/grading/params", json_string({"max_sensor_force": case.max_sensor_force,
                                                                      "label": case.label}), T0)]
    for i, (count, expected) in enumerate(zip(case.counts, case.expected)):
        t = T0 + 0.02 * (i + 1)
        out.append(("/pub_force", Int16(data=count), t))
        out.append(("/force_mapped", Float32(data=expected), t))
    return out


def read_mapping_trace(path: Union[str, Path] = TRACE_DIR / "mapping_public.bag") -> Tuple[MappingCase, List[float]]:
    """(the case, the expected values as stored) from a mapping trace bag."""
    path = Path(path)
    bag = read_topics(path, ["/grading/params", "/pub_force", "/force_mapped"])
    params = trace_params(bag, path)
    case = MappingCase(params["label"], int(params["max_sensor_force"]), tuple(int(m.data) for _, m in bag["/pub_force"]))
    return case, [float(m.data) for _, m in bag["/force_mapped"]]


#: bag file -> (what its messages are built from, when ``hri-grade traces`` writes it)
PUBLIC_TRACES: Dict[str, Callable[[], List[Tuple[str, Any, float]]]] = {
    "mapping_public.bag": lambda: _mapping_messages(public_mapping_case())}
