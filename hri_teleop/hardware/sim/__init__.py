"""Simulated boards that speak the real Arduino's serial protocols.

The firmware on simavr and a rosserial board on a pty: the lab's serial bridge and rosserial_python
cannot tell them from the board. The physics they report comes from the lock-step simulation
(``hri_teleop.sim``).
"""
