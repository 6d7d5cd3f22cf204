"""The lab twin's ``/joint_state_publisher``: the arm's and the fingers' joint states merged on ``/joint_states``.

franka_control.launch starts joint_state_publisher with a ``source_list`` of
``franka_state_controller/joint_states`` and ``franka_gripper/joint_states`` at 30 Hz; the notebooks'
3D view follows its ``/joint_states``. Here the latest message of each source is merged (arm joints
first, then the fingers) and published at ``~rate``. Counts: messages published.
"""

from __future__ import annotations

import threading
from typing import Dict, List, Optional, Tuple

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Header

from hri_teleop.core.joints import FRANKA_JOINT_STATES_TOPIC
from hri_teleop.ros.lab_twin.counts import CountsFile
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.ros.stop_signals import init_node

__all__ = ["SOURCES", "RATE_HZ", "merge", "main"]

#: franka_control.launch's source_list, in its order.
SOURCES = (FRANKA_JOINT_STATES_TOPIC, "/franka_gripper/joint_states")
#: franka_control.launch's rate for joint_state_publisher (Hz).
RATE_HZ = 30.0

Joints = Tuple[List[str], List[float], List[float], List[float]]


def merge(latest: Dict[str, JointState]) -> Optional[Joints]:
    """Names, positions, velocities and efforts of every source heard so far, in SOURCES' order."""
    names: List[str] = []
    position: List[float] = []
    velocity: List[float] = []
    effort: List[float] = []
    for topic in SOURCES:
        msg = latest.get(topic)
        if msg is None:
            continue
        count = len(msg.name)
        names += list(msg.name)
        position += list(msg.position)[:count]
        velocity += (list(msg.velocity) + [0.0] * count)[:count]
        effort += (list(msg.effort) + [0.0] * count)[:count]
    return (names, position, velocity, effort) if names else None


def main() -> int:
    init_node("joint_state_publisher")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    counts = CountsFile.from_env(rospy.get_name())
    rate_hz = get_param("~rate", RATE_HZ, kind=float)
    if not 0.0 < rate_hz <= 1000.0:
        fail(f"parameter {rospy.get_name()}/rate is {rate_hz!r}; set a rate in (0, 1000] Hz, e.g. {RATE_HZ:g}")
    lock = threading.Lock()
    latest: Dict[str, JointState] = {}

    def heard(topic: str, msg: JointState) -> None:
        with lock:
            latest[topic] = msg

    publisher = rospy.Publisher("/joint_states", JointState, queue_size=5)
    subscribers = [rospy.Subscriber(topic, JointState, lambda m, t=topic: heard(t, m), queue_size=1)
                   for topic in SOURCES]
    rate = rospy.Rate(rate_hz)
    try:
        while not rospy.is_shutdown():
            with lock:
                merged = merge(latest)
            if merged is not None:
                names, position, velocity, effort = merged
                publisher.publish(JointState(header=Header(stamp=rospy.Time.now()), name=names, position=position,
                                             velocity=velocity, effort=effort))
                if counts is not None:
                    counts.add("published")
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
    finally:
        del subscribers
        if counts is not None:
            counts.close(stopped=True)
    return 0


if __name__ == "__main__":
    run_node(main)
