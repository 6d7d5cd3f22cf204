"""Stand-ins for the lab's hardware packages in the grading workspace.

A student's teleoperation.launch starts ``rosserial_python/serial_node.py`` (the Arduino) and
includes franka_control (the robot); neither exists on a grading machine. In simulation lab_sim
plays the hardware and sends the board's counts on :data:`BOARD_TOPIC`; the stand-in serial_node
forwards them to ``/pub_force``, so the force reaches the pipeline only if the student's launch
file starts a serial_node, as in the lab.
"""

from __future__ import annotations

__all__ = ["BOARD_TOPIC", "SERIAL_NODE_SCRIPT", "serial_node"]

#: Where lab_sim's simulated board publishes in a grading session (remapped from /pub_force).
BOARD_TOPIC = "/hri_grader/board/pub_force"

#: The stand-in's executable in the workspace's rosserial_python package.
SERIAL_NODE_SCRIPT = (
    "#!/usr/bin/env python3\n"
    '"""Grader stand-in for rosserial_python: the simulated sensor board (hri_teleop.grading.run.standins)."""\n'
    "import sys\n\n"
    "from hri_teleop.grading.run.standins import serial_node\n\n"
    "sys.exit(serial_node())\n"
)


def serial_node() -> int:
    """Forward the simulated board's counts to /pub_force (std_msgs/Int16) until shut down.

    Like rosserial_python's node it reads ``~port`` (default /dev/ttyUSB0) and ``~baud``,
    and says which port it serves; it opens no device.
    """
    import rospy  # noqa: PLC0415 - ROS in the stand-in only (the grader imports this)
    from std_msgs.msg import Int16  # noqa: PLC0415 - ROS in the stand-in only (the grader imports this)

    rospy.init_node("serial_node")
    port = rospy.get_param("~port", "/dev/ttyUSB0")
    baud = rospy.get_param("~baud", 57600)
    publisher = rospy.Publisher("/pub_force", Int16, queue_size=20, tcp_nodelay=True)
    rospy.Subscriber(BOARD_TOPIC, Int16, publisher.publish, queue_size=20, tcp_nodelay=True)
    rospy.loginfo("serial_node (grader stand-in): the simulated sensor board on %s at %s baud", port, baud)
    rospy.spin()
    return 0
