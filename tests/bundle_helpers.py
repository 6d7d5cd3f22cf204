"""What the student-bundle tests share (tests/integration/test_student_bundle.py, tests/container/):
the answer key copied into a bundle, and the points `make check` prints."""

from __future__ import annotations

from hri_teleop.course.release import copy_answer_key  # noqa: F401 - the tests import it from here


def notebook_points(output: str) -> dict:
    """notebook -> (points, possible) of make check's notebook lines."""
    scores = {}
    for line in output.splitlines():
        if line.strip().endswith(")") and "points (" in line and ".ipynb ... " in line:
            name = line.split("/")[1].split(".ipynb")[0]
            got, most = line.split(" ... ")[1].split(" points")[0].split("/")
            scores[name.strip()] = (float(got), float(most))
    return scores


def files_points(output: str) -> tuple:
    """(points, possible) of make check's line for the files (the checks' points are the files')."""
    line = next(line for line in output.splitlines() if line.endswith("points for your files, beside the "
                                                                        "notebooks' autograded points above"))
    got, most = line.split("check: ")[1].split(" points")[0].split("/")
    return float(got), float(most)
