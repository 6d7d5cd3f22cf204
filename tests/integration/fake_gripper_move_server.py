#!/usr/bin/env python3
"""A stand-in franka_gripper move action server for tests: logs every goal it gets.

Each goal is accepted, then succeeds after ``~move_time_s`` unless it is cancelled first.
Goal events go as JSON lines to ``~log`` (time in s, event, width in m, and the goal's stamp:
when its client sent it, on the client's clock, free of the transport's delays).
"""

from __future__ import annotations

import json
import threading
import time

import actionlib
import rospy

from hri_teleop.ros.franka_gripper_msgs import MoveAction, MoveResult


def main() -> None:
    rospy.init_node("fake_franka_gripper")
    log_path = rospy.get_param("~log")
    move_time_s = float(rospy.get_param("~move_time_s", 0.3))
    lock = threading.Lock()
    log = open(log_path, "a")

    def write(event: str, width: float, stamp: float) -> None:
        with lock:
            log.write(json.dumps({"t": time.time(), "event": event, "width": width, "stamp": stamp}) + "\n")
            log.flush()

    def on_goal(handle) -> None:
        width = handle.get_goal().width
        stamp = handle.get_goal_id().stamp.to_sec()
        handle.set_accepted()
        write("goal", width, stamp)

        def finish(_event) -> None:
            status = handle.get_goal_status().status
            if status in (1, 6):  # ACTIVE or PREEMPTING
                handle.set_succeeded(MoveResult(success=True))
                write("done", width, stamp)

        rospy.Timer(rospy.Duration(move_time_s), finish, oneshot=True)

    def on_cancel(handle) -> None:
        handle.set_canceled(MoveResult(success=False))
        write("cancel", handle.get_goal().width, handle.get_goal_id().stamp.to_sec())

    server = actionlib.ActionServer("/franka_gripper/move", MoveAction, on_goal, on_cancel, auto_start=False)
    server.start()
    rospy.spin()


if __name__ == "__main__":
    main()
