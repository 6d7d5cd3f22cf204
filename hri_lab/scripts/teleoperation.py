#!/usr/bin/env python3
"""Teleoperation node (handout Ex. 8-10, 12-14): gamepad -> Cartesian twist, gripper width, rumble.

Every rule lives in hri_teleop.core.teleop.TeleopController; this script reads the settings
(``~config``, hri_lab/config/teleop.yaml, overridden by private parameters), opens the pad and once
per tick (``~rate``, 50 Hz) polls it, steps the controller and publishes the twist, /gripper_width,
/joy and ``~rumble``; it warns before a joint limit and sends error recovery on options. Quit,
Ctrl-C, SIGTERM and a lost pad all ramp the twist to zero first. Details: docs/ros-nodes.md.
"""

from __future__ import annotations

import math
import signal
import threading
import time
from typing import Any, Optional, TextIO, Tuple

import rosgraph
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState, Joy
from std_msgs.msg import Bool, Float32

from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.gamepad import GamepadError, PadState, RumbleRequests
from hri_teleop.core.gamepad.rumble import RUMBLE_CHECK_LEVEL, RUMBLE_CHECK_S
from hri_teleop.core.gamepad.stale import StaleInputWatch
from hri_teleop.core.joints import (
    CLEAR_MARGIN_RAD,
    FRANKA_JOINT_STATES_TOPIC,
    JOINT_STATES_TIMEOUT_S,
    WARNING_MARGIN_RAD,
    WARNING_PULSE_S,
    WARNING_RUMBLE,
    JointLimitWatch,
    JointsError,
    JointStateWarning,
    JointVector,
    positions_by_name,
)
from hri_teleop.core.limits import Watchdog
from hri_teleop.core.reflex import ERROR_RECOVERY_ACTION
from hri_teleop.core.teleop import (
    ButtonPress,
    TeleopCommand,
    TeleopController,
    TeleopError,
    check_extra_button,
    motor_rumble,
    next_tick_s,
    recovery_refusal,
)
from hri_teleop.hardware.gamepad import check_pad_rumble, open_gamepad
from hri_teleop.ros.clock import ClockError, NodeClock
from hri_teleop.ros.commands import command_publisher
from hri_teleop.ros.error_recovery import ErrorRecoveryRequester
from hri_teleop.ros.joy import joy_message
from hri_teleop.ros.params import fail, get_name_param, get_param, package_file, private_params, run_node
from hri_teleop.sim.virtual_pad import (
    RUMBLE_LOG_HEADER,
    RumbleRecord,
    ScriptedPad,
    VirtualPad,
    rumble_log_line,
)

#: Private parameters of this node that are not part of the teleop configuration.
NODE_ONLY_KEYS = ("config", "pad_script", "pad_index", "stop_timeout_s", "script_wait_s", "rumble_log",
                  "joint_states_topic", "joint_states_timeout_s", "joint_warning_margin_rad", "joint_warning_clear_rad",
                  "joint_warning_rumble", "joint_warning_pulse_s", "recover_button", "error_recovery_action",
                  "rumble_check_s", "rumble_check_level")
#: The joint warning's parameters: node parameter -> (core argument, default).
JOINT_WARNING_PARAMS = {"joint_warning_margin_rad": ("warn_margin_rad", WARNING_MARGIN_RAD),
                        "joint_warning_clear_rad": ("clear_margin_rad", CLEAR_MARGIN_RAD),
                        "joint_warning_rumble": ("rumble_level", WARNING_RUMBLE),
                        "joint_warning_pulse_s": ("pulse_period_s", WARNING_PULSE_S),
                        "joint_states_timeout_s": ("timeout_s", JOINT_STATES_TIMEOUT_S)}


def default_config_path() -> str:
    """hri_lab/config/teleop.yaml of the package this script belongs to ('' if not found)."""
    return package_file("config/teleop.yaml", __file__)


