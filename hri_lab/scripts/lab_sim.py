#!/usr/bin/env python3
"""The lab's hardware, simulated: Franka arm and hand, an object, the FSR board.

One node, one job: it runs a :class:`hri_teleop.sim.world.LabWorld` (a 1 kHz arm that
judges every command like the robot, the hand with franka_gripper's goals, the object, the piston
attachment and the sensor board) in real time, behind exactly the real hardware's interfaces, so
teleoperation.py, gripper_manager.py and mapping_node.py cannot tell it from the lab. Its clock
(wall or /clock), parameters, topics, actions and services: docs/ros-nodes.md.
"""

from __future__ import annotations

import os

# Before numpy loads: the arm solves a 7 x 7 system every millisecond, which older OpenBLAS builds
# (numpy 1.24, the lab PCs' Python 3.8) hand to a second thread that spins on the other core.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import functools
import threading
import time
from typing import Any, Dict, List, Optional, Tuple

import actionlib
import rospy
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, Float64, Header, Int16, UInt32
from std_srvs.srv import Trigger, TriggerResponse

from hri_teleop.core.joints import (
    FRANKA_JOINT_STATES_TOPIC,
    JOINT_ERRORS,
    nearest_limit,
)
from hri_teleop.core.reflex import explain_reflex
from hri_teleop.ros import franka_msgs as fm
from hri_teleop.ros.clock import ClockError, NodeClock
from hri_teleop.ros.gripper_actions import ACTIONS, command_from_goal, end_goal
from hri_teleop.ros.params import (
    fail,
    get_name_param,
    get_param,
    package_file,
    private_params,
    refuse_beside_hardware,
    run_node,
)
from hri_teleop.ros.stop_signals import init_node
from hri_teleop.sim.arm import (
    ACCELERATION_DISCONTINUITY,
    EVENT_RECOVERED,
    EVENT_REFLEX,
    NON_FINITE_COMMAND,
    STATE_REFLEX,
    STATE_TIMEOUT,
    VELOCITY_DISCONTINUITY,
    VELOCITY_LIMITS_VIOLATION,
)
from hri_teleop.sim.config import (
    default_sim_yaml,
    describe,
    load_world_config,
    world_overrides_from_params,
)
from hri_teleop.sim.gripper_goals import GoalRecord
from hri_teleop.sim.hand_params import HandSimError
from hri_teleop.sim.world import LabWorld, ObjectStatus

#: Private parameters of the node itself; every other private parameter is a sim.yaml override.
NODE_KEYS = ("config", "scenario", "twist_topic", "gripper_ns", "control_ns", "board", "frame_id", "gripper_rate_hz",
             "state_controller_rate_hz", "state_rate_hz", "status_rate_hz", "object_rate_hz", "loop_period_s",
             "stall_s")
#: Every name the arm reports a violation under, in the order ~arm_status lists them.
ARM_ERRORS = (VELOCITY_LIMITS_VIOLATION, VELOCITY_DISCONTINUITY, ACCELERATION_DISCONTINUITY, NON_FINITE_COMMAND,
              *(error for _what, error in JOINT_ERRORS))
def default_config_path() -> str:
    """hri_lab/config/sim.yaml of the package this script belongs to ('' if not found)."""
    found = package_file("config/sim.yaml", __file__)
    if not found:
        in_checkout = default_sim_yaml()
        found = str(in_checkout) if in_checkout is not None else ""
    return found


class _Goal:
    """An accepted actionlib goal and the hand's record of it."""

    __slots__ = ("action", "handle", "record")

    def __init__(self, action: str, handle: Any, record: GoalRecord) -> None:
        self.action = action
        self.handle = handle
        self.record = record


