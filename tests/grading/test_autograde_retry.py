"""Which failed autograde runs make grade repeats: the machine's failures, never the submission's."""

from __future__ import annotations

import pytest

from hri_teleop.grading.batch.nbgrader_batch import retry_cause


@pytest.mark.parametrize("log, cause", [
    ("sqlite3.OperationalError: database is locked", "the gradebook was locked"),
    ("RuntimeError: Kernel didn't respond in 120 seconds", "the notebook's kernel did not start"),
])
def test_a_failure_of_the_grading_machine_is_graded_again(log, cause):
    assert retry_cause(f"[AutogradeApp] ERROR ...\n{log}\n") == cause


@pytest.mark.parametrize("log", [
    "nbclient.exceptions.DeadKernelError: Kernel died while waiting for execute reply",  # the student's cell
    "CellTimeoutError: A cell timed out while it was being executed, after 300 seconds",
    "AssertionError: /robot_mass is not on the server",
    "",
])
def test_a_failure_of_the_submission_is_not_graded_again(log):
    assert retry_cause(log) == ""
