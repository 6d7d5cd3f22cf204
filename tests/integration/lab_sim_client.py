#!/usr/bin/env python3
"""A scripted client of lab_sim for tests: gripper goals, velocity commands, service calls.

It plays a plan (``~plan``: path of a JSON file, a list of steps) against the simulated hardware and
writes what happened as JSON lines to ``~log`` (``t`` is wall-clock time in s, the clock
rosbag stamps with, so the test can line events up with recorded topics). Steps:

  {"goal": "move"|"grasp"|"homing"|"stop", "id": "m1", ...goal fields}  send (not wait)
      move: width, speed; grasp: width, speed, force, inner, outer
  {"wait": "m1", "timeout": 10}      until goal m1 is done (logs "result")
  {"cancel": "m1"}                   actionlib cancel of goal m1
  {"sleep": 0.5}
  {"mark": "name"}                   a timestamp for the test
  {"twists": [[vx, vy, vz, wx, wy, wz], ...], "rate_hz": 100}   published one per period
  {"call": "recover"}                the node's ~recover (std_srvs/Trigger); ``~sim`` "" : none (the lab twin)
  {"recover_action": 10}             franka_control's error_recovery action, waiting this long for its result

Every goal's terminal state is logged as {"event": "result", "id", "status", "success", "error"}; an
error recovery as {"event": "recovery", "status", "text"}.
"""

from __future__ import annotations

import json
import threading
import time

import actionlib
import rospy
from actionlib import CommState
from geometry_msgs.msg import Twist
from std_srvs.srv import Trigger

from hri_teleop.ros import franka_gripper_msgs as fg
from hri_teleop.ros import franka_msgs as fm
from hri_teleop.ros.error_recovery import recover_and_wait

SPECS = {"move": fg.MoveAction, "grasp": fg.GraspAction, "homing": fg.HomingAction, "stop": fg.StopAction}


def main() -> None:
    rospy.init_node("lab_sim_client")
    with open(rospy.get_param("~plan")) as fh:
        plan = json.load(fh)
    log = open(rospy.get_param("~log"), "a")
    sim = rospy.get_param("~sim", "/lab_sim")
    lock = threading.Lock()
    done = {}

    def write(**entry) -> None:
        with lock:
            log.write(json.dumps(dict(t=time.time(), **entry)) + "\n")
            log.flush()

    clients = {name: actionlib.ActionClient(f"/franka_gripper/{name}", spec) for name, spec in SPECS.items()}
    for name, client in clients.items():
        if not client.wait_for_server(rospy.Duration(20.0)):
            write(event="error", what=f"no {name} server")
            return
    recovery = actionlib.ActionClient("/franka_control/error_recovery", fm.ErrorRecoveryAction)
    if not recovery.wait_for_server(rospy.Duration(20.0)):
        write(event="error", what="no error_recovery server")
        return
    twist_pub = rospy.Publisher("/cartesian_velocity_controller/cmd_vel", Twist, queue_size=100)
    recover = None
    if sim:  # "" : franka_control itself (the lab twin), which has no ~recover service
        rospy.wait_for_service(f"{sim}/recover", 20.0)
        recover = rospy.ServiceProxy(f"{sim}/recover", Trigger)
    deadline = time.monotonic() + 10.0
    while twist_pub.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    handles = {}

    def on_transition(goal_id: str, handle) -> None:
        if handle.get_comm_state() != CommState.DONE or goal_id in done:
            return
        result = handle.get_result()
        done[goal_id] = True
        write(event="result", id=goal_id, status=handle.get_goal_status(),
              success=getattr(result, "success", None), error=getattr(result, "error", None))

    write(event="ready")
    for step in plan:
        if "goal" in step:
            kind, goal_id = step["goal"], step["id"]
            if kind == "move":
                goal = fg.MoveGoal(width=step["width"], speed=step["speed"])
            elif kind == "grasp":
                goal = fg.GraspGoal(width=step["width"], speed=step["speed"], force=step["force"],
                                    epsilon=fg.GraspEpsilon(inner=step["inner"], outer=step["outer"]))
            elif kind == "homing":
                goal = fg.HomingGoal()
            else:
                goal = fg.StopGoal()
            write(event="sent", id=goal_id, action=kind)
            handles[goal_id] = clients[kind].send_goal(
                goal, transition_cb=lambda h, goal_id=goal_id: on_transition(goal_id, h))
        elif "wait" in step:
            end = time.monotonic() + step.get("timeout", 10.0)
            while step["wait"] not in done and time.monotonic() < end:
                time.sleep(0.01)
            if step["wait"] not in done:
                write(event="timeout", id=step["wait"])
        elif "cancel" in step:
            write(event="cancel", id=step["cancel"])
            handles[step["cancel"]].cancel()
        elif "sleep" in step:
            time.sleep(step["sleep"])
        elif "mark" in step:
            write(event="mark", name=step["mark"])
        elif "twists" in step:
            period = 1.0 / step.get("rate_hz", 100.0)
            start = time.monotonic()
            sent = []
            for k, values in enumerate(step["twists"]):
                delay = start + k * period - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
                msg = Twist()
                msg.linear.x, msg.linear.y, msg.linear.z = values[:3]
                msg.angular.x, msg.angular.y, msg.angular.z = values[3:]
                twist_pub.publish(msg)
                sent.append([time.time()] + list(values))
            write(event="twists", sent=sent)
        elif "call" in step:
            assert recover is not None, "a ~recover call needs ~sim"
            response = recover()
            write(event="called", success=response.success, message=response.message)
        elif "recover_action" in step:
            write(event="sent", id="error_recovery", action="error_recovery")
            _found, finished, text = recover_and_wait("/franka_control/error_recovery", 1.0, step["recover_action"])
            write(event="recovery", status=finished, text=text)
    write(event="finished")
    log.close()


if __name__ == "__main__":
    main()
