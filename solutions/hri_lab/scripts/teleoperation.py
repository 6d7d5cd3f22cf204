#!/usr/bin/env python3
"""Handout Ex. 8-9: teleoperation with a gamepad -- Cartesian velocity, gripper width, rumble.

Ex. 8: complete the four methods marked "Ex. 8" in the class Teleoperation. run() reads
       the gamepad: every event sets the variables of the pad state below (booleans for the
       buttons, floats for the sticks); your methods turn them into the commands.
Ex. 9: complete the parts marked "Ex. 9": the node, its publishers and subscriber, the
       rate, and the messages (teleoperation_subscriber_publisher.py has the lines).

Controller assignment (handout Figure 7). Sticks read +1 to the right and +1 up.
  translation mode:  left stick up/down    -> v_x  (up = forward, +x)
                     left stick left/right -> v_y  (left = +y: the base frame's y points left)
                     right stick up/down   -> v_z  (up = +z)
  rotation mode:     the same sticks       -> w_x, w_y, w_z
  triangle: switch translation <-> rotation (once per press)
  cross: close the gripper while held      circle: open the gripper while held
         (both held: the width does not change)
  square: quit (the robot is brought to rest first)
The checks of Ex. 8-10 grade exactly this assignment. To try another one (Ex. 10),
change a copy of this file (teleoperation_remapped.py), not this one.

Run it:
  rosrun hri_lab teleoperation.py                          # the lab's gamepad
  rosrun hri_lab teleoperation.py _pad:=virtual _pad_script:=/abs/path/script.yaml
                                                           # no gamepad: a scripted virtual pad
  rosrun hri_lab teleoperation.py _pad:=browser            # a gamepad read by the notebook's page
                                                           # (widgets.BrowserPad; at home, not in the lab)
Parameters (private, with their defaults): ~rate 50.0 (Hz), ~k_trans 0.1 (m/s at full
stick), ~k_rot 0.3 (rad/s at full stick), ~k_gripper 0.04 (m/s), ~deadzone 0.1,
~pad pygame|virtual|browser, ~layout dualshock4|dualsense|xbox, ~pad_script "" (virtual pad only),
~wait_for_robot_s 5.0 (s: how long the pad waits for the robot to listen before it starts),
~feedback true (false: the pad never rumbles, Ex. 14's condition without feedback; set it
before the node starts: rosparam set /teleoperation/feedback false).
"""

import signal
import time

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float32

from hri_teleop.student import (
    JOYAXISMOTION,
    JOYBUTTONDOWN,
    JOYBUTTONUP,
    PadState,
    TwistLimiter,
    normalize_analog_input,
    open_gamepad,
    pad_events,
)

GRIPPER_MIN_WIDTH = 0.0   # m
GRIPPER_MAX_WIDTH = 0.08  # m: the Franka Hand opens 0 .. 0.08 m
FORCE_TIMEOUT = 1.0       # s: an older /force_mapped value no longer makes the pad rumble
STOP_TIMEOUT = 3.0        # s: longest ramp to rest when quitting


