#!/usr/bin/env python3
"""Gripper manager (handout Ex. 12): target width on /gripper_width -> franka_gripper move goals.

teleoperation.py publishes the target opening every tick (50 Hz); sending each as a goal would
flood the Franka Hand, so hri_teleop.core.gripper.GoalThrottle decides which targets become goals
(``~min_step_m``, ``~settle_s``, ``~max_goal_rate_hz``) and a new goal cancels an unfinished one.
Without an action server on ``~action_ns`` it warns once and sends the latest target when one
appears. Parameters: hri_lab/README.md, in full docs/ros-nodes.md.
"""

from __future__ import annotations

import threading
from typing import Optional

import actionlib
import rospy
from actionlib import CommState
from actionlib_msgs.msg import GoalStatus
from std_msgs.msg import Float32

from hri_teleop.student import (
    GRIPPER_MAX_WIDTH_M,
    GoalThrottle,
    MoveAction,
    MoveGoal,
    NodeClock,
    fail,
    get_param,
    goal_status_name,
    run_node,
    usable_width_m,
)

#: How often the action server's presence is checked (each check blocks at most 50 ms).
SERVER_CHECK_PERIOD_S = 0.25



class GripperManager:
    """Forwards width targets to the gripper's move action, throttled by GoalThrottle."""

    def __init__(self) -> None:
        name = rospy.get_name()
        self.action_ns = get_param("~action_ns", "/franka_gripper/move", kind=str)
        self.speed = get_param("~speed", 0.1, kind=float)
        self.width_min = get_param("~width_min_m", 0.0, kind=float)
        self.width_max = get_param("~width_max_m", GRIPPER_MAX_WIDTH_M, kind=float)  # the robot's hand, open
        if not self.speed > 0:
            fail(f"parameter {name}/speed is {self.speed!r}; set it to a positive speed in m/s, e.g. 0.1")
        if not 0.0 <= self.width_min < self.width_max:
            fail(f"parameters {name}/width_min_m={self.width_min!r} and width_max_m={self.width_max!r} "
                 f"do not form a range; use 0.0 and {GRIPPER_MAX_WIDTH_M:g} (the robot's hand)")
        self.throttle = GoalThrottle(
            min_step_m=get_param("~min_step_m", 0.002, kind=float),
            max_goal_rate_hz=get_param("~max_goal_rate_hz", 5.0, kind=float),
            settle_s=get_param("~settle_s", 0.2, kind=float),
            clock=NodeClock().now,  # goals per second of ROS time: /clock when the grader owns it
        )
        self._lock = threading.Lock()
        self._target: Optional[float] = None
        self._goal: Optional[actionlib.ClientGoalHandle] = None  # the latest goal sent ...
        self._goal_width = 0.0  # ... and its width
        self._server_ready = False
        self._warned_missing = False
        self._warned_clamp = False
        # The plain ActionClient, not SimpleActionClient: replacing a goal that is still
        # running is normal here, and SimpleActionClient logs an error for every status
        # update of a goal it no longer tracks.
        self.client = actionlib.ActionClient(self.action_ns, MoveAction)
        self.sub = rospy.Subscriber("gripper_width", Float32, self.on_width, queue_size=1)
        rospy.Timer(rospy.Duration(SERVER_CHECK_PERIOD_S), self.check_server)
        # Lets the settle rule fire when targets stop arriving.
        rospy.Timer(rospy.Duration(0.05), lambda _e: self.maybe_send())
        rospy.loginfo("forwarding %s to %s (min step %.4f m, at most %.1f goals/s, speed %.3f m/s)",
                      self.sub.resolved_name, self.action_ns, self.throttle.min_step_m,
                      self.throttle.max_goal_rate_hz, self.speed)

    def check_server(self, _event: object = None) -> None:
        """Notice the action server coming and going without ever blocking for long."""
        if rospy.is_shutdown():
            return
        ready = bool(self.client.wait_for_server(rospy.Duration(0.05)))
        if rospy.is_shutdown():
            return
        if ready and not self._server_ready:
            rospy.loginfo("gripper action server %s is up", self.action_ns)
        elif not ready and self._server_ready:
            rospy.logwarn("gripper action server %s went away; holding the target until it is back",
                          self.action_ns)
        elif not ready and not self._warned_missing:
            rospy.logwarn("no gripper action server on %s yet: start the robot (teleoperation.launch "
                          "robot:=true) or the gripper simulation; targets wait until it appears",
                          self.action_ns)
            self._warned_missing = True
        self._server_ready = ready
        if ready:
            self.maybe_send()

    def on_width(self, msg: Float32) -> None:
        width, problem = usable_width_m(msg.data, self.width_min, self.width_max)
        if problem and not self._warned_clamp:
            rospy.logwarn("%s (said once)", problem)
            self._warned_clamp = True
        if width is None:
            return
        with self._lock:
            self._target = width
        self.maybe_send()

    def maybe_send(self) -> None:
        with self._lock:
            target = self._target
            if target is None or not self._server_ready or rospy.is_shutdown():
                return
            if not self.throttle.should_send(target):
                return
            previous = self._goal
            if previous is not None and previous.get_comm_state() != CommState.DONE:
                # A newer target preempts the older goal: cancel it, then send the new one.
                previous.cancel()
            self._goal_width = target
            self._goal = self.client.send_goal(MoveGoal(width=target, speed=self.speed),
                                               transition_cb=self._on_transition)
            self.throttle.sent(target)
            rospy.logdebug("move goal %.4f m sent (%d so far)", target, self.throttle.goals_sent)

    def _on_transition(self, goal: actionlib.ClientGoalHandle) -> None:
        """Report a move that failed; replaced (older) goals are ignored."""
        if self._goal is None or goal != self._goal or goal.get_comm_state() != CommState.DONE:
            return
        state = goal.get_goal_status()
        result = goal.get_result()
        if state in (GoalStatus.PREEMPTED, GoalStatus.RECALLED):
            return
        if state == GoalStatus.SUCCEEDED and getattr(result, "success", True):
            return
        error = getattr(result, "error", "") if result is not None else ""
        rospy.logwarn_throttle(2.0, "gripper move to %.4f m ended %s%s", self._goal_width,
                               goal_status_name(state), f": {error}" if error else "")


def main() -> int:
    rospy.init_node("gripper_manager")
    GripperManager()
    rospy.spin()
    return 0


if __name__ == "__main__":
    run_node(main)
