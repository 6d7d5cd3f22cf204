"""The lab twin's ``/franka_gripper``: franka_gripper's four actions and its finger joint states.

franka_gripper_node serves ``/franka_gripper/{move,grasp,homing,stop}`` and publishes
``/franka_gripper/joint_states`` (two finger joints, half the width each). Here the project's
simulated hand (:class:`hri_teleop.sim.hand.HandSim`, as lab_sim runs it, without an
object) carries the goals out. Counts: goals received per action, and the width
(:mod:`hri_teleop.ros.lab_twin.counts`).
"""

from __future__ import annotations

import functools
import threading
import time
from typing import Any, Dict, Optional

import actionlib
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Header

from hri_teleop.core.joints import FINGER_JOINT_NAMES
from hri_teleop.core.limits import ROBOT_PERIOD_S
from hri_teleop.ros.gripper_actions import ACTIONS, command_from_goal, end_goal
from hri_teleop.ros.lab_twin.counts import CountsFile
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.ros.stop_signals import init_node
from hri_teleop.sim.gripper_goals import GoalRecord
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.hand_params import HandSimError

__all__ = ["FrankaGripperTwin", "main", "PUBLISH_RATE_HZ", "LOOP_PERIOD_S"]

#: franka_gripper_node's publish_rate (Hz).
PUBLISH_RATE_HZ = 30.0
#: How often the hand is run up to the present (s); it steps its 1 ms cycles in between.
LOOP_PERIOD_S = 0.005


class FrankaGripperTwin:
    """The hand behind franka_gripper's interfaces, counting the goals that reach it."""

    def __init__(self, counts: Optional[CountsFile]) -> None:
        self.counts = counts
        self.rate_hz = get_param("~publish_rate", PUBLISH_RATE_HZ, kind=float)
        if not 0.0 < self.rate_hz <= 1000.0:
            fail(f"parameter {rospy.get_name()}/publish_rate is {self.rate_hz!r}; set a rate in (0, 1000] Hz, "
                 f"e.g. {PUBLISH_RATE_HZ:g}")
        self._lock = threading.Lock()
        self._t0 = time.monotonic()
        self.hand = HandSim(start_s=0.0)
        self._goals: Dict[int, Any] = {}  # hand goal id -> (action, handle), until ended
        self.joints_pub = rospy.Publisher("~joint_states", JointState, queue_size=5)
        self.servers = []
        for action, (spec, _result) in ACTIONS.items():
            server = actionlib.ActionServer(f"~{action}", spec, functools.partial(self._on_goal, action),
                                            functools.partial(self._on_cancel, action), auto_start=False)
            server.start()
            self.servers.append(server)
        self._width()
        rospy.loginfo("franka_gripper: actions %s/{move,grasp,homing,stop}, joint states on %s", rospy.get_name(),
                      self.joints_pub.resolved_name)

    def now(self) -> float:
        return time.monotonic() - self._t0

    def _width(self) -> None:
        if self.counts is not None:
            self.counts.set("width_m", round(self.hand.width_m, 6))

    def _step_locked(self, now: float) -> None:
        hand = self.hand
        while hand.now_s + ROBOT_PERIOD_S <= now + 1e-9:
            hand.step(hand.now_s + ROBOT_PERIOD_S)

    def _on_goal(self, action: str, handle: Any) -> None:
        if self.counts is not None:
            self.counts.add_to("goals", action)
        _spec, result_cls = ACTIONS[action]
        try:
            command = command_from_goal(action, handle.get_goal())
        except HandSimError as exc:  # a field that is not a number: only a broken client sends it
            handle.set_rejected(result_cls(success=False, error=str(exc)), str(exc))
            return
        now = self.now()
        with self._lock:
            self._step_locked(now)
            record = self.hand.send(command, max(now, self.hand.now_s))
            self._goals[record.goal_id] = (action, handle, record)
            handle.set_accepted(f"goal {record.goal_id}")

    def _on_cancel(self, _action: str, handle: Any) -> None:
        now = self.now()
        with self._lock:
            found = next((g for g in self._goals.values() if g[1] == handle), None)
            if found is None:
                return
            self._step_locked(now)
            self.hand.cancel(found[2], max(now, self.hand.now_s))

    def run(self) -> int:
        period = 1.0 / self.rate_hz
        next_publish = 0.0
        while not rospy.is_shutdown():
            now = self.now()
            with self._lock:
                self._step_locked(now)
                ended = [self._goals.pop(r.goal_id) for r in self.hand.pop_finished() if r.goal_id in self._goals]
                width = self.hand.width_m
                velocity = self.hand.joint_velocities_m_per_s
            for action, handle, record in ended:
                self._end(action, handle, record)
            if now >= next_publish:
                next_publish = max(next_publish + period, now)
                self._width()
                self.joints_pub.publish(JointState(header=Header(stamp=rospy.Time.now()),
                                                   name=list(FINGER_JOINT_NAMES), position=[0.5 * width] * 2,
                                                   velocity=list(velocity), effort=[0.0, 0.0]))
            time.sleep(LOOP_PERIOD_S)
        return 0

    def _end(self, action: str, handle: Any, record: GoalRecord) -> None:
        ended = end_goal(action, handle, record)
        if self.counts is not None:
            self.counts.add_to("goals_" + ended, action)


def main() -> int:
    init_node("franka_gripper")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    counts = CountsFile.from_env(rospy.get_name())
    try:
        return FrankaGripperTwin(counts).run()
    finally:
        if counts is not None:
            counts.close(stopped=True)


if __name__ == "__main__":
    run_node(main)
