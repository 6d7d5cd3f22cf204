"""Widgets for the lab's notebooks (ipywidgets 8 + matplotlib; ipympl for interactive figures).

One per need of the handout, each an ``ipywidgets.VBox`` shown as a cell's last expression:
FsrExplorer (Ex. 1, 5), DeadzoneExplorer (Fig. 8), ControllerView (Ex. 8), LivePlot, ArmView (the
Panda in 3D), CalibrationWidget (Ex. 11), GraphView (Ex. 15),
Doctor (make doctor) and BrowserPad (the browser's pad drives the node; loaded when first used).
Importing needs neither rospy nor pygame: the ROS widgets start ROS when they are created
(:func:`~hri_teleop.course.notebook_ros.ensure_ros`), or say in one line what is missing.
"""

from __future__ import annotations

from typing import Any

try:
    import ipywidgets as _ipywidgets  # noqa: F401 - only to say below what is missing
except ImportError:  # pragma: no cover - exercised by a subprocess test
    raise ImportError("ipywidgets is not installed: run `make setup` (or `pip install -e '.[lab]'`) to get the "
                      "notebook widgets") from None

from hri_teleop.course.widgets.arm3d import ArmView
from hri_teleop.course.widgets.calibration import CalibrationWidget
from hri_teleop.course.widgets.controller import ControllerView
from hri_teleop.course.widgets.deadzone import DeadzoneExplorer
from hri_teleop.course.widgets.doctor import Doctor
from hri_teleop.course.widgets.fsr import FsrExplorer
from hri_teleop.course.widgets.graph import GraphView
from hri_teleop.course.widgets.live import LivePlot

#: What a notebook cell creates (the notebooks and the user docs use each, a test checks both ways).
#: Everything else (the models, the figure helpers, TlxWidget and RehearsalOffer, which
#: ``course.experiment`` offers) lives in its own module and is the toolkit's inside.
__all__ = ["FsrExplorer", "DeadzoneExplorer", "ControllerView", "LivePlot", "ArmView", "CalibrationWidget",
           "GraphView", "Doctor", "BrowserPad"]


def __getattr__(name: str) -> Any:
    """BrowserPad on first use: a kernel without anywidget still gets every other widget."""
    if name != "BrowserPad":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    try:
        from hri_teleop.course.widgets.browser_pad import BrowserPad  # noqa: PLC0415 - anywidget only when asked
    except ImportError as exc:
        raise ImportError(f"widgets.BrowserPad needs anywidget ({exc}): run `make setup` (or `pip install -e .`)") from None
    return BrowserPad