class LabSimNode:
    """The shell around LabWorld: ROS in, world stepped in real time, ROS out (docs/ros-nodes.md)."""

    def __init__(self) -> None:
        name = rospy.get_name()
        self.name = name
        config_path = get_param("~config", "", kind=str).strip() or default_config_path()
        scenario = get_param("~scenario", "", kind=str).strip()
        overrides = world_overrides_from_params(private_params(), f"{name} private parameters", NODE_KEYS)
        self.config = load_world_config(config_path, overrides, f"{name} private parameters",
                                        scenario=scenario or None)
        robot = self.config.robot  # sim.yaml's robot: its topics and action namespaces are the defaults
        twist_topic = get_name_param("~twist_topic", robot.topics["twist_command"])
        gripper_ns = get_name_param("~gripper_ns", robot.gripper.namespace, namespace=True)
        control_ns = get_name_param("~control_ns", robot.topics["error_recovery"].rsplit("/", 1)[0] or "/",
                                    namespace=True)
        self.board_on = get_param("~board", True, kind=bool)
        self.frame_id = get_param("~frame_id", "panda_link0", kind=str)
        periods = {}
        for param, default in (("gripper_rate_hz", 30.0), ("state_controller_rate_hz", 30.0), ("state_rate_hz", 100.0),
                               ("status_rate_hz", 10.0), ("object_rate_hz", 20.0)):
            rate = get_param(f"~{param}", default, kind=float)
            if not 0.0 < rate <= 1000.0:
                fail(f"parameter {name}/{param} is {rate!r}; set it to a rate in (0, 1000] Hz, e.g. {default:g}")
            periods[param] = 1.0 / rate
        self.loop_period_s = get_param("~loop_period_s", 0.002, kind=float)
        if not 0.0 < self.loop_period_s <= 0.05:
            fail(f"parameter {name}/loop_period_s is {self.loop_period_s!r}; set it to (0, 0.05] s, e.g. 0.002")
        self.stall_s = get_param("~stall_s", 0.1, kind=float)
        if not self.stall_s > 2 * self.loop_period_s:
            fail(f"parameter {name}/stall_s is {self.stall_s!r}; set it above twice ~loop_period_s, e.g. 0.1")
        self._periods = {"joints": periods["gripper_rate_hz"], "arm_joints": periods["state_controller_rate_hz"],
                         "state": periods["state_rate_hz"],
                         "status": periods["status_rate_hz"], "object": periods["object_rate_hz"]}
        self._next_due = {key: 0.0 for key in self._periods}

        # Outputs first: they exist before anything can happen.
        self.force_pub = rospy.Publisher("/pub_force", Int16, queue_size=20) if self.board_on else None
        self.joints_pub = rospy.Publisher(f"{gripper_ns}/joint_states", JointState, queue_size=5)
        # franka_state_controller's arm joints and joint_state_publisher's merge of arm and hand.
        self.arm_joints_pub = (rospy.Publisher(FRANKA_JOINT_STATES_TOPIC, JointState, queue_size=5)
                               if self.config.arm.joints else None)
        self.all_joints_pub = rospy.Publisher("/joint_states", JointState, queue_size=5)
        self.pose_pub = rospy.Publisher("~ee_pose", PoseStamped, queue_size=5)
        self.twist_pub = rospy.Publisher("~ee_twist", TwistStamped, queue_size=5)
        self.grip_pub = rospy.Publisher("~grip_force", Float32, queue_size=5)
        self.status_pub = rospy.Publisher("~arm_status", DiagnosticStatus, queue_size=5)
        self.violations_pub = rospy.Publisher("~violations", UInt32, queue_size=1, latch=True)
        self.command_time_pub = rospy.Publisher("~command_time_s", Float64, queue_size=100, tcp_nodelay=True)
        self.object_pub = rospy.Publisher("~object", DiagnosticStatus, queue_size=5)

        # The world and its clock; every callback and the loop touch it under this lock.
        # Lock order: an actionlib server's lock may be held while taking this one (goal and
        # cancel callbacks), never the other way round: goal results are sent outside it.
        self._lock = threading.Lock()
        self.world = LabWorld(self.config, start_s=0.0)
        # the joints as the robot of this world reports them (its profile: HRI_ROBOT, or sim.yaml's robot:)
        self.joint_names = list(self.config.robot.joint_names)
        self.finger_joints = list(self.config.robot.gripper.finger_joints)
        self.clock = NodeClock()
        self.sim_time = self.clock.sim_time
        # On the wall clock the world starts now; under /clock when the clock starts (run()),
        # after every topic, server and service below is registered.
        self._t0: Optional[float] = None if self.sim_time else self.clock.now()
        self._clock_lock = threading.Lock()
        self._last_wall = self._t0 or 0.0
        self._skipped_s = 0.0
        self.stalls = 0
        self._last_command_s = float("-inf")  # when the last velocity command was applied (see now())
        self._samples: List[Tuple[float, int]] = []
        self._goals: Dict[int, _Goal] = {}   # hand goal id -> goal, until reported
        self._ids: Dict[str, int] = {}       # actionlib goal id -> hand goal id, same lifetime
        self._status_key: Optional[tuple] = None
        self._violations_sent = -1
        self._crushed = False
        self._lifted = False
        self._held_aloft = False  # lifted and carried by friction at the last tick

        self.servers = []
        for action, (spec, _result) in ACTIONS.items():
            server = actionlib.ActionServer(f"{gripper_ns}/{action}", spec,
                                            functools.partial(self._on_goal, action),
                                            functools.partial(self._on_cancel, action), auto_start=False)
            server.start()
            self.servers.append(server)
        # franka_control's error recovery; ~recover (a Trigger) does the same, for a quick rosservice call.
        self.recovery_server = actionlib.ActionServer(f"{control_ns}/error_recovery", fm.ErrorRecoveryAction,
                                                      self._on_error_recovery, auto_start=False)
        self.recovery_server.start()
        self.recover_srv = rospy.Service("~recover", Trigger, self._on_recover)
        self.twist_sub = rospy.Subscriber(twist_topic, Twist, self._on_twist, queue_size=100, tcp_nodelay=True)
        rospy.loginfo("simulating the lab: %s. Commands on %s, gripper actions on %s/{move,grasp,homing,stop}, "
                      "error recovery on %s/error_recovery%s", describe(self.config), self.twist_sub.resolved_name,
                      gripper_ns, control_ns, ", board on /pub_force" if self.board_on else ", board off (~board false)")

    # -- clock and world ------------------------------------------------------------------

    def now(self) -> float:
        """Simulation time: seconds since the world was created, less this process's stalls.

        The loop asks for the time every ~loop_period_s. When it has not for more than
        ~stall_s, this process was starved (a busy machine), not idle: the commands that
        were sent meanwhile are still waiting to be read. Running the world through that
        gap would judge a command timeout and then a step that never happened, so the
        simulated time skips the stall (and says so, at most every 5 s).
        """
        if self.sim_time:
            return rospy.get_time() - self._t0 if self._t0 is not None else 0.0
        with self._clock_lock:
            wall = time.monotonic()
            gap = wall - self._last_wall
            if gap > self.stall_s:
                self._skipped_s += gap - self.loop_period_s
                self.stalls += 1
                rospy.logwarn_throttle(5.0, "simulation stalled for %.0f ms (the machine is busy): simulated "
                                       "time skips it (%d stalls, %.2f s skipped so far)"
                                       % (gap * 1e3, self.stalls, self._skipped_s))
            self._last_wall = wall
            return wall - (self._t0 or 0.0) - self._skipped_s

    def _await_clock_after(self, last_s: float, wait_s: float = 5.0) -> None:
        """Under /clock: a command can overtake the tick it belongs to (the node heard the new time
        first). Wait until this process's clock has moved past the last command's time, so each
        tick's command is applied at its own tick, never on top of the one before. The wait ends
        on rospy's own clock update (its condition), however long a busy machine delays it;
        ``wait_s`` (beyond the grader's step timeout) only keeps a clock that stopped from
        holding the node for ever."""
        cond = rospy.rostime.get_rostime_cond()
        deadline = time.monotonic() + wait_s
        with cond:  # read under the lock that the /clock update notifies with: no update is missed
            while not (self.now() > last_s or rospy.is_shutdown()):
                left = deadline - time.monotonic()
                if left <= 0:
                    return
                cond.wait(min(left, 0.1))

    def _advance_locked(self, now: float) -> None:
        """Run the world up to ``now`` (hold the lock); keep the board's samples for the loop."""
        samples = self.world.advance(now)
        if samples:
            self._samples.extend(samples)

    # -- inputs ---------------------------------------------------------------------------

    def _on_twist(self, msg: Twist) -> None:
        if self.sim_time:
            self._await_clock_after(self._last_command_s)
        stamp = rospy.get_time()
        now = self.now()
        self._last_command_s = now
        twist = (msg.linear.x, msg.linear.y, msg.linear.z, msg.angular.x, msg.angular.y, msg.angular.z)
        with self._lock:
            self._advance_locked(now)
            self.world.command_twist(twist, now)
        self.command_time_pub.publish(Float64(data=stamp))

    def _on_goal(self, action: str, handle: Any) -> None:
        _spec, result_cls = ACTIONS[action]
        try:
            command = command_from_goal(action, handle.get_goal())
        except HandSimError as exc:  # a field that is not a number: only a broken client sends it
            handle.set_rejected(result_cls(success=False, error=str(exc)), str(exc))
            return
        now = self.now()
        with self._lock:
            self._advance_locked(now)
            record = self.world.send_gripper(command, now)
            self._goals[record.goal_id] = _Goal(action, handle, record)
            self._ids[handle.get_goal_id().id] = record.goal_id
            # Accepted before the loop can collect the record as finished (it does so under this lock).
            handle.set_accepted(f"simulated hand goal {record.goal_id}")

    def _on_cancel(self, action: str, handle: Any) -> None:
        now = self.now()
        with self._lock:
            goal = self._goals.get(self._ids.get(handle.get_goal_id().id, -1))
            if goal is None:
                return  # already finished; its result is on its way
            self._advance_locked(now)
            self.world.cancel_gripper(goal.record, now)  # a running goal ends PREEMPTED

    def _recover(self) -> str:
        """Clear a reflex, as franka_control's error recovery does; what happened, in one line."""
        now = self.now()
        with self._lock:
            self._advance_locked(now)
            errors = self.world.arm.reflex_errors
            recovered = self.world.arm.recover(now)
            state = self.world.arm.state
        if recovered:
            return f"recovered from reflex [{', '.join(errors)}]; the arm accepts commands again"
        return f"no reflex to recover from (the arm is {state})"

    def _on_error_recovery(self, handle: Any) -> None:
        """franka_msgs/ErrorRecoveryAction: recover, then succeed (the world's lock is free again by then)."""
        message = self._recover()
        handle.set_accepted(message)
        # franka_control's error recovery succeeds whether or not there was an error.
        handle.set_succeeded(fm.ErrorRecoveryResult(), message)

    def _on_recover(self, _request: Any) -> TriggerResponse:
        return TriggerResponse(success=True, message=self._recover())

    # -- the loop -------------------------------------------------------------------------

    def run(self) -> int:
        period = self.loop_period_s
        if self.sim_time:
            return self._run_on_ros_time(period)
        wake = time.monotonic()
        while not rospy.is_shutdown():
            self.tick()
            wake += period
            delay = wake - time.monotonic()
            if delay > 0.0:
                time.sleep(delay)
            else:
                wake = time.monotonic()  # late: carry on from now, never in a burst
        return 0

    def _run_on_ros_time(self, period: float) -> int:
        """One tick each time /clock has moved by at least ``period`` (however far it jumped)."""
        try:
            self._t0 = self.clock.wait_started()  # the grader starts it once all is connected
        except ClockError as exc:
            fail(str(exc))
        while not rospy.is_shutdown():
            self.tick()
            try:
                rospy.sleep(period)
            except rospy.exceptions.ROSTimeMovedBackwardsException:
                continue
            except rospy.ROSInterruptException:
                break
        return 0

    def _due(self, key: str, now: float) -> bool:
        due = self._next_due[key]
        if now < due:
            return False
        period = self._periods[key]
        self._next_due[key] = due + period if now - due < period else now + period
        return True

    def tick(self) -> None:
        """Run the world up to now, then publish, report and log what it produced."""
        now = self.now()
        due = {key: self._due(key, now) for key in self._periods}
        world = self.world
        arm, hand = world.arm, world.hand
        with self._lock:
            self._advance_locked(now)
            samples, self._samples = self._samples, []
            events = arm.new_events()
            finished: List[_Goal] = []
            for record in hand.pop_finished():
                goal = self._goals.pop(record.goal_id, None)
                if goal is not None:  # every goal is tracked from its acceptance
                    self._ids.pop(goal.handle.get_goal_id().id, None)
                    finished.append(goal)
            width = hand.width_m
            joint_v = hand.joint_velocities_m_per_s
            arm_q, arm_dq = (arm.joint_positions, arm.joint_velocities) if due["arm_joints"] else (None, None)
            explanation = self._reflex_words_locked()[0] if any(e.kind == EVENT_REFLEX for e in events) else ""
            pose = arm.pose if due["state"] else None
            velocity = arm.velocity
            grip = hand.grip_force_n
            state = arm.state
            violations = arm.violation_count
            status = self._arm_status_values() if due["status"] or (state, violations) != self._status_key else None
            obj = world.object_status()
            peak, ever_grasped, ever_lifted = world.peak_grip_force_n, world.ever_grasped, world.ever_lifted

        if self.force_pub is not None:
            for _t, count in samples:
                self.force_pub.publish(Int16(data=count))
        for goal in finished:
            self._report(goal)
        for event in events:
            self._log_event(event, explanation)
        stamp = rospy.Time.now()
        if due["joints"]:
            self.joints_pub.publish(JointState(
                header=self._header(stamp, ""), name=self.finger_joints, position=[0.5 * width, 0.5 * width],
                velocity=list(joint_v), effort=[0.0, 0.0]))
        if due["arm_joints"]:
            self._publish_joint_states(stamp, arm_q, arm_dq, width, joint_v)
        if pose is not None:
            msg = PoseStamped(header=self._header(stamp, self.frame_id))
            p, q = msg.pose.position, msg.pose.orientation
            p.x, p.y, p.z = pose.position_m
            q.x, q.y, q.z, q.w = pose.orientation_xyzw
            self.pose_pub.publish(msg)
            tmsg = TwistStamped(header=self._header(stamp, self.frame_id))
            lin, ang = tmsg.twist.linear, tmsg.twist.angular
            lin.x, lin.y, lin.z, ang.x, ang.y, ang.z = velocity
            self.twist_pub.publish(tmsg)
            self.grip_pub.publish(Float32(data=grip))
        if status is not None:
            self._status_key = (state, violations)
            self.status_pub.publish(status)
        if violations != self._violations_sent:
            self._violations_sent = violations
            self.violations_pub.publish(UInt32(data=violations))
        self._watch_object(obj)
        if due["object"]:
            self.object_pub.publish(self._object_status(obj, peak, ever_grasped, ever_lifted))

    # -- outputs --------------------------------------------------------------------------

    @staticmethod
    def _header(stamp: rospy.Time, frame_id: str) -> Header:
        return Header(stamp=stamp, frame_id=frame_id)

    def _report(self, goal: _Goal) -> None:
        """A finished hand goal -> its actionlib terminal state, with success/error as the hand says."""
        record = goal.record
        ended = end_goal(goal.action, goal.handle, record)
        if ended == "succeeded" and not record.success:
            rospy.logwarn("gripper %s goal %d ended without success: %s", goal.action, record.goal_id, record.detail)
        elif ended == "aborted":
            rospy.logwarn("gripper %s goal %d aborted: %s%s", goal.action, record.goal_id, record.error,
                          f" ({record.detail})" if record.detail else "")
        elif ended == "preempted":
            rospy.logdebug("gripper %s goal %d preempted: %s", goal.action, record.goal_id, record.detail)

    def _publish_joint_states(self, stamp: rospy.Time, q: Optional[Tuple[float, ...]], dq: Optional[Tuple[float, ...]],
                              width: float, finger_v: Tuple[float, float]) -> None:
        """franka_state_controller's arm joints, and /joint_states: the arm's then the fingers (width/2
        each), as joint_state_publisher merges them; the fingers alone when the arm has no joints."""
        names, position, velocity = list(self.finger_joints), [0.5 * width, 0.5 * width], list(finger_v)
        if q is not None and dq is not None and self.arm_joints_pub is not None:
            self.arm_joints_pub.publish(JointState(header=self._header(stamp, ""), name=list(self.joint_names),
                                                   position=list(q), velocity=list(dq), effort=[0.0] * 7))
            names, position, velocity = list(self.joint_names) + names, list(q) + position, list(dq) + velocity
        self.all_joints_pub.publish(JointState(header=self._header(stamp, ""), name=names, position=position,
                                               velocity=velocity, effort=[0.0] * len(names)))

    def _log_event(self, event: Any, explanation: str) -> None:
        if event.kind == EVENT_REFLEX:
            rospy.logerr("simulated Franka at %.3f s: %s", event.time_s, event.message)
            if explanation:
                rospy.logerr("%s", explanation)
        elif event.kind == EVENT_RECOVERED:
            rospy.loginfo("simulated Franka at %.3f s: %s", event.time_s, event.message)
        else:  # command timeout, workspace limit, command ignored
            rospy.logwarn("simulated Franka at %.3f s: %s", event.time_s, event.message)

    def _reflex_words_locked(self) -> Tuple[str, str]:
        """The current reflex in plain words, and how near its nearest limit the joints stand
        ("", "" without a reflex; call under the lock)."""
        arm = self.world.arm
        if arm.state != STATE_REFLEX:
            return "", ""
        explanation = "\n".join(explain_reflex([violation.cause() for violation in arm.reflex_violations]))
        q = arm.joint_positions
        return explanation, (nearest_limit(q, self.config.robot.joint_limits).describe() if q is not None else "")

    def _arm_status_values(self) -> DiagnosticStatus:
        """~arm_status from the arm (call under the lock)."""
        arm = self.world.arm
        state = arm.state
        level = (DiagnosticStatus.ERROR if state == STATE_REFLEX
                 else DiagnosticStatus.WARN if state == STATE_TIMEOUT else DiagnosticStatus.OK)
        counts = arm.violation_counts
        x, y, z = arm.position_m
        values = [KeyValue(key="state", value=state), KeyValue(key="violations", value=str(arm.violation_count))]
        values += [KeyValue(key=error, value=str(counts.get(error, 0))) for error in ARM_ERRORS]
        values += [KeyValue(key="ignored_commands", value=str(arm.ignored_command_count)),
                   KeyValue(key="reflex_errors", value=", ".join(arm.reflex_errors)),
                   KeyValue(key="position_m", value=f"{x:.4f} {y:.4f} {z:.4f}")]
        explanation, nearest = self._reflex_words_locked()
        values += [KeyValue(key="explanation", value=explanation), KeyValue(key="nearest_joint_limit", value=nearest)]
        return DiagnosticStatus(level=level, name=f"{self.name}: arm", message=arm.status,
                                hardware_id="simulated Franka Panda", values=values)

    def _object_status(self, obj: Any, peak: float, ever_grasped: bool, ever_lifted: bool) -> DiagnosticStatus:
        if obj is None:
            return DiagnosticStatus(level=DiagnosticStatus.OK, name=f"{self.name}: object",
                                    message="no object on the table", hardware_id="simulated object",
                                    values=[KeyValue(key="name", value="none"),
                                            KeyValue(key="peak_grip_force_n", value=f"{peak:.3f}")])
        flags = [w for w, on in (("crushed", obj.crushed), ("held", obj.held), ("grasped", obj.grasped),
                                 ("lifted", obj.lifted), ("in contact", obj.in_contact),
                                 ("between the fingers", obj.between_fingers)) if on]
        message = (f"{obj.name}: {', '.join(flags) or 'on the table, not touched'}; height {obj.height_m:.3f} m, "
                   f"grip {obj.grip_force_n:.2f} N (peak {peak:.2f} N)")
        values = [("name", obj.name), ("height_m", f"{obj.height_m:.4f}"),
                  ("between_fingers", obj.between_fingers), ("in_contact", obj.in_contact), ("held", obj.held),
                  ("grasped", obj.grasped), ("lifted", obj.lifted), ("crushed", obj.crushed),
                  ("grip_force_n", f"{obj.grip_force_n:.3f}"), ("peak_grip_force_n", f"{peak:.3f}"),
                  ("ever_grasped", ever_grasped), ("ever_lifted", ever_lifted)]
        return DiagnosticStatus(
            level=DiagnosticStatus.ERROR if obj.crushed else DiagnosticStatus.OK, name=f"{self.name}: object",
            message=message, hardware_id="simulated object",
            values=[KeyValue(key=k, value=str(v).lower() if isinstance(v, bool) else str(v)) for k, v in values])

    def _watch_object(self, obj: Optional[ObjectStatus]) -> None:
        """Log once when the object is crushed, lifted, put down or dropped."""
        if obj is None:
            return
        thing = self.world.hand.object  # immutable: safe to read outside the lock
        if obj.crushed and not self._crushed:
            breaking = thing.breaking_force_n if thing is not None else None
            rospy.logwarn("the %s was crushed: the grip force passed its breaking force of %s N; stop closing "
                          "earlier (the rumble says when the piston is pressed)", obj.name,
                          f"{breaking:g}" if breaking is not None else "?")
        self._crushed = obj.crushed
        if obj.lifted and not self._lifted:
            rospy.loginfo("the %s is lifted (%.3f m above the table, grip %.2f N)", obj.name, obj.height_m,
                          obj.grip_force_n)
        elif self._lifted and not obj.lifted:
            if self._held_aloft:
                rospy.loginfo("the %s is back on the table", obj.name)
            elif not obj.crushed:  # a crushed one falls too: said already
                need = thing.min_grip_force_n() if thing is not None else float("nan")
                rospy.logwarn("the %s dropped: it slipped out of the fingers (a grip of %.2f N holds it; "
                              "squeeze harder or lift more gently)", obj.name, need)
        self._held_aloft = obj.lifted and obj.held
        self._lifted = obj.lifted


def main() -> int:
    init_node("lab_sim")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    refuse_beside_hardware("the simulated Franka lab_sim.py")
    node = LabSimNode()
    return node.run()


if __name__ == "__main__":
    run_node(main)
