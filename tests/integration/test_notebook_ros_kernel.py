"""ROS inside a Jupyter kernel: a private roscore when none is reachable, stopped with the kernel;
one node however often the cell runs; one line and working non-ROS widgets without rospy."""

from __future__ import annotations

import os
import socket
import subprocess
import textwrap
import time
from pathlib import Path

import pytest

from hri_teleop.course.notebook_ros import NO_ROSPY_MESSAGE
from hri_teleop.ros.master import free_port

pytestmark = pytest.mark.ros  # they start roscores (private ones, as a kernel would)

REPO = Path(__file__).resolve().parents[2]
PYTHON = str(REPO / ".venv" / "bin" / "python")


def _port_open(port: int) -> bool:
    with socket.socket() as sock:
        return sock.connect_ex(("127.0.0.1", port)) == 0


def _port_of(uri: str) -> int:
    return int(uri.rstrip("/").rsplit(":", 1)[1])


def _wait_closed(port: int, timeout_s: float = 15.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if not _port_open(port):
            return True
        time.sleep(0.1)
    return False


def test_without_rospy_ros_cells_say_what_to_install_in_one_line_and_the_rest_works():
    code = textwrap.dedent("""
        import sys
        sys.modules["rospy"] = None  # a laptop without ROS: `import rospy` raises ImportError
        from hri_teleop.course.notebook_ros import NotebookRosError, ensure_ros
        session = ensure_ros()
        print("session", bool(session))
        from hri_teleop.course.widgets import CalibrationWidget, FsrExplorer, LivePlot
        print("fsr count", FsrExplorer(figure="image").reading.count)
        print("live plot", LivePlot().status.value)
        print("calibration", CalibrationWidget().status.value)
        try:
            ensure_ros(required=True)
        except NotebookRosError as exc:
            print("raised", exc)
    """)
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{free_port()}/")
    out = subprocess.run([PYTHON, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stderr.strip() == f"ROS: {NO_ROSPY_MESSAGE}", "not exactly one line on stderr"
    lines = out.stdout.splitlines()
    assert lines[0] == "session False"
    assert lines[1] == "fsr count 597"
    assert NO_ROSPY_MESSAGE.replace("`", "") in lines[2].replace("`", "") and "color:#b00020" in lines[2]
    assert "rospy is not installed" in lines[3]
    assert lines[4] == f"raised {NO_ROSPY_MESSAGE}"


def test_without_a_master_a_private_roscore_starts_and_stops_when_the_process_exits(tmp_path):
    code = textwrap.dedent("""
        import os
        from hri_teleop.ros.master_api import master_reachable
        from hri_teleop.course.notebook_ros import ensure_ros
        session = ensure_ros("private")
        assert ensure_ros() is session
        print(session.master_uri, os.environ["ROS_MASTER_URI"], session.started_master,
              master_reachable(session.master_uri), session._master.work_dir, flush=True)
    """)
    unused = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{unused}/", ROS_LOG_DIR=str(tmp_path))
    out = subprocess.run([PYTHON, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    report, values = out.stdout.splitlines()
    uri, env_uri, started, reachable, work_dir = values.split()
    assert uri == env_uri and uri != f"http://127.0.0.1:{unused}/" and ":11311" not in uri
    assert started == "True" and reachable == "True"
    assert report.startswith("ROS (home mode): node /private_") and f"private roscore at {uri}" in report
    assert f"export ROS_MASTER_URI={uri}" in report
    assert _wait_closed(_port_of(uri)), f"the private roscore at {uri} outlived its process"
    assert not Path(work_dir).exists(), "the private roscore's folder (logs, pid) outlived its process"
    assert "Traceback" not in out.stderr, f"the exit printed a traceback: {out.stderr}"


def test_in_a_jupyter_kernel_rerunning_the_cell_keeps_one_node_and_stopping_the_kernel_stops_roscore(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    from hri_teleop.ros.kernel import install_kernelspec

    install_kernelspec()  # what `make lab` does; idempotent
    cell = ("from hri_teleop.course.notebook_ros import ensure_ros\nsession = ensure_ros()\n"
            "print(session.master_uri, session.node_name)")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(cell), nbformat.v4.new_code_cell(cell),  # the cell run twice
                nbformat.v4.new_code_cell("from hri_teleop.course.widgets import LivePlot\nplot = LivePlot(figure='image')"),
                nbformat.v4.new_code_cell("import asyncio\nawait asyncio.sleep(1.2)\n"
                                          "print(plot.ticker.in_kernel_loop, plot.ticker.ticks >= 2)")]
    env_uri = f"http://127.0.0.1:{free_port()}/"
    old = os.environ.get("ROS_MASTER_URI")
    os.environ["ROS_MASTER_URI"] = env_uri  # the kernel inherits it: nothing listens there
    try:
        client = nbclient.NotebookClient(nb, timeout=120, kernel_name="hri-teleop",
                                         resources={"metadata": {"path": str(tmp_path)}})
        client.execute()
    finally:
        if old is None:
            os.environ.pop("ROS_MASTER_URI", None)
        else:
            os.environ["ROS_MASTER_URI"] = old

    def text(index):
        return "".join(o.get("text", "") for o in nb.cells[index].outputs if o.get("name") == "stdout")

    first, second = text(0).splitlines()[-1], text(1).strip()
    assert first == second, "re-running the cell made another node or master"
    uri = first.split()[0]
    assert uri != env_uri and "private roscore" in text(0)
    assert not any(o.get("output_type") == "error" for c in nb.cells for o in c.outputs)
    assert text(3).strip() == "True True", "the live plot does not redraw in the kernel's event loop"
    assert _wait_closed(_port_of(uri)), f"the private roscore at {uri} outlived its kernel"
