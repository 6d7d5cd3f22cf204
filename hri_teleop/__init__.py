"""hri-teleop: the rules of the HRI teleoperation lab as plain, ROS-free Python.

The modules directly under this package form the functional core (no rospy, no
pygame at import time, no I/O besides reading the YAML files they are handed).
``hri_teleop.ros`` holds the helpers the ROS shells share and is the only place
that imports rospy.
"""

__version__ = "0.1.0"
