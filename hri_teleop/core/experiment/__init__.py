"""Ex. 14's force-feedback experiment: trial plans, per-trial metrics, the paired comparison.

Pure functions over plain data (no rospy): the recording command and the analysis
notebook call them; the tests run them on simulated trials whose truth is known.

* :mod:`~hri_teleop.core.experiment.plan` -- counterbalanced trial plans (AB/BA, Latin-square objects);
* :mod:`~hri_teleop.core.experiment.metrics` -- per-trial metrics (force in N through the FSR model);
* :mod:`~hri_teleop.core.experiment.sidecar` -- the YAML beside each trial's bag (atomic updates);
* :mod:`~hri_teleop.core.experiment.tlx` -- the raw NASA-TLX questionnaire;
* :mod:`~hri_teleop.core.experiment.stats` -- exact Wilcoxon signed-rank test, rank-biserial effect size;
* :mod:`~hri_teleop.plots.study` -- the study figure;
* :mod:`~hri_teleop.core.experiment.analysis` -- a folder of trials to a :class:`StudyResult`.

Recording, rehearsing and the command line: :mod:`hri_teleop.ros.trial`.
"""
