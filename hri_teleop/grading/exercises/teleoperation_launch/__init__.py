"""Ex. 12-13: ``launch/teleoperation.launch``: its nodes, serial_node's port, /max_sensor_force, the robot's include;
then launched in the simulated lab, the pad driving the arm.

``cases``: the simulated world and the drive; ``judge``: its parts; ``check``: the check and its ``EXERCISE``.
The session is the grader's simulated lab (``run/launch_runs.py``), which Ex. 10's drive shares.
"""
