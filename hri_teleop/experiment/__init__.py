"""Ex. 14's force-feedback experiment: trial plans, per-trial metrics, the paired comparison.

Pure functions over plain data (no rospy): the recording command and the analysis
notebook call them; the tests run them on simulated trials whose truth is known.
"""
