"""Simulated hardware for the lab at home: the Franka arm and hand, an object, the FSR attachment.

Pure, deterministic physics and rules (no rospy, no clocks of their own): the simulation
nodes step them at 1 kHz and wire them to the same topics and actions as the real robot.
"""
