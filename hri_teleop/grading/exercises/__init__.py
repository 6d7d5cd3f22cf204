"""The course's graded deliverables, one module (or folder) each: docs/adding-an-exercise.md.

Everything the grader knows about one deliverable (its hidden inputs, the session that runs it, its
judge, its parts and points, its feedback) lives in its module, which ends with an
:class:`~hri_teleop.grading.exercise.Exercise`. :mod:`hri_teleop.grading.deliverables` lists
them (the registry's list); :mod:`~hri_teleop.grading.exercises.registry` loads them for the run, the
judge, the points, the reports, Gradescope, ``make check`` and the course.
"""