def joint_warning_from_params(name: str) -> JointStateWarning:
    """The joint-limit warning from the node's parameters; a bad one ends the node naming it."""
    values = {param: get_param(f"~{param}", default, kind=float) for param, (_arg, default) in JOINT_WARNING_PARAMS.items()}
    args = {JOINT_WARNING_PARAMS[param][0]: value for param, value in values.items()}
    try:
        timeout_s = args.pop("timeout_s")
        return JointStateWarning(JointLimitWatch(**args), timeout_s)
    except JointsError as exc:
        message = str(exc)
        for param, (arg, _default) in JOINT_WARNING_PARAMS.items():  # speak the parameters' names
            message = message.replace(arg, f"~{param}")
        fail(f"{name} parameters: {message}")


def _twist_msg(twist: Tuple[float, ...]) -> Twist:
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = twist[0], twist[1], twist[2]
    msg.angular.x, msg.angular.y, msg.angular.z = twist[3], twist[4], twist[5]
    return msg


class TeleoperationNode:
    """The shell around TeleopController: pad in, topics out (docs/ros-nodes.md)."""

    def __init__(self) -> None:
        name = rospy.get_name()
        self.config_path = get_param("~config", "", kind=str).strip() or default_config_path()
        # The node reads the file itself, not <rosparam load> in the launch file: a YAML
        # mistake is then one line with the file, the line and the fix.
        self.config = load_teleop_config(self.config_path, private_params(exclude=NODE_ONLY_KEYS),
                                         f"{name} private parameters")
        params = self.config.params
        pad_script = get_param("~pad_script", "", kind=str).strip()
        pad_index = get_param("~pad_index", 0, kind=int)
        self.stop_timeout_s = get_param("~stop_timeout_s", 3.0, kind=float)
        self.script_wait_s = get_param("~script_wait_s", 10.0, kind=float)
        if not self.script_wait_s >= 0:
            fail(f"parameter {name}/script_wait_s is {self.script_wait_s!r}; set it to a time in s >= 0, e.g. 10.0")
        if not self.stop_timeout_s > 0:
            fail(f"parameter {name}/stop_timeout_s is {self.stop_timeout_s!r}; set it to a positive time in s, e.g. 3.0")

        self.controller = TeleopController(params, self.config.limits, self.config.robot.cartesian_limits)
        self.dt_s = 1.0 / params.rate_hz
        # Wall clock in the lab; /clock when the autograder owns the time (/use_sim_time).
        self.clock = NodeClock()
        # A scripted pad runs on the node's ticks, not on the wall clock: step k happens at
        # the same tick in every run, however busy the machine (tests, the demo, traces).
        self._ticks = 0
        self._script_pending = bool(pad_script)  # the script waits for the robot (see tick)
        self._script_wait_started: Optional[float] = None
        self._next_listen_check = 0.0
        self.pad = open_gamepad(self.config.pad, self.config.layout, index=pad_index,
                                script=pad_script or None, log=rospy.logwarn,
                                clock=(lambda: self._ticks * self.dt_s) if pad_script else None)
        self.pad_watchdog = Watchdog(params.input_timeout_s)
        # A real pad whose held stick reads bit for bit the same counts as lost (core.gamepad.stale);
        # not a pad driven by code or sliders, whose exact values may rightly stay the same.
        self.stale_watch = (StaleInputWatch(params.stale_input_timeout_s, params.deadzone, params.assignment.axes_used())
                            if getattr(self.pad, "stale_input_watch", False) else None)
        # pad:=virtual without a script is driven by messages on ~virtual_joy (a notebook
        # widget, a test, `rosbag play` of a recorded /joy): its input is fresh only while
        # they keep coming, so the watchdog is fed by them, not by polling.
        self.topic_driven = isinstance(self.pad, VirtualPad) and not isinstance(self.pad, ScriptedPad)
        self.virtual_joy_sub = (rospy.Subscriber("~virtual_joy", Joy, self.on_virtual_joy, queue_size=1)
                                if self.topic_driven else None)

        self._force: Optional[Tuple[float, float]] = None  # (value, arrival time on self.clock)
        self._force_arrived = threading.Event()  # wakes the loop between ticks (see _sleep_until)
        self._stop_requested = threading.Event()
        self._abort = threading.Event()  # a second stop signal: give up the ramp
        self._stopped = threading.Event()
        self.rumble_requests = RumbleRequests()  # when to send the pad a request
        self.rumble_log = self._open_rumble_log(get_param("~rumble_log", "", kind=str).strip())
        self._poll_error_logged = False
        self._quit_logged = False
        self.last_command: Optional[TeleopCommand] = None

        self.twist_pub = command_publisher(self.config.twist_topic, Twist, params.rate_hz)  # every tick, in order
        self.width_pub = rospy.Publisher("gripper_width", Float32, queue_size=1)
        self.joy_pub = rospy.Publisher("joy", Joy, queue_size=1)
        self.rumble_pub = rospy.Publisher("~rumble", Float32, queue_size=1)
        self.rumble_ok_pub = rospy.Publisher("~rumble_ok", Bool, queue_size=1, latch=True)
        self.force_sub = rospy.Subscriber("force_mapped", Float32, self.on_force, queue_size=1)

        # Before a joint limit: a warning from the robot's joint states (logged, and a pulse on the pad).
        self.joint_warning = joint_warning_from_params(name)
        self._joint_state: Optional[Tuple[JointVector, float]] = None  # (positions, arrival), from the callback
        self._joint_state_fed: Optional[Tuple[JointVector, float]] = None
        # After a reflex: a press of ~recover_button sends franka_control's error recovery.
        try:
            recover_button = check_extra_button(params, get_param("~recover_button", "start", kind=str).strip(),
                                                "recover_button")
        except TeleopError as exc:
            fail(f"parameter {name}/{exc}")
        self.recover_press = ButtonPress(recover_button)
        joint_states_topic = get_name_param("~joint_states_topic", FRANKA_JOINT_STATES_TOPIC)
        self.recovery = ErrorRecoveryRequester(get_name_param("~error_recovery_action", ERROR_RECOVERY_ACTION))
        self.joint_states_sub = rospy.Subscriber(joint_states_topic, JointState, self.on_joint_states, queue_size=1)
        self._check_rumble(name)
        rospy.loginfo(
            "teleoperation at %.0f Hz: pad %s (%s, layout %s: %s), twist on %s, k_trans %.3f m/s, "
            "k_rot %.3f rad/s, k_gripper %.3f m/s (config %s)", params.rate_hz, self.config.pad,
            getattr(self.pad, "name", "?"), self.pad.layout.name,
            getattr(self.pad, "layout_reason", "set by the configuration"), self.twist_pub.resolved_name,
            params.k_trans, params.k_rot, params.k_gripper, self.config_path or "built-in defaults")

    def _check_rumble(self, name: str) -> None:
        """A short rumble at start: refused -> one line with cause and fix; ~rumble_ok (latched) says which."""
        duration_s = get_param("~rumble_check_s", RUMBLE_CHECK_S, kind=float)
        level = get_param("~rumble_check_level", RUMBLE_CHECK_LEVEL, kind=float)
        if not (0.0 <= duration_s <= 2.0 and 0.0 < level <= 1.0):
            fail(f"parameters {name}/rumble_check_s {duration_s!r} and rumble_check_level {level!r}: set a time in "
                 "0..2 s (0: no check) and a strength in (0, 1], e.g. 0.2 and 0.5")
        if duration_s == 0.0:
            return  # no check asked
        refusal = check_pad_rumble(self.pad, self.controller.params.feedback, level, duration_s)
        if refusal is None:
            return  # a pad that cannot tell, or a pad that must stay silent (feedback: false)
        self.rumble_ok_pub.publish(Bool(data=not refusal))
        if refusal:
            rospy.logwarn(refusal)

    # -- inputs -----------------------------------------------------------------------
    def on_force(self, msg: Float32) -> None:
        self._force = (float(msg.data), self.clock.now())
        self._force_arrived.set()

    def on_joint_states(self, msg: JointState) -> None:
        """The arm's seven positions by name (the loop feeds them to the warning: one thread touches it)."""
        positions = positions_by_name(msg.name, msg.position)
        if positions is not None:
            self._joint_state = (positions, self.clock.now())

    def on_virtual_joy(self, msg: Joy) -> None:
        """Raw axes/buttons in the layout's order (as this node publishes on /joy)."""
        try:
            self.pad.set_raw(msg.axes, msg.buttons)
        except GamepadError as exc:
            rospy.logwarn_throttle(5.0, "ignoring a ~virtual_joy message: %s" % (exc,))
            return
        self.pad_watchdog.feed(self.clock.now())

    def _read_pad(self, now: float) -> Optional[Any]:
        """The pad's state, or None when there is none to act on.

        A failed read gives None and a disconnected reading is passed on as it is: the
        controller stops on both at once. A connected reading counts only while the input
        is fresh (the watchdog: fed by every good poll, or for the topic-driven virtual pad
        by its messages); input older than input_timeout also gives None, and so do readings
        of a real pad frozen with a stick held for stale_input_timeout (core.gamepad.stale).
        """
        try:
            state = self.pad.poll()
        except GamepadError as exc:
            if not self._poll_error_logged:
                rospy.logwarn("cannot read the gamepad (%s): bringing the robot to a stop", exc)
                self._poll_error_logged = True
            state = None
        if state is not None and state.connected:
            if not self.topic_driven:
                self.pad_watchdog.feed(now)
            self._poll_error_logged = False
        if state is not None and state.connected and self.pad_watchdog.is_stale(now):
            return None  # no fresh input for input_timeout: stop as for a lost pad
        if self.stale_watch is not None and self._frozen(state, now):
            return None
        return state

    def _frozen(self, state: Optional[PadState], now: float) -> bool:
        """The stale-input watchdog: True while a held stick's readings are frozen (one log line each way)."""
        assert self.stale_watch is not None
        was = self.stale_watch.stale
        if self.stale_watch.update(state, now):
            if not was:
                rospy.logwarn("gamepad %r: its readings have not changed for %.1f s with a stick held "
                              "(stale_input_timeout): a wireless link that dropped? Treating the pad as lost, the "
                              "twist ramps to zero; move a stick, or reconnect the pad (a USB cable), to continue",
                              getattr(self.pad, "name", "?"), self.stale_watch.timeout_s)
            return True
        if was:
            rospy.loginfo("gamepad readings change again: teleoperation continues")
        return False

    # -- one tick ---------------------------------------------------------------------
    def _robot_listens(self, now: float) -> bool:
        """Whether something other than a recorder (rosbag's /record_*) subscribes to the twist.

        Asks the master at most every 0.25 s, and only while the script waits.
        """
        if self.twist_pub.get_num_connections() == 0 or now < self._next_listen_check:
            return False
        self._next_listen_check = now + 0.25
        try:
            _pubs, subs, _srvs = rosgraph.Master(rospy.get_name()).getSystemState()
        except Exception as exc:  # noqa: BLE001 - master unreachable: keep waiting, ~script_wait_s bounds it
            rospy.logdebug("cannot ask the master for subscribers: %s", exc)
            return False
        names = next((nodes for topic, nodes in subs if topic == self.twist_pub.resolved_name), [])
        return any(not name.startswith("/record") for name in names)

    def _script_may_start(self, now: float) -> bool:
        """A pad script starts once the velocity controller listens (or after ~script_wait_s).

        Nodes of one launch start in any order. A script that moved the stick before the
        (real or simulated) robot subscribed would hand it a velocity out of the blue: a
        step, which the Franka refuses. So the script's clock starts at the first tick
        with a subscriber on the twist topic other than a recorder (rosbag record may
        subscribe first); with no robot at all it starts anyway after ~script_wait_s.
        """
        if not self._script_pending:
            return True
        if self._script_wait_started is None:
            self._script_wait_started = now
            rospy.loginfo("pad script waits for a subscriber on %s (at most %.0f s) before it starts",
                          self.twist_pub.resolved_name, self.script_wait_s)
        if self._robot_listens(now):
            rospy.loginfo("pad script starts: %s has a subscriber", self.twist_pub.resolved_name)
        elif now - self._script_wait_started >= self.script_wait_s:
            rospy.logwarn("pad script starts without a subscriber on %s after %.0f s",
                          self.twist_pub.resolved_name, self.script_wait_s)
        else:
            return False
        self._script_pending = False
        return True

    def tick(self, stopping: bool = False) -> TeleopCommand:
        now = self.clock.now()
        if stopping:
            state = None
        elif not self._script_may_start(now):
            state = PadState.neutral()  # the operator has not started yet
            self.pad_watchdog.feed(now)
        else:
            state = self._read_pad(now)
        force = self._force
        value, age = (force[0], now - force[1]) if force is not None else (None, math.inf)
        cmd = self.controller.step(state, value, age, self.dt_s)
        self.last_command = cmd
        self.twist_pub.publish(_twist_msg(cmd.twist))
        self.width_pub.publish(Float32(data=cmd.gripper_width_m))
        self._watch_joints(now)
        motors = self._motors(cmd.rumble, now, cmd.stopping)
        self.rumble_pub.publish(Float32(data=max(motors)))  # what the pad feels at most
        if state is not None:
            self._publish_joy(state)
        self._rumble(motors, now)
        if self.recover_press.update(state):
            refusal = recovery_refusal(cmd.twist)
            if refusal is None:
                self.recovery.request()
            else:
                rospy.logwarn(refusal)
        if not self._script_pending:
            self._ticks += 1
        if cmd.quit and not self._quit_logged:
            rospy.loginfo("quit pressed (%s): ramping the twist to zero, then exiting",
                          self.controller.params.quit_button)
            self._quit_logged = True
        return cmd

    def _watch_joints(self, now: float) -> None:
        """Feed the latest joint state to the warning; one log line when a warning starts or goes stale."""
        joints = self._joint_state
        if joints is not None and joints is not self._joint_state_fed:
            self._joint_state_fed = joints
            started = self.joint_warning.update(*joints)
            if started is not None:
                rospy.logwarn("joint limit: %s", started.describe())
        if self.joint_warning.expire(now):
            rospy.logwarn("joint limit warning ended: no joint states for %.2f s (nothing is known of the joints)",
                          self.joint_warning.timeout_s)

    def _publish_joy(self, state: Any) -> None:
        self.joy_pub.publish(joy_message(self.pad.layout, state))

    def _motors(self, force_rumble: float, now: float, stopping: bool) -> Tuple[float, float]:
        """(low, high) motor strengths: force and joint warning apart or combined (~rumble_motors)."""
        params = self.controller.params
        return motor_rumble(force_rumble, self.joint_warning.rumble(now), stopping, params.feedback,
                            params.rumble_motors)

    def _rumble(self, motors: Tuple[float, float], now: float) -> None:
        request = self.rumble_requests.update_motors(motors[0], motors[1], now)
        if request is None:
            return
        low, high, duration_s = request
        two_motors = getattr(self.pad, "rumble_motors", None)
        if two_motors is not None:
            two_motors(low, high, duration_s)
        else:
            self.pad.rumble(max(low, high), duration_s)
        if self.rumble_log is not None:
            record = RumbleRecord(time.monotonic(), max(low, high), duration_s, low, high)
            self.rumble_log.write(rumble_log_line(record) + "\n")

    @staticmethod
    def _open_rumble_log(path: str) -> Optional[TextIO]:
        if not path:
            return None
        try:
            log = open(path, "w", buffering=1)  # line-buffered: a killed node loses nothing
        except OSError as exc:
            fail(f"cannot write the rumble log {path!r} ({exc.strerror}); set ~rumble_log to a writable file or ''")
        log.write(RUMBLE_LOG_HEADER + "\n")
        return log

    def _sleep_until(self, due_s: float) -> None:
        """Sleep until the tick due at ``due_s``, answering each force that arrives meanwhile.

        Why not rospy.Rate: a force would then wait for the next tick before the operator
        feels it, on average half a period and up to a whole one (10 and 20 ms at 50 Hz),
        which `make bench` measured as most of the force-to-rumble latency. The pad is
        still only touched from this thread; the callback only wakes it.
        """
        while not rospy.is_shutdown() and not self._stop_requested.is_set():
            if self.clock.reached(due_s):
                return
            if self.clock.sleep_until(due_s, self._force_arrived):
                self._force_arrived.clear()
                self._rumble_on_arrival()
            elif self.clock.sim_time:
                return  # reached, or the clock's owner stopped it: do not spin

    def _rumble_on_arrival(self) -> None:
        """The rumble for the force that just arrived, by the controller's rule (none while stopping)."""
        force = self._force
        if force is None:
            return
        now = self.clock.now()
        last = self.last_command
        self._rumble(self._motors(self.controller.rumble_between_ticks(force[0], now - force[1]), now,
                                  last is None or last.stopping), now)

    # -- running and stopping ---------------------------------------------------------
    def request_stop(self, *_args: object) -> None:
        """SIGINT/SIGTERM: ramp to zero first; a second signal abandons the ramp at once.

        Runs in the main thread between two bytecodes of the loop: it only sets flags,
        the loop does the work (blocking here would stall the ramp it waits for).
        """
        if self._stop_requested.is_set():
            self._abort.set()
            return
        self._stop_requested.set()

    def _on_rospy_shutdown(self) -> None:
        """rospy is shutting down from outside (rosnode kill): let the loop ramp first."""
        self._stop_requested.set()
        if threading.current_thread() is not threading.main_thread():
            self._stopped.wait(self.stop_timeout_s + 0.5)

    def run(self) -> int:
        rospy.on_shutdown(self._on_rospy_shutdown)
        try:
            due_s = self.clock.wait_started()
        except ClockError as exc:
            fail(str(exc))
        try:
            while not rospy.is_shutdown() and not self._stop_requested.is_set():
                self.tick()
                if self.controller.finished:
                    rospy.loginfo("twist is zero after quit: teleoperation ends")
                    return 0
                due_s = next_tick_s(due_s, self.clock.now(), self.dt_s)
                self._sleep_until(due_s)
            self._ramp_to_zero()
            return 0
        except rospy.ROSInterruptException:
            self._ramp_to_zero()
            return 0
        except Exception:
            # A bug must not leave the robot with its last velocity: ramp, then report it.
            rospy.logerr("teleoperation failed; ramping the twist to zero before exiting")
            self._ramp_to_zero()
            raise
        finally:
            self._stopped.set()
            self.pad.rumble(0.0, 0.0)
            self.pad.close()
            if self.rumble_log is not None:
                self.rumble_log.close()

    def _ramp_to_zero(self) -> None:
        """Keep publishing with the pad ignored until the limited twist is exactly zero."""
        deadline = self.clock.now() + self.stop_timeout_s
        last = self.last_command
        if last is None or all(c == 0.0 for c in last.twist):
            self.tick(stopping=True)  # still say "zero" once to whoever listens
            return
        rospy.loginfo("stopping: ramping the twist to zero")
        zero_ticks = 0
        while self.clock.now() < deadline and zero_ticks < 2 and not self._abort.is_set():
            cmd = self.tick(stopping=True)
            zero_ticks = zero_ticks + 1 if all(c == 0.0 for c in cmd.twist) else 0
            self.clock.sleep_until(self.clock.now() + self.dt_s)  # not rospy.Rate: it may be shutting down
        if self._abort.is_set():
            rospy.logwarn("second stop signal: ramp abandoned at %s", self.last_command.twist if self.last_command else None)
        elif zero_ticks < 2:
            rospy.logwarn("twist not zero after %.1f s of ramping; last command %s",
                          self.stop_timeout_s, self.last_command.twist if self.last_command else None)


def main() -> int:
    # Our own SIGINT/SIGTERM handling: rospy's would stop publishing at once, mid-motion.
    rospy.init_node("teleoperation", disable_signals=True)
    node = TeleoperationNode()
    signal.signal(signal.SIGINT, node.request_stop)
    signal.signal(signal.SIGTERM, node.request_stop)
    code = node.run()
    rospy.signal_shutdown("teleoperation finished")
    return code


if __name__ == "__main__":
    run_node(main)
