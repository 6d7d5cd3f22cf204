"""Controller mapping files: raw SDL/pygame indices <-> positional names.

Raw indices depend on the controller, its kernel driver and SDL's backend, so each supported
controller has one YAML file in ``layouts/`` saying where every logical axis and button sits and
where that was verified. The file format and the axis normalisation: docs/teleoperation.md.
"""

from __future__ import annotations

import importlib.resources
import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

from hri_teleop.core.checks import is_int, is_number
from hri_teleop.core.gamepad.state import AXES, BUTTONS, STICK_AXES, TRIGGER_AXES, GamepadError, PadState
from hri_teleop.core.yamlfile import read_yaml

__all__ = ["AxisMap", "Layout", "LAYOUT_DIR", "DEFAULT_LAYOUT", "AUTO_LAYOUT", "available_layouts",
           "load_layout", "as_layout", "layout_from_dict", "shipped_layouts_folder"]


def shipped_layouts_folder() -> Path:
    """The package data folder of layouts, found through importlib.resources (3.9+)."""
    files = getattr(importlib.resources, "files", None)
    if files is None:  # Python 3.8 (the lab PCs), where the package is always unpacked on disk
        return Path(__file__).resolve().parent / "layouts"
    return Path(str(files(__package__) / "layouts"))


LAYOUT_DIR = shipped_layouts_folder()
DEFAULT_LAYOUT = "dualshock4"
#: The layout setting that asks a real pad to identify itself (core.gamepad.identify); a pad
#: that cannot (virtual, unknown) gets DEFAULT_LAYOUT.
AUTO_LAYOUT = "auto"

#: Buttons every layout must map: the lab's gripper, mode and quit buttons.
REQUIRED_BUTTONS = ("south", "east", "west", "north")
_TOP_KEYS = ("name", "description", "verified", "axes", "buttons", "labels")
_AXIS_KEYS = ("index", "invert", "rest")


class AxisMap(NamedTuple):
    """Where a logical axis sits in the raw axes, and how to normalise it."""

    raw_index: int
    invert: bool = False
    rest: float = 0.0


def _clip(value: float, low: float, high: float) -> float:
    return min(high, max(low, value))


@dataclass(frozen=True)
class Layout:
    """One controller's mapping between raw indices and positional names."""

    name: str
    description: str
    axes: Mapping[str, AxisMap]
    buttons: Mapping[str, int]
    verified: str = ""
    labels: Mapping[str, str] = field(default_factory=dict)
    source: Optional[str] = None  # the file it was loaded from, for messages

    def __post_init__(self) -> None:
        object.__setattr__(self, "axes", MappingProxyType(
            {k: AxisMap(*v) if not isinstance(v, AxisMap) else v for k, v in dict(self.axes).items()}))
        object.__setattr__(self, "buttons", MappingProxyType(dict(self.buttons)))
        object.__setattr__(self, "labels", MappingProxyType(dict(self.labels)))

    @property
    def num_axes(self) -> int:
        """How many raw axes a pad needs for this layout (highest mapped index + 1)."""
        return max((a.raw_index for a in self.axes.values()), default=-1) + 1

    @property
    def num_buttons(self) -> int:
        """How many raw buttons a pad needs for this layout (highest mapped index + 1)."""
        return max(self.buttons.values(), default=-1) + 1

    def label(self, button: str) -> str:
        """What the user sees printed on the pad for a positional button name."""
        return self.labels.get(button, button)

    def state_from_raw(self, raw_axes: Sequence[float], raw_buttons: Sequence[Union[int, bool]],
                       connected: bool = True) -> PadState:
        """Raw pygame/Joy values -> PadState. Missing or non-finite raw values read as at rest."""
        axes: Dict[str, float] = {}
        for name, (index, invert, rest) in self.axes.items():
            raw = float(raw_axes[index]) if index < len(raw_axes) else rest
            if not math.isfinite(raw):
                raw = rest
            value = (_clip(raw, -1.0, 1.0) - rest) / (1.0 - rest)
            if invert:
                value = -value
            low = 0.0 if name in TRIGGER_AXES else -1.0
            axes[name] = _clip(value, low, 1.0) + 0.0  # + 0.0 turns -0.0 into 0.0
        buttons = {name: bool(raw_buttons[index]) if index < len(raw_buttons) else False
                   for name, index in self.buttons.items()}
        return PadState(axes, buttons, connected)

    def raw_from_state(self, state: PadState) -> Tuple[List[float], List[int]]:
        """PadState -> (raw axes, raw buttons) in this pad's order, e.g. for a sensor_msgs/Joy.

        The inverse of ``state_from_raw``: unmapped raw slots read 0.0 / 0.
        """
        raw_axes = [0.0] * self.num_axes
        for name, (index, invert, rest) in self.axes.items():
            value = state.axis(name)
            if invert:
                value = -value
            raw_axes[index] = _clip(value * (1.0 - rest) + rest, -1.0, 1.0) + 0.0
        raw_buttons = [0] * self.num_buttons
        for name, index in self.buttons.items():
            raw_buttons[index] = int(state.pressed(name))
        return raw_axes, raw_buttons


