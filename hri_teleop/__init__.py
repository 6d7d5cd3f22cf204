"""The HRI teleoperation lab's toolkit: its rules, simulated hardware, ROS shells, grader and course.

Layers are folders, each importing only those below it (tests/unit/test_layers.py; the plan,
drawn from the imports, in docs/architecture.md): ``core`` (the lab's rules as plain Python: no
rospy, pygame, process, thread or socket; files only where a rule's data lives, YAML and the
trials' CSV) < ``plots`` < ``hardware`` < ``ros`` < ``grading`` < ``course``; ``student``, what
students' files import, on ``ros`` (docs/student-api.md).
"""

__version__ = "0.1.0"
