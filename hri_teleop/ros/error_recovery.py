"""The error recovery of franka_control, asked for from a node: one goal per request, never blocking.

The teleoperation node sends it on a pad gesture from its control loop, which must not wait for a
server or a result: :meth:`ErrorRecoveryRequester.request` checks for a connected server without
waiting, sends the goal, and the result arrives in rospy's thread as one log line. The same goal
goes to franka_control_node in the lab and to lab_sim at home (docs/ros-nodes.md).
"""

from __future__ import annotations

import threading
from typing import Any, List, Optional, Tuple

import actionlib
import rospy
from actionlib import CommState
from actionlib_msgs.msg import GoalStatus

from hri_teleop.ros.franka_msgs import ErrorRecoveryAction, ErrorRecoveryGoal

__all__ = ["ErrorRecoveryRequester", "recover_and_wait", "status_name"]

_STATUS_NAMES = {getattr(GoalStatus, name): name for name in
                 ("PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING", "RECALLING",
                  "RECALLED", "LOST")}


class ErrorRecoveryRequester:
    """An actionlib client of ``franka_msgs/ErrorRecoveryAction`` that never blocks its caller."""

    def __init__(self, action_ns: str) -> None:
        self.action_ns = rospy.resolve_name(action_ns)
        self._client = actionlib.ActionClient(self.action_ns, ErrorRecoveryAction)
        self._lock = threading.RLock()
        self._pending: Optional[Any] = None  # the goal handle sent last, until its result

    def server_ready(self) -> bool:
        """Whether a server is connected now: it sent its status, and it subscribes to our goals."""
        client = self._client
        return client.last_status_msg is not None and client.pub_goal.get_num_connections() > 0

    def request(self) -> bool:
        """Send one recovery goal (True), or say in one line why not: no server, or one still under way."""
        if not self.server_ready():
            with self._lock:
                self._pending = None  # a goal to a server that went away has no result to wait for
            rospy.logwarn("error recovery: no franka_msgs/ErrorRecoveryAction server on %s; in the lab start "
                          "franka_control (franka_control.launch), at home lab_sim (teleoperation.launch sim:=true)",
                          self.action_ns)
            return False
        with self._lock:
            if self._pending is not None:
                rospy.loginfo("error recovery: the last request is still under way on %s", self.action_ns)
                return False
            self._pending = self._client.send_goal(ErrorRecoveryGoal(), transition_cb=self._on_transition)
        rospy.loginfo("error recovery: goal sent to %s", self.action_ns)
        return True

    def _on_transition(self, handle: Any) -> None:
        if handle.get_comm_state() != CommState.DONE:
            return
        with self._lock:
            if self._pending is None or handle != self._pending:
                return  # an older goal's, or said already
            self._pending = None
        status = handle.get_goal_status()
        text = handle.get_goal_status_text()
        if status == GoalStatus.SUCCEEDED:
            rospy.loginfo("error recovery succeeded: %s", text or "the robot accepts commands again")
        else:
            rospy.logwarn("error recovery ended %s: %s", _STATUS_NAMES.get(status, str(status)),
                          text or "no reason given; look at the robot's log (franka_control or lab_sim)")


def status_name(status: Optional[int]) -> str:
    """actionlib's name of a goal status (SUCCEEDED, ABORTED, ...); "no answer" for None."""
    return "no answer" if status is None else _STATUS_NAMES.get(status, str(status))


def recover_and_wait(action_ns: str, server_timeout_s: float, result_timeout_s: float
                     ) -> Tuple[bool, Optional[int], str]:
    """Send one recovery goal and wait for its end: (server found, final status or None, status text).

    Not SimpleActionClient: it stores the goal handle only after sending, so a server as fast as
    lab_sim can answer first, and the answer is logged as "not tracking" and lost. Here the
    callback needs no stored handle, and the handle is kept alive until the end.
    """
    client = actionlib.ActionClient(rospy.resolve_name(action_ns), ErrorRecoveryAction)
    if not client.wait_for_server(rospy.Duration.from_sec(max(0.1, server_timeout_s))):
        return False, None, ""
    done = threading.Event()
    ended: List[Tuple[int, str]] = []

    def on_transition(handle: Any) -> None:
        if handle.get_comm_state() == CommState.DONE and not done.is_set():
            ended.append((handle.get_goal_status(), handle.get_goal_status_text()))
            done.set()

    handle = client.send_goal(ErrorRecoveryGoal(), transition_cb=on_transition)
    finished = done.wait(max(0.1, result_timeout_s))
    del handle  # kept alive until here: actionlib tracks goals by weak reference
    if not finished:
        return True, None, ""
    return True, ended[0][0], ended[0][1]
