"""Widgets for the lab's notebooks (ipywidgets 8 + matplotlib; ipympl for interactive figures).

One per need of the handout; each is an ``ipywidgets.VBox`` you display by leaving it as
a cell's last expression. The rules and numbers come from the core (``hri_teleop.core.fsr``,
``mapping``, ``gamepad``, ``teleop``, ``paramfile``); what is here is the view and small
pure helpers, tested without a browser.

====================  ==========================================================  =========
widget                what it shows                                               needs ROS
====================  ==========================================================  =========
FsrExplorer           force -> resistance -> voltage -> count -> mapped (Ex. 1, 5)  no
DeadzoneExplorer      normalize_analog_input, curve and stick (Fig. 8)            no
ControllerView        pad (real or virtual) -> mode, gripper, twist, rumble (Ex. 8) no
LivePlot              /pub_force, /force_mapped, /gripper_width, twist, live      yes
CalibrationWidget     max /pub_force -> /max_sensor_force and your launch file    yes
GraphView             nodes, topics and message types of the live system (Ex. 15) a master
TlxWidget             raw NASA-TLX after a trial -> the trial's sidecar (Ex. 14)  no
RehearsalOffer        a folder's trials, or a simulated session rehearsed into it  to rehearse
====================  ==========================================================  =========

Importing this package needs neither rospy nor pygame: the ROS widgets start ROS through
:func:`hri_teleop.course.notebook_ros.ensure_ros` when they are created, and say in one line what
is missing when it cannot be had.
"""

from __future__ import annotations

try:
    import ipywidgets as _ipywidgets  # noqa: F401
except ImportError:  # pragma: no cover - exercised by a subprocess test
    raise ImportError("ipywidgets is not installed: run `make setup` (or `pip install -e '.[lab]'`) to get the "
                      "notebook widgets") from None

from hri_teleop.course.widgets._base import FigureView, Ticker, WidgetError, lab_teleop_config
from hri_teleop.course.widgets.calibration import CalibrationWidget, MaxRecorder
from hri_teleop.course.widgets.controller import (
    ControllerModel,
    ControllerSnapshot,
    ControllerView,
    open_pad,
    pad_svg,
)
from hri_teleop.course.widgets.deadzone import DeadzoneExplorer, deadzone_curve, filter_stick
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
    "CalibrationWidget", "MaxRecorder",
    "GraphView", "RosGraph", "graph_from_state", "layered_layout", "draw_graph", "read_graph",
    "TlxWidget", "trial_sidecars", "RehearsalOffer", "count_trials",
]