class Teleoperation:
    """The gamepad's state, and what the node computes from it once per tick."""

    def __init__(self, rate=50.0, k_trans=0.1, k_rot=0.3, k_gripper=0.04, deadzone=0.1):
        self.rate = float(rate)            # Hz: run() computes and publishes this often
        self.k_trans = float(k_trans)      # m/s at full stick deflection
        self.k_rot = float(k_rot)          # rad/s at full stick deflection
        self.k_gripper = float(k_gripper)  # m/s while cross or circle is held
        self.deadzone = float(deadzone)    # fraction of stick travel ignored around the centre

        # The gamepad's state, set by handle_event()
        self.left_x = 0.0          # left stick, -1 (left) .. +1 (right)
        self.left_y = 0.0          # left stick, -1 (down) .. +1 (up)
        self.right_x = 0.0         # right stick
        self.right_y = 0.0
        self.close_gripper = False  # cross is held
        self.open_gripper = False   # circle is held
        self.quit = False           # square was pressed

        # What the node computes
        self.rotation_mode = False                  # False: sticks drive v_x.., True: w_x..
        self.gripper_width = GRIPPER_MAX_WIDTH      # m, starts open
        self.cartesian_velocity = [0.0] * 6         # [v_x, v_y, v_z, w_x, w_y, w_z], m/s and rad/s
        self.force = 0.0                            # latest value on /force_mapped, 0..1
        self.force_time = None                      # when it arrived (ROS time, rospy.get_time())
        self.rumble = 0.0                           # vibration intensity 0..1
        self.feedback = True                        # False: the pad never rumbles (Ex. 14's other condition)

    # -- the gamepad ------------------------------------------------------------------
    def handle_event(self, event):
        """Store one gamepad event in the variables above (handout: "Analyze the run() function")."""
        if event.type == JOYAXISMOTION:
            if event.axis in ("left_x", "left_y", "right_x", "right_y"):
                setattr(self, event.axis, event.value)
        elif event.type == JOYBUTTONDOWN:
            if event.button == "south":      # cross
                self.close_gripper = True
            elif event.button == "east":     # circle
                self.open_gripper = True
            elif event.button == "north":    # triangle: once per press
                self.toggle_mode()
            elif event.button == "west":     # square
                self.quit = True
        elif event.type == JOYBUTTONUP:
            if event.button == "south":
                self.close_gripper = False
            elif event.button == "east":
                self.open_gripper = False

    def normalize_analog_input(self, value):
        """A stick value -1..1 without drift: 0 inside the dead zone (handout Figure 8)."""
        return normalize_analog_input(value, self.deadzone)

    # -- Ex. 8 ------------------------------------------------------------------------
    def toggle_mode(self):
        """Ex. 8: triangle was pressed: switch between translation and rotation mode."""
        ### BEGIN SOLUTION
        self.rotation_mode = not self.rotation_mode
        ### END SOLUTION

    def update_gripper_width(self):
        """Ex. 8: once per tick: while cross is held close, while circle is held open the
        gripper by k_gripper / rate; keep the width within GRIPPER_MIN_WIDTH .. GRIPPER_MAX_WIDTH."""
        ### BEGIN SOLUTION
        step = self.k_gripper / self.rate
        if self.close_gripper:
            self.gripper_width -= step
        if self.open_gripper:
            self.gripper_width += step
        self.gripper_width = min(GRIPPER_MAX_WIDTH, max(GRIPPER_MIN_WIDTH, self.gripper_width))
        ### END SOLUTION

    def update_cartesian_velocity(self):
        """Ex. 8: once per tick: the sticks (through normalize_analog_input) times k_trans or
        k_rot into self.cartesian_velocity, following the controller assignment above; the
        half of the mode that is not active is zero."""
        ### BEGIN SOLUTION
        x = self.normalize_analog_input(self.left_y)
        y = -self.normalize_analog_input(self.left_x)
        z = self.normalize_analog_input(self.right_y)
        if self.rotation_mode:
            self.cartesian_velocity = [0.0, 0.0, 0.0, self.k_rot * x, self.k_rot * y, self.k_rot * z]
        else:
            self.cartesian_velocity = [self.k_trans * x, self.k_trans * y, self.k_trans * z, 0.0, 0.0, 0.0]
        ### END SOLUTION

    def update_rumble(self):
        """Ex. 8: once per tick: the vibration intensity self.rumble from the mapped force
        self.force, limited to 0..1."""
        ### BEGIN SOLUTION
        self.rumble = min(1.0, max(0.0, self.force))
        ### END SOLUTION

    # -- Ex. 9: ROS -------------------------------------------------------------------
    def connect(self):
        """Ex. 9: the publishers of the velocity command (geometry_msgs/Twist on
        /cartesian_velocity_controller/cmd_vel) and of the gripper width (std_msgs/Float32
        on /gripper_width), and the subscriber of /force_mapped (callback: self.on_force)."""
        ### BEGIN SOLUTION
        self.twist_pub = rospy.Publisher("/cartesian_velocity_controller/cmd_vel", Twist, queue_size=1)
        self.gripper_pub = rospy.Publisher("/gripper_width", Float32, queue_size=1)
        self.force_sub = rospy.Subscriber("/force_mapped", Float32, self.on_force)
        ### END SOLUTION
        self.rumble_pub = rospy.Publisher("~rumble", Float32, queue_size=1)  # for rqt_plot

    def on_force(self, msg):
        """Ex. 9: a new mapped force arrived: keep its value in self.force."""
        ### BEGIN SOLUTION
        self.force = msg.data
        ### END SOLUTION
        self.force_time = rospy.get_time()  # ROS time: the grader's clock when it owns the time

    def publish(self, velocity):
        """Ex. 9: build the Twist from velocity ([v_x, v_y, v_z, w_x, w_y, w_z]) and the
        Float32 from self.gripper_width, and publish both."""
        ### BEGIN SOLUTION
        twist = Twist()
        twist.linear.x, twist.linear.y, twist.linear.z = velocity[0], velocity[1], velocity[2]
        twist.angular.x, twist.angular.y, twist.angular.z = velocity[3], velocity[4], velocity[5]
        self.twist_pub.publish(twist)
        self.gripper_pub.publish(Float32(self.gripper_width))
        ### END SOLUTION

    # -- the loop (given) -------------------------------------------------------------
    def open_pad(self, kind="pygame", layout="dualshock4", script=""):
        self.pad = open_gamepad(kind, layout, script=script or None)
        # The robot differentiates every command at 1 kHz: a velocity that jumps stops it
        # with a reflex error. The limiter ramps every command inside safe limits.
        self.limiter = TwistLimiter()

    def wait_for_robot(self, timeout_s=5.0):
        """Wait (at most timeout_s) until the robot listens to the velocity command.

        A scripted pad starts playing at the first poll: commands sent before the robot (or
        the simulated one) is connected would be lost, and the hand would not move.
        """
        publisher = getattr(self, "twist_pub", None)
        if publisher is None:
            return
        # Counted in wall-clock sleeps on purpose: under the autograder's /clock, ROS time
        # stands still until this node's loop runs.
        for _ in range(int(timeout_s / 0.02)):
            if publisher.get_num_connections() > 0 or rospy.is_shutdown():
                return
            time.sleep(0.02)
        rospy.logwarn("nobody listens on %s yet: is the robot (or lab_sim) running?", publisher.resolved_name)

    def request_quit(self, *_args):
        """Ctrl-C or rosnode kill: leave the loop, bring the robot to rest, then end."""
        self.quit = True

    def send(self):
        """Rumble the pad, then publish the velocity (ramped by the limiter) and the width."""
        fresh = self.force_time is not None and rospy.get_time() - self.force_time <= FORCE_TIMEOUT
        rumble = self.rumble if fresh and self.feedback else 0.0
        self.pad.rumble(rumble, 0.0)
        self.rumble_pub.publish(Float32(rumble))
        self.publish(self.limiter.step(self.cartesian_velocity, 1.0 / self.rate))

    def run(self):
        """Read the pad, compute, publish, rate times a second, until square is pressed."""
        # Ex. 9: the rate object that keeps the loop at self.rate Hz
        ### BEGIN SOLUTION
        rate = rospy.Rate(self.rate)
        ### END SOLUTION
        previous = PadState.neutral()
        while not rospy.is_shutdown() and not self.quit:
            state = self.pad.poll()
            for event in pad_events(previous, state):
                self.handle_event(event)
            previous = state
            self.update_gripper_width()
            self.update_cartesian_velocity()
            self.update_rumble()
            self.send()
            rate.sleep()
        self.stop(rate)

    def stop(self, rate=None):
        """Ramp the velocity to zero inside the limits (never a step), then stop the rumble.

        rate: the loop's rate object, so the ramp keeps the loop's ticks; without one, it
        sleeps one period between commands.
        """
        self.cartesian_velocity = [0.0] * 6
        self.rumble = 0.0
        deadline = rospy.get_time() + STOP_TIMEOUT  # ROS time, as the loop's
        period = rate.sleep if rate is not None else lambda: rospy.sleep(1.0 / self.rate)
        try:
            while any(v != 0.0 for v in self.limiter.velocity) and rospy.get_time() < deadline:
                self.send()
                period()
            self.send()
            # One more period before the node ends: rospy sends a message from a thread of its
            # own, and a node that ends at once can end before its last command went out.
            period()
        except rospy.ROSException:
            pass  # rospy already shut down (rosnode kill): nothing can be published any more
        self.pad.rumble(0.0, 0.0)
        self.pad.close()


