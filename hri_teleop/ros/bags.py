"""Reading and writing ROS 1 bag files for tests, demos and the grader.

Why bags: they are what the lab records with ``rosbag record`` and what ``rosbag play``
replays, so an input sequence written here reaches a node exactly as a recording would.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, Iterable, List, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError


class BagError(HriTeleopError, RuntimeError):
    """A bag file could not be read or written."""


def read_topics(bag_path: Path, topics: Sequence[str]) -> Dict[str, List[Tuple[float, Any]]]:
    """Messages per topic as (receive time in s, message), in recorded order."""
    import rosbag  # noqa: PLC0415 - ros.trial imports this module without ROS (course.widgets, study analysis)

    out: Dict[str, List[Tuple[float, Any]]] = {t: [] for t in topics}
    path = Path(bag_path)
    if not path.exists():
        raise BagError(f"{path}: no such bag; did rosbag record stop cleanly (SIGINT)?")
    try:
        with rosbag.Bag(str(path)) as bag:
            for topic, msg, stamp in bag.read_messages(topics=list(topics)):
                out[topic].append((stamp.to_sec(), msg))
    except rosbag.ROSBagException as exc:
        raise BagError(f"{path}: not a readable bag ({exc}); record it again") from None
    return out


def write_bag(bag_path: Path, messages: Iterable[Tuple[str, Any, float]], overwrite: bool = False) -> Path:
    """Write (topic, message, time in s) triples to a new bag; refuses to overwrite by default."""
    import rosbag  # noqa: PLC0415 - ros.trial imports this module without ROS (course.widgets, study analysis)
    import rospy  # noqa: PLC0415 - as rosbag

    path = Path(bag_path)
    if path.exists() and not overwrite:
        raise BagError(f"{path}: exists; delete it or pass overwrite=True")
    path.parent.mkdir(parents=True, exist_ok=True)
    with rosbag.Bag(str(path), "w") as bag:
        for topic, msg, t_s in messages:
            bag.write(topic, msg, rospy.Time.from_sec(t_s))
    return path