# --------------------------------------------------------------------------- loading

def available_layouts() -> List[str]:
    """Names of the layouts shipped with the toolkit (files in hri_teleop/core/gamepad/layouts)."""
    return sorted(p.stem for p in LAYOUT_DIR.glob("*.yaml"))


def _fail(source: str, problem: str, fix: str) -> GamepadError:
    return GamepadError("%s: %s; %s" % (source, problem, fix))


def _check_index(source: str, where: str, value: Any) -> int:
    if not is_int(value) or value < 0:
        raise _fail(source, "%s is %r" % (where, value), "give a raw index, an integer >= 0")
    return value


def layout_from_dict(data: Any, source: str = "<dict>") -> Layout:
    """Build and check a Layout from parsed YAML; every problem is one line naming ``source``."""
    if not isinstance(data, dict):
        raise _fail(source, "expected a mapping with keys %s, found %s" % (
            ", ".join(_TOP_KEYS), type(data).__name__), "see hri_teleop/core/gamepad/layouts/dualshock4.yaml")
    unknown = [k for k in data if k not in _TOP_KEYS]
    if unknown:
        raise _fail(source, "unknown key %r" % unknown[0], "use only %s" % ", ".join(_TOP_KEYS))
    for key in ("name", "description", "verified", "axes", "buttons"):
        if key not in data or data[key] is None or data[key] == "":
            raise _fail(source, "missing key %r" % key,
                        "add it (see hri_teleop/core/gamepad/layouts/dualshock4.yaml)")
    for key in ("name", "description", "verified"):
        if not isinstance(data[key], str):
            raise _fail(source, "%r must be text, found %r" % (key, data[key]), "quote it")

    axes_data = data["axes"]
    if not isinstance(axes_data, dict):
        raise _fail(source, "'axes' must be a mapping, found %r" % (axes_data,),
                    "write e.g. 'axes: {left_x: {index: 0}}'")
    axes: Dict[str, AxisMap] = {}
    for name, spec in axes_data.items():
        if name not in AXES:
            raise _fail(source, "unknown axis %r" % (name,), "use one of %s" % ", ".join(AXES))
        if is_int(spec):
            spec = {"index": spec}
        if not isinstance(spec, dict) or "index" not in spec:
            raise _fail(source, "axis %r is %r" % (name, spec), "write it as {index: N, invert: false}")
        bad = [k for k in spec if k not in _AXIS_KEYS]
        if bad:
            raise _fail(source, "axis %r has unknown key %r" % (name, bad[0]),
                        "use only %s" % ", ".join(_AXIS_KEYS))
        index = _check_index(source, "axis %r index" % name, spec["index"])
        invert = spec.get("invert", False)
        if not isinstance(invert, bool):
            raise _fail(source, "axis %r invert is %r" % (name, invert), "write true or false")
        rest = spec.get("rest", 0.0)
        if not is_number(rest) or not -1.0 <= rest < 1.0:
            raise _fail(source, "axis %r rest is %r" % (name, rest),
                        "give the raw resting value, -1.0 for a trigger that rests at -1, else 0")
        axes[name] = AxisMap(index, invert, float(rest))
    missing_axes = [a for a in STICK_AXES if a not in axes]
    if missing_axes:
        raise _fail(source, "axis %r is not mapped" % missing_axes[0],
                    "map all of %s under 'axes'" % ", ".join(STICK_AXES))
    _check_unique(source, "axis", {k: v.raw_index for k, v in axes.items()})

    buttons_data = data["buttons"]
    if not isinstance(buttons_data, dict):
        raise _fail(source, "'buttons' must be a mapping, found %r" % (buttons_data,),
                    "write e.g. 'buttons: {south: 0}'")
    buttons: Dict[str, int] = {}
    for name, index in buttons_data.items():
        if name not in BUTTONS:
            raise _fail(source, "unknown button %r" % (name,),
                        "use a positional name, one of %s" % ", ".join(BUTTONS))
        buttons[name] = _check_index(source, "button %r" % name, index)
    missing = [b for b in REQUIRED_BUTTONS if b not in buttons]
    if missing:
        raise _fail(source, "button %r is not mapped" % missing[0],
                    "map all of %s under 'buttons'" % ", ".join(REQUIRED_BUTTONS))
    _check_unique(source, "button", buttons)

    labels = data.get("labels") or {}
    if not isinstance(labels, dict) or any(k not in BUTTONS or not isinstance(v, str)
                                           for k, v in labels.items()):
        raise _fail(source, "'labels' must map positional button names to text",
                    "write e.g. 'labels: {south: cross}'")
    return Layout(name=data["name"], description=data["description"].strip(), axes=axes,
                  buttons=buttons, verified=data["verified"].strip(), labels=labels,
                  source=None if source == "<dict>" else source)


