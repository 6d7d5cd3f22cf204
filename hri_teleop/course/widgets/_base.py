"""What every widget shares: a figure shown as a widget, a kernel-friendly timer, the lab's config.

Written once so that every widget draws and updates the same way: :class:`FigureView` (ipympl's
canvas, or a PNG where ipympl is missing) and :class:`Ticker` (periodic calls in the kernel's own
thread, never concurrently with the student's code).
"""

from __future__ import annotations

import asyncio
import html
import io
import sys
import threading
import time
import weakref
from typing import Any, Callable, Optional, Tuple

import ipywidgets as widgets
from matplotlib.figure import Figure

from hri_teleop.core.config import LAB_TELEOP_CONFIG, ConfigError, TeleopConfig, load_teleop_config
from hri_teleop.core.errors import HriTeleopError

__all__ = ["WidgetError", "FigureView", "Ticker", "LAB_TELEOP_CONFIG", "lab_teleop_config", "message_html",
           "current_cell_id", "replace_in_cell"]


FIGURE_MODES = ("auto", "ipympl", "image")


class WidgetError(HriTeleopError, ValueError):
    """A widget was given an argument it cannot use (one line: which, what, the fix)."""


def lab_teleop_config(config: Any = None) -> TeleopConfig:
    """A TeleopConfig: the one given, one loaded from a path, or the lab's teleop.yaml (defaults if absent)."""
    if isinstance(config, TeleopConfig):
        return config
    if config is not None:
        return load_teleop_config(config)
    try:
        return load_teleop_config(LAB_TELEOP_CONFIG if LAB_TELEOP_CONFIG.is_file() else "")
    except ConfigError:
        return load_teleop_config("")  # a broken lab file must not break the preparation notebooks


def message_html(text: str, error: bool = False) -> str:
    """One line of text for an ``ipywidgets.HTML``, escaped; red when it is an error."""
    color = "#b00020" if error else "inherit"
    return f'<span style="color:{color}">{html.escape(text)}</span>'


_BY_CELL: "weakref.WeakValueDictionary[Tuple[str, str], Any]" = weakref.WeakValueDictionary()


def current_cell_id() -> str:
    """The id of the notebook cell running now ('' outside JupyterLab, which sends it with each run)."""
    try:
        from IPython import get_ipython  # noqa: PLC0415 - there in a notebook only
    except ImportError:
        return ""
    header = getattr(get_ipython(), "parent_header", None) or {}
    return str((header.get("metadata") or {}).get("cellId") or "")


def replace_in_cell(widget: Any, cell_id: Optional[str] = None) -> None:
    """Re-running a cell closes the widget of the same class it made last time.

    Why: a live plot, the controller view and the calibration keep timers, subscriptions
    or a gamepad; a student who runs the cell again expects one plot, not two updating
    ones (and a second reader of the same pad). Outside JupyterLab (no cell id) nothing
    is replaced.
    """
    key = (current_cell_id() if cell_id is None else cell_id, type(widget).__name__)
    if not key[0]:
        return
    old = _BY_CELL.get(key)
    if old is not None and old is not widget:
        try:
            old.close()
        except Exception:  # noqa: BLE001 - the old widget may be half gone already
            pass
    _BY_CELL[key] = widget


def _ipympl_canvas(figure: Figure) -> Any:
    from ipympl.backend_nbagg import Canvas, FigureManager  # noqa: PLC0415 - optional

    canvas = Canvas(figure)
    FigureManager(canvas, 0)  # the canvas needs a manager for resizing and the toolbar
    canvas.header_visible = False
    canvas.footer_visible = False
    canvas.resizable = False
    canvas.toolbar_position = "right"
    return canvas


