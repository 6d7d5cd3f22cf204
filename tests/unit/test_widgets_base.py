"""FigureView and Ticker: figures as widgets, periodic redraws in the right thread."""

from __future__ import annotations

import asyncio
import sys
import threading
import time

import pytest
from matplotlib.figure import Figure

from hri_teleop.course.widgets._base import FigureView, Ticker, WidgetError


def test_image_mode_shows_the_figure_as_png_and_redraw_updates_it():
    figure = Figure(figsize=(2, 2), dpi=50)
    ax = figure.subplots()
    view = FigureView(figure, "image")
    first = bytes(view.widget.value)
    assert first.startswith(b"\x89PNG")
    ax.plot([0, 1], [0, 1], lw=8)
    view.redraw()
    assert bytes(view.widget.value) != first


def test_an_unknown_mode_is_refused():
    with pytest.raises(WidgetError, match="use one of auto, ipympl, image"):
        FigureView(Figure(), "svg")


def test_outside_a_kernel_the_ticker_runs_in_a_daemon_thread_and_stops():
    calls = []
    ticker = Ticker(lambda: calls.append(threading.current_thread().name), 0.01, name="t").start()
    time.sleep(0.2)
    ticker.stop()
    count = len(calls)
    time.sleep(0.05)
    assert count >= 5 and len(calls) == count and not ticker.running
    assert not ticker.in_kernel_loop and calls[0] == "t"


def test_inside_a_running_event_loop_the_ticker_runs_in_the_loops_thread():
    threads = []

    async def main():
        ticker = Ticker(lambda: threads.append(threading.current_thread()), 0.01).start()
        await asyncio.sleep(0.1)
        ticker.stop()
        return ticker

    ticker = asyncio.run(main())
    assert ticker.in_kernel_loop and len(threads) >= 3
    assert set(threads) == {threading.main_thread()}


def test_an_error_in_the_callback_is_reported_once_and_the_ticker_keeps_going(capsys):
    def fail():
        raise ValueError("bad message")

    ticker = Ticker(fail, 0.01, name="plot").start()
    time.sleep(0.1)
    ticker.stop()
    assert ticker.errors >= 3
    assert capsys.readouterr().err.strip() == "plot: ValueError: bad message"


def test_importing_the_widgets_needs_neither_rospy_nor_pygame():
    import subprocess

    code = ("import sys, hri_teleop.course.widgets; "
            "print(sorted(m for m in ('rospy', 'pygame') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def test_a_thread_ticker_runs_in_its_own_thread_even_inside_a_running_loop():
    threads = []

    async def main():
        ticker = Ticker(lambda: threads.append(threading.current_thread()), 0.01, name="drawer", thread=True).start()
        await asyncio.sleep(0.1)
        ticker.stop()
        return ticker

    ticker = asyncio.run(main())
    assert not ticker.in_kernel_loop and not ticker.running
    assert threads and {t.name for t in threads} == {"drawer"}
