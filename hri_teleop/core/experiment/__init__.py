"""Ex. 14's force-feedback experiment: trial plans, per-trial metrics, the paired comparison.

Pure functions over plain data (no rospy), called by the trials' library (:mod:`hri_teleop.ros.trial`,
behind ``hri_teleop.apps.trial``) and the analysis notebook, and tested on simulated trials whose truth
is known: ``plan`` (counterbalanced plans), ``metrics``, ``sidecar``, ``tlx`` (raw NASA-TLX),
``stats`` (exact Wilcoxon test) and ``analysis`` (a folder of trials to a ``StudyResult``).
The experiment's design and definitions: docs/experiment.md.
"""