class FigureView:
    """A matplotlib Figure as a widget (``.widget``); call :meth:`redraw` after changing artists.

    With ipympl (the lab's JupyterLab) ipympl's interactive canvas (zoom, pan); without it, or
    with ``mode="image"``, a PNG in an ``ipywidgets.Image``, which renders anywhere. Build
    figures with ``Figure()``, never pyplot: nothing is shown twice and no global figure list
    grows while a plot updates for hours.
    """

    def __init__(self, figure: Figure, mode: str = "auto") -> None:
        if mode not in FIGURE_MODES:
            raise WidgetError(f"figure mode {mode!r} is unknown; use one of {', '.join(FIGURE_MODES)}")
        self.figure = figure
        self.mode = mode
        self._canvas = None
        if mode in ("auto", "ipympl"):
            try:
                self._canvas = _ipympl_canvas(figure)
            except ImportError:
                if mode == "ipympl":
                    raise WidgetError("ipympl is not installed: run `make setup` or `pip install ipympl`, "
                                      "or use figure='image'") from None
        if self._canvas is not None:
            self.mode = "ipympl"
            self.widget: widgets.DOMWidget = self._canvas
        else:
            self.mode = "image"
            self.widget = widgets.Image(format="png")
        self.redraw()

    def png(self) -> bytes:
        """The figure as PNG bytes (what the image mode shows)."""
        buffer = io.BytesIO()
        self.figure.savefig(buffer, format="png", dpi=self.figure.get_dpi())
        return buffer.getvalue()

    def redraw(self) -> None:
        """Show the figure's current state (ipympl: the browser fetches it when it can)."""
        if self._canvas is not None:
            self._canvas.draw_idle()
        else:
            self.widget.value = self.png()


class Ticker:
    """Call ``fn()`` every ``interval_s`` until :meth:`stop`; in the kernel's thread when there is one.

    In a kernel it is an asyncio task on the kernel's running loop, so it runs between cells and
    never concurrently with the student's code or matplotlib; elsewhere (a script, a test) a
    daemon thread. An exception in ``fn`` is printed once (one line) and the ticker keeps going:
    a live plot must survive one bad message. ``thread=True`` always takes a thread: for what
    must go on while a cell runs and touches only its own, locked state (the 3D view's redraws).
    """

    def __init__(self, fn: Callable[[], object], interval_s: float, name: str = "ticker",
                 thread: bool = False) -> None:
        if not 0.0 < float(interval_s) < 3600.0:
            raise WidgetError(f"{name}: interval_s must be in (0, 3600) s, got {interval_s!r}; e.g. 0.2")
        self._fn = fn
        self.interval_s = float(interval_s)
        self.name = name
        self.thread = thread
        self._stop = threading.Event()
        self._task: Optional[Any] = None
        self._thread: Optional[threading.Thread] = None
        self.ticks = 0
        self.errors = 0
        self.in_kernel_loop = False

    @property
    def running(self) -> bool:
        if self._task is not None:
            return not self._task.done()
        return self._thread is not None and self._thread.is_alive()

    def start(self) -> "Ticker":
        if self.running:
            return self
        self._stop.clear()
        try:
            loop = None if self.thread else asyncio.get_running_loop()
        except RuntimeError:
            loop = None
        if loop is not None:
            self.in_kernel_loop = True
            self._task = loop.create_task(self._run_async())
        else:
            self.in_kernel_loop = False
            self._thread = threading.Thread(target=self._run_thread, name=self.name, daemon=True)
            self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._task is not None:
            self._task.cancel()
            self._task = None
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=2.0 + self.interval_s)

    def _call(self) -> None:
        try:
            self._fn()
        except Exception as exc:  # noqa: BLE001 - reported once, see the class doc
            self.errors += 1
            if self.errors == 1:
                print(f"{self.name}: {exc.__class__.__name__}: {exc}".replace("\n", " "), file=sys.stderr)
        self.ticks += 1

    async def _run_async(self) -> None:
        while not self._stop.is_set():
            started = time.monotonic()
            self._call()
            await asyncio.sleep(max(0.0, self.interval_s - (time.monotonic() - started)))

    def _run_thread(self) -> None:
        while not self._stop.is_set():
            started = time.monotonic()
            self._call()
            self._stop.wait(max(0.0, self.interval_s - (time.monotonic() - started)))
