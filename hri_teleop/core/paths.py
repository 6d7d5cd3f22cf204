"""Where things are in a checkout of the project: the one module that knows its layout.

The toolkit runs from a checkout (or the student bundle, which keeps the same layout for what
it ships), so the lab package, the course notebooks and the firmware are found from here.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["REPO", "LAB_PACKAGE", "LAB_CONFIG", "SCENARIOS", "NOTEBOOKS", "SOLUTIONS", "FIRMWARE", "TRACES",
           "TRIALS", "OUT", "TOOLS"]

#: The checkout's root (where the Makefile is).
REPO = Path(__file__).resolve().parents[2]
#: The ROS package the lab runs (``hri_lab``), its config files and simulated-lab scenarios.
LAB_PACKAGE = REPO / "hri_lab"
LAB_CONFIG = LAB_PACKAGE / "config"
SCENARIOS = LAB_PACKAGE / "scenarios"
#: The nbgrader course: source notebooks, releases, submissions.
NOTEBOOKS = REPO / "notebooks"
#: The answer key's ``hri_lab`` files (not in the student bundle).
SOLUTIONS = REPO / "solutions" / "hri_lab"
FIRMWARE = REPO / "firmware"
#: The grader's reference traces.
TRACES = REPO / "grading" / "traces"
#: Recorded trials (Ex. 14's study), unless ``HRI_TRIALS`` says otherwise.
TRIALS = REPO / "trials"
#: Everything the Makefile's targets write.
OUT = REPO / "out"
TOOLS = REPO / "tools"
