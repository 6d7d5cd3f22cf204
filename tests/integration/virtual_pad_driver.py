#!/usr/bin/env python3
"""Drives teleoperation.py's virtual pad (``~virtual_joy``) for tests, waiting on the robot's state.

A pad script counts the node's ticks; this driver instead waits for what the simulated robot
reports, so a test never guesses how long a motion takes. ``~plan`` (a JSON file) is a list of
``{"pad": {"axes": {...}, "buttons": [...]}, "for": s}`` (that pad state for so long) or
``{"pad": ..., "until": "reflex" | "idle" | "still", "timeout": s}`` (until lab_sim's ~arm_status
state is that, or the twist is zero). Each step's end goes to ``~log`` as a JSON line with the
wall-clock time ``t`` (rosbag's clock): {"event": "done" | "timeout", "step": i}.
"""

from __future__ import annotations

import json
import time

import rospy
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Joy

from hri_teleop.core.gamepad import PadState
from hri_teleop.core.gamepad.layout import as_layout

RATE_HZ = 50.0


def main() -> None:
    rospy.init_node("virtual_pad_driver")
    with open(rospy.get_param("~plan")) as fh:
        plan = json.load(fh)
    log = open(rospy.get_param("~log"), "a")
    layout = as_layout(rospy.get_param("~layout", "dualshock4"))
    seen = {"state": "", "still": False}

    def on_status(msg: DiagnosticStatus) -> None:
        seen["state"] = next((kv.value for kv in msg.values if kv.key == "state"), "")

    def on_twist(msg: Twist) -> None:
        seen["still"] = all(c == 0.0 for c in (msg.linear.x, msg.linear.y, msg.linear.z,
                                                msg.angular.x, msg.angular.y, msg.angular.z))

    rospy.Subscriber(rospy.get_param("~arm_status", "/lab_sim/arm_status"), DiagnosticStatus, on_status)
    rospy.Subscriber(rospy.get_param("~twist_topic", "/cartesian_velocity_controller/cmd_vel"), Twist, on_twist)
    pub = rospy.Publisher("/teleoperation/virtual_joy", Joy, queue_size=1)
    deadline = time.monotonic() + 20.0
    while (pub.get_num_connections() == 0 or not seen["state"]) and time.monotonic() < deadline:
        time.sleep(0.01)

    def write(**entry: object) -> None:
        log.write(json.dumps(dict(t=time.time(), **entry)) + "\n")
        log.flush()

    write(event="ready", connected=pub.get_num_connections() > 0, state=seen["state"])
    period = 1.0 / RATE_HZ
    for index, step in enumerate(plan):
        pad = step.get("pad", {})
        state = PadState(pad.get("axes", {}), {b: True for b in pad.get("buttons", [])}, True)
        axes, buttons = layout.raw_from_state(state)
        msg = Joy(axes=[float(a) for a in axes], buttons=[int(b) for b in buttons])
        start = time.monotonic()
        end = start + step.get("for", step.get("timeout", 30.0))
        until = step.get("until")
        met = False
        while not rospy.is_shutdown() and time.monotonic() < end:
            msg.header.stamp = rospy.Time.now()
            pub.publish(msg)
            if until is not None and (seen["still"] if until == "still" else seen["state"] == until):
                met = True
                break
            time.sleep(period)
        write(event="timeout" if until is not None and not met else "done", step=index, state=seen["state"])
    log.close()


if __name__ == "__main__":
    main()
