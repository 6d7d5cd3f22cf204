#!/usr/bin/env python3
"""Provided with the handout's Ex. 9: the ROS lines teleoperation.py needs, in a node of their own.

    rosrun hri_lab teleoperation_subscriber_publisher.py

It starts a node, publishes a velocity command (geometry_msgs/Twist) and a gripper width
(std_msgs/Float32) ten times a second and logs the mapped force it receives. It commands
no motion: every velocity stays 0 and the width stays where the hand is opened to. Take
the lines you need into teleoperation.py, at the places marked "Ex. 9", and adapt them.
"""

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float32

PUBLISH_HZ = 10.0      # Hz: how often this example publishes
OPEN_WIDTH_M = 0.08    # m: the Franka Hand fully open


def force_callback(message):
    """Called by rospy for every std_msgs/Float32 on /force_mapped."""
    rospy.loginfo_throttle(1.0, "force_mapped = %.3f", message.data)


def example():
    rospy.init_node("teleoperation_subscriber_publisher")
    velocity_out = rospy.Publisher("/cartesian_velocity_controller/cmd_vel", Twist, queue_size=1)
    width_out = rospy.Publisher("/gripper_width", Float32, queue_size=1)
    rospy.Subscriber("/force_mapped", Float32, force_callback)
    loop = rospy.Rate(PUBLISH_HZ)
    while not rospy.is_shutdown():
        command = Twist()               # all six components 0.0: no motion
        command.linear.x = 0.0          # m/s, forward;   .linear.y left, .linear.z up
        command.angular.z = 0.0         # rad/s about z;  .angular.x, .angular.y likewise
        velocity_out.publish(command)
        width_out.publish(Float32(data=OPEN_WIDTH_M))
        loop.sleep()


if __name__ == "__main__":
    try:
        example()
    except rospy.ROSInterruptException:
        pass
