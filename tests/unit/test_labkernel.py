"""`make lab`'s kernel: .venv's Python in the lab's ROS shell, registered inside .venv."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from hri_teleop.apps.lab import lab_command
from hri_teleop.ros.kernel import KERNEL_NAME, install_kernelspec, kernelspec

REPO = Path(__file__).resolve().parents[2]


def test_the_kernelspec_starts_ipykernel_through_the_env_wrapper():
    spec = kernelspec(REPO)
    assert spec["argv"] == ["bash", str(REPO / "tools" / "kernel.sh"), "-m", "ipykernel_launcher", "-f",
                            "{connection_file}"]
    assert spec["language"] == "python"


def test_installing_twice_writes_once_into_the_given_prefix(tmp_path):
    folder = install_kernelspec(REPO, tmp_path)
    target = folder / "kernel.json"
    assert folder == tmp_path / "share" / "jupyter" / "kernels" / KERNEL_NAME
    assert json.loads(target.read_text()) == kernelspec(REPO)
    os.utime(target, (1, 1))
    install_kernelspec(REPO, tmp_path)
    assert target.stat().st_mtime == 1, "an unchanged kernelspec was rewritten"


def test_the_wrapper_gives_the_kernel_rospy_and_hri_lab_on_the_package_path():
    env = {"PATH": "/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp")}  # as from a desktop icon
    code = "import os, sys, rospy; print(sys.prefix); print(os.environ['ROS_PACKAGE_PATH'])"
    out = subprocess.run(["bash", str(REPO / "tools" / "kernel.sh"), "-c", code], env=env, capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    prefix, package_path = out.stdout.splitlines()
    assert Path(prefix) == REPO / ".venv"
    assert str(REPO / "hri_lab") in package_path.split(":")


def test_jupyter_lab_opens_notebooks_with_the_hri_teleop_kernel():
    command = lab_command(REPO / "notebooks", ["--no-browser"])
    assert command[:3] == [sys.executable, "-m", "jupyterlab"]
    assert f"--ServerApp.root_dir={REPO / 'notebooks'}" in command
    assert f"--MultiKernelManager.default_kernel_name={KERNEL_NAME}" in command
    assert command[-1] == "--no-browser"


def test_make_lab_runs_setup_then_the_lab_module():
    out = subprocess.run(["make", "-n", "lab", "LAB_ARGS=--port=9999"], cwd=REPO, capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert "tools/setup.sh" in out.stdout
    assert "-m hri_teleop.apps.lab --port=9999" in out.stdout


def test_notebook_kernels_talk_over_private_unix_sockets_with_no_tcp_port_to_lose(tmp_path):
    """TCP kernels pick five ports and release them before binding: a roscore starting beside
    them can take one and the kernel dies. Our runs use socket files in a folder of their own."""
    import nbformat
    from nbclient import NotebookClient

    from hri_teleop.ros.kernel import ipc_kernel_argv, ipc_kernel_config

    install_kernelspec()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("from ipykernel import get_connection_info; print(get_connection_info())")]
    with ipc_kernel_config() as first, ipc_kernel_config() as second:
        folder = Path(first.KernelManager.ip).parent
        assert first.KernelManager.ip != second.KernelManager.ip
        NotebookClient(nb, config=first, kernel_name=KERNEL_NAME, timeout=60, startup_timeout=120).execute()
        info = json.loads(nb.cells[0].outputs[0]["text"])
        assert info["transport"] == "ipc" and info["ip"] == first.KernelManager.ip
    assert not folder.exists(), "the sockets' folder outlived the run"
    assert ipc_kernel_argv(tmp_path) == ["--KernelManager.transport=ipc", f"--KernelManager.ip={tmp_path / 'k'}"]


def test_the_students_jupyter_config_comes_first_once_and_turns_off_the_instructors_nbgrader(tmp_path):
    from hri_teleop.apps.lab import INSTRUCTOR_SERVER_EXTENSIONS, student_config, student_env

    config = student_config(tmp_path)
    env = student_env({"JUPYTER_CONFIG_PATH": f"/elsewhere{os.pathsep}{config}"}, config)
    assert env["JUPYTER_CONFIG_PATH"].split(os.pathsep) == [str(config), "/elsewhere"]
    server = json.loads((config / "jupyter_server_config.json").read_text())["ServerApp"]["jpserver_extensions"]
    assert server == {name: False for name in INSTRUCTOR_SERVER_EXTENSIONS}
    assert "course_id" in (config / "nbgrader_config.py").read_text()


def test_the_students_jupyter_config_is_left_alone_when_right_and_made_in_tmp_where_the_toolkit_is_not_writable(
        tmp_path):
    from hri_teleop.apps.lab import student_config

    first = student_config(tmp_path / "venv")
    stamps = {p: p.stat().st_mtime_ns for p in first.rglob("*") if p.is_file()}
    assert student_config(tmp_path / "venv") == first
    assert {p: p.stat().st_mtime_ns for p in first.rglob("*") if p.is_file()} == stamps
    blocked = tmp_path / "root-owned"
    blocked.mkdir()
    (blocked / "etc").write_text("a file where the folder would go\n")  # as a toolkit the student cannot write
    fallback = student_config(blocked)
    assert fallback.parent == Path(tempfile.gettempdir()) and (fallback / "nbgrader_config.py").is_file()
