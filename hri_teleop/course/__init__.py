"""What the course's notebooks import, and nothing else: twelve names.

``ensure_ros`` joins the kernel to ROS; ``lab`` starts and stops nodes; ``check`` scores the
student's files; ``sim`` is the lock-step lab; ``widgets`` the explorers and live plots;
``experiment`` the trial analysis; ``fsr`` the sensor's formulas; ``show_file``,
``import_student_file``, ``build_workspace`` and ``seconds`` help a cell; ``hand_in`` hands an
autograded cell's values to the grader, which judges them. The namespaces are
submodules, imported when a notebook asks for them.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from hri_teleop.core import fsr
from hri_teleop.course.answers import hand_in
from hri_teleop.course.cells import import_student_file, seconds, show_file
from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.ros.catkin_ws import build_workspace

__all__ = ["ensure_ros", "lab", "check", "sim", "widgets", "experiment", "fsr", "show_file", "import_student_file",
           "build_workspace", "seconds", "hand_in"]

_NAMESPACES = ("lab", "check", "sim", "widgets", "experiment")


def __getattr__(name: str) -> ModuleType:
    """``course.lab`` and the other namespaces, imported on first use (widgets need ipywidgets)."""
    if name in _NAMESPACES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
