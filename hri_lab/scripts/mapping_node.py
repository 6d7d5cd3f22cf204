#!/usr/bin/env python3
"""Mapping node (handout Ex. 5): raw count on /pub_force -> mapped force 0..1 on /force_mapped.

The range is 0../max_sensor_force (the count with the piston pressed level with the housing,
Ex. 11), checked at start: a bad value ends the node with one line naming the fix. Unlike the
handout, the node re-reads the parameter every ``~reread_period_s`` (1.0 s), so a calibration set
during the lab applies without a restart; a bad value set while running is reported once and the
last good one stays. One /force_mapped per count, published from the callback (docs/ros-nodes.md).
"""

from __future__ import annotations

import threading

import rospy
from std_msgs.msg import Float32, Int16

from hri_teleop.core.mapping import MappingError, map_force, validate_max_sensor_force
from hri_teleop.ros.params import fail, get_param, run_node

PARAM = "/max_sensor_force"
_NOTHING = object()


class MappingNode:
    """Holds the current range and maps every incoming count."""

    def __init__(self) -> None:
        self.max_sensor_force = validate_max_sensor_force(rospy.get_param(PARAM, None), PARAM)
        self._lock = threading.Lock()
        self._reported_bad: object = _NOTHING
        self.pub = rospy.Publisher("force_mapped", Float32, queue_size=10)
        self.sub = rospy.Subscriber("pub_force", Int16, self.on_count, queue_size=10)
        rospy.loginfo("mapping %s -> %s over 0..%g", self.sub.resolved_name, self.pub.resolved_name,
                      self.max_sensor_force)

    def on_count(self, msg: Int16) -> None:
        with self._lock:
            maximum = self.max_sensor_force
        self.pub.publish(Float32(data=map_force(int(msg.data), maximum)))

    def reread(self, _event: object = None) -> None:
        """Pick up a new /max_sensor_force; keep the old one if the new one is bad."""
        try:
            value = rospy.get_param(PARAM, None)
        except Exception as exc:  # noqa: BLE001 - the master may be going away at shutdown
            rospy.logdebug("could not re-read %s: %s", PARAM, exc)
            return
        try:
            new = validate_max_sensor_force(value, PARAM)
        except MappingError as exc:
            if value != self._reported_bad:
                self._reported_bad = value
                rospy.logerr("%s (still mapping over 0..%g)", exc, self.max_sensor_force)
            return
        self._reported_bad = _NOTHING
        with self._lock:
            old, self.max_sensor_force = self.max_sensor_force, new
        if new != old:
            rospy.loginfo("%s changed: now mapping over 0..%g (was %g)", PARAM, new, old)


def main() -> int:
    rospy.init_node("mapping_node")
    period_s = get_param("~reread_period_s", 1.0, kind=float)
    if period_s < 0:
        fail(f"parameter {rospy.get_name()}/reread_period_s is {period_s!r}; set it to 0 (read once) or a period in seconds, e.g. 1.0")
    node = MappingNode()
    if period_s > 0:
        rospy.Timer(rospy.Duration(period_s), node.reread)
    rospy.spin()
    return 0


if __name__ == "__main__":
    run_node(main)
