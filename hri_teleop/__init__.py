"""The HRI teleoperation lab's toolkit: its rules, simulation, hardware boundary, ROS shells, grader and course.

Layers are folders, each importing only those below it (tests/unit/test_layers.py; the plan, drawn from
the imports, in docs/architecture.md): ``core`` (the lab's rules as plain Python: no rospy, pygame,
process, thread or socket; of third parties only numpy and PyYAML) < ``plots`` < ``sim`` < ``hardware``
< ``ros`` < {``grading``, ``student``} < ``course`` < ``apps`` (every command; no other layer imports one).
``student`` is what students' files import (docs/student-api.md); only last term's paths import it.
"""

__version__ = "0.1.0"