def read_parameters():
    """The node's private parameters with the lab's defaults."""
    defaults = {"rate": 50.0, "k_trans": 0.1, "k_rot": 0.3, "k_gripper": 0.04, "deadzone": 0.1}
    return {name: float(rospy.get_param("~" + name, value)) for name, value in defaults.items()}


def main():
    # Ex. 9: initialise the node, named teleoperation
    ### BEGIN SOLUTION
    rospy.init_node("teleoperation")
    ### END SOLUTION
    node = Teleoperation(**read_parameters())
    node.feedback = bool(rospy.get_param("~feedback", True))  # Ex. 14: false, the condition without feedback
    node.open_pad(rospy.get_param("~pad", "pygame"), rospy.get_param("~layout", "dualshock4"),
                  rospy.get_param("~pad_script", ""))
    node.connect()
    node.wait_for_robot(float(rospy.get_param("~wait_for_robot_s", 5.0)))
    # Ctrl-C and rosnode kill bring the robot to rest first (rospy would stop publishing at once).
    signal.signal(signal.SIGINT, node.request_quit)
    signal.signal(signal.SIGTERM, node.request_quit)
    rospy.on_shutdown(node.request_quit)
    node.run()
    rospy.signal_shutdown("teleoperation finished")


if __name__ == "__main__":
    main()
