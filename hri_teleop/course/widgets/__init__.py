"""Widgets for the lab's notebooks (ipywidgets 8 + matplotlib; ipympl for interactive figures).

One per need of the handout, each an ``ipywidgets.VBox`` shown as a cell's last expression:
FsrExplorer (Ex. 1, 5), DeadzoneExplorer (Fig. 8), ControllerView (Ex. 8), LivePlot, ArmView (the
Panda in 3D), CalibrationWidget (Ex. 11), GraphView (Ex. 15), TlxWidget, RehearsalOffer (Ex. 14),
Doctor (make doctor) and BrowserPad (the browser's pad drives the node; loaded when first used).
Importing needs neither rospy nor pygame: the ROS widgets start ROS when they are created
(:func:`~hri_teleop.course.notebook_ros.ensure_ros`), or say in one line what is missing.
"""

from __future__ import annotations

from typing import Any

try:
    import ipywidgets as _ipywidgets  # noqa: F401
except ImportError:  # pragma: no cover - exercised by a subprocess test
    raise ImportError("ipywidgets is not installed: run `make setup` (or `pip install -e '.[lab]'`) to get the "
                      "notebook widgets") from None

from hri_teleop.course.widgets._base import FigureView, Ticker, WidgetError, lab_teleop_config
from hri_teleop.course.widgets.arm3d import ArmView, ArmViewError, joint_config, read_joint_states
from hri_teleop.course.widgets.calibration import CalibrationWidget, MaxRecorder
from hri_teleop.course.widgets.controller import (
    ControllerModel,
    ControllerSnapshot,
    ControllerView,
    open_pad,
    pad_svg,
)
from hri_teleop.course.widgets.deadzone import DeadzoneExplorer, deadzone_curve, filter_stick
from hri_teleop.course.widgets.doctor import Doctor, findings_html
from hri_teleop.course.widgets.fsr import (
    FsrCurve,
    FsrExplorer,
    FsrReading,
    describe_reading,
    fsr_curve,
    fsr_reading,
)
from hri_teleop.course.widgets.graph import (
    GraphView,
    RosGraph,
    draw_graph,
    graph_from_state,
    layered_layout,
    read_graph,
)
from hri_teleop.course.widgets.live import (
    LivePlot,
    LiveTopics,
    TopicBuffer,
    TopicSpec,
    lab_topics,
    numeric_fields,
)
from hri_teleop.course.widgets.rehearsal import RehearsalOffer, count_trials
from hri_teleop.course.widgets.tlx import TlxWidget, trial_sidecars

__all__ = [
    "WidgetError", "FigureView", "Ticker", "lab_teleop_config",
    "FsrExplorer", "FsrReading", "FsrCurve", "fsr_reading", "fsr_curve", "describe_reading",
    "DeadzoneExplorer", "deadzone_curve", "filter_stick",
    "ControllerView", "ControllerModel", "ControllerSnapshot", "open_pad", "pad_svg",
    "LivePlot", "LiveTopics", "TopicBuffer", "TopicSpec", "lab_topics", "numeric_fields",
    "ArmView", "ArmViewError", "joint_config", "read_joint_states",
    "CalibrationWidget", "MaxRecorder",
    "GraphView", "RosGraph", "graph_from_state", "layered_layout", "draw_graph", "read_graph",
    "TlxWidget", "trial_sidecars", "RehearsalOffer", "count_trials",
    "BrowserPad", "Doctor", "findings_html",
]


def __getattr__(name: str) -> Any:
    """BrowserPad on first use: a kernel without anywidget still gets every other widget."""
    if name != "BrowserPad":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    try:
        from hri_teleop.course.widgets.browser_pad import BrowserPad  # noqa: PLC0415 - anywidget only when asked
    except ImportError as exc:
        raise ImportError(f"widgets.BrowserPad needs anywidget ({exc}): run `make setup` (or `pip install -e .`)") from None
    return BrowserPad
