"""The HRI teleoperation lab's toolkit: its rules, simulated hardware, ROS shells, grader and course.

Layers are folders, each importing only those below it (tests/unit/test_layers.py):
``core`` (the lab's rules as plain Python: no rospy, no pygame, no I/O but the YAML files it is
handed) < ``hardware`` (real and simulated pads, boards, arm and hand), ``plots`` < ``ros`` <
``grading`` < ``course``; ``student``, what students' files import, on ``ros`` (docs/student-api.md).
"""

__version__ = "0.1.0"