def _check_unique(source: str, kind: str, indices: Mapping[str, int]) -> None:
    seen: Dict[int, str] = {}
    plural = "axes" if kind == "axis" else kind + "s"
    for name, index in indices.items():
        if index in seen:
            raise _fail(source, "%s %r and %r both use raw index %d" % (plural, seen[index], name, index),
                        "give each %s its own index" % kind)
        seen[index] = name


def _looks_like_path(name_or_path: str) -> bool:
    return ("/" in name_or_path or "\\" in name_or_path
            or name_or_path.endswith((".yaml", ".yml")))


def load_layout(name_or_path: Union[Layout, str, Path]) -> Layout:
    """A shipped layout by name (``dualshock4``) or any layout file by path.

    Unknown names, missing files, YAML syntax errors and missing or wrong keys each raise a
    one-line GamepadError naming the file (or the known layouts) and the fix.
    """
    if isinstance(name_or_path, Layout):
        return name_or_path
    if not isinstance(name_or_path, (str, Path)) or str(name_or_path).strip() == "":
        raise GamepadError("layout %r is not a name or a path: set layout to one of %s or to a "
                           "layout YAML file" % (name_or_path, ", ".join(available_layouts())))
    text = str(name_or_path).strip()
    if isinstance(name_or_path, Path) or _looks_like_path(text):
        path = Path(text).expanduser()
        if not path.is_file():
            raise GamepadError("layout file not found: %s; check the path or use one of the shipped "
                               "layouts: %s" % (path, ", ".join(available_layouts())))
    else:
        path = LAYOUT_DIR / (text + ".yaml")
        if not path.is_file():
            raise GamepadError("unknown gamepad layout %r: set layout to one of %s, or to the path "
                               "of your own layout YAML file" % (text, ", ".join(available_layouts())))
    source = str(path)
    data = read_yaml(source, GamepadError, what="layout file")
    return layout_from_dict(data, source)


def as_layout(layout: Union[Layout, str, Path, None]) -> Layout:
    """A Layout from a Layout, a name or a path; None and ``auto`` give the default (DualShock 4)."""
    if layout is None or (isinstance(layout, str) and layout.strip() == AUTO_LAYOUT):
        return load_layout(DEFAULT_LAYOUT)
    return load_layout(layout)
