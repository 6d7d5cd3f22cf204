"""Ex. 12-13: ``launch/teleoperation.launch`` as roslaunch's loader sees it, then launched in the simulated lab.

Its nodes, serial_node's port, /max_sensor_force and the robot's include, then the pad driving the arm.
``cases``: the simulated world and the drive; ``judge``: its parts; ``check``: the check and its ``EXERCISE``.
The session is the grader's simulated lab (``run/launch_runs.py``), which Ex. 10's drive shares.
"""
