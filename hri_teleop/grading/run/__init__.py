"""Step 2 of grading: run a student's nodes in a sandbox on a private ROS master, in lockstep."""
