"""The lock-step simulation of the lab, in one package.

The Panda arm and its joints, the hand and its goals, an object, the FSR attachment and the
sensor board, the world that steps them, the scripted pad, simulated operators and the Ex. 14 study.

Pure and deterministic (no rospy, no clocks of their own): whoever steps it owns the time. The
hardware adapters (``hardware/sim``: the board's serial protocols), ``lab_sim.py``, the notebooks
and the grader all use this one package.
"""
