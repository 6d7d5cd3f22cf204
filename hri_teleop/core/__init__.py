"""The lab's rules as plain typed functions: force, mapping, limits, teleoperation, pads, studies.

No rospy, pygame, subprocess, serial port or widget is imported here (a test holds this);
the nodes, the notebooks and the grader call these functions instead of repeating them.
"""
