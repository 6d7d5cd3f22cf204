"""The lab twin's installed packages, counts files a later process takes over, and a report that
tells the twin's own nodes from those a launch started (no master: files only)."""

from __future__ import annotations

import os
import sys
import threading
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from hri_teleop.apps.lab_twin import news
from hri_teleop.ros.lab_twin.counts import (
    CountsFile,
    counts_path,
    owner_lock,
    read_activated,
    read_json,
    write_activated,
    write_json_atomic,
)
from hri_teleop.ros.lab_twin.packages import (
    CARTESIAN_VELOCITY_LAUNCH,
    EXECUTABLES,
    ROBOT_IP,
    found_elsewhere,
    write_packages,
)
from hri_teleop.ros.lab_twin.report import NODES, read_report

PORT = "/dev/pts/7"


def test_the_packages_are_laid_out_as_installed_with_this_twins_paths_baked_in(tmp_path: Path) -> None:
    root = write_packages(tmp_path / "packages", tmp_path / "counts", PORT, sys.executable)
    for package in ("franka_control", "rosserial_python"):
        assert ET.parse(root / package / "package.xml").getroot().findtext("name") == package
    launch = ET.parse(root / "franka_control" / "launch" / CARTESIAN_VELOCITY_LAUNCH).getroot()
    assert {a.get("name"): a.get("default") for a in launch.iter("arg")} == {"robot_ip": ROBOT_IP,
                                                                             "load_gripper": "true"}
    nodes = {n.get("name"): n.attrib for n in launch.iter("node")}
    assert {name: (a["pkg"], a["type"]) for name, a in nodes.items()} == {
        "franka_control": ("franka_control", "franka_control_node"),
        "franka_gripper": ("franka_control", "franka_gripper_node"),
        "joint_state_publisher": ("franka_control", "joint_state_publisher")}
    assert nodes["franka_gripper"]["if"] == "$(arg load_gripper)" and nodes["franka_control"]["required"] == "true"
    for (package, executable), module in EXECUTABLES.items():
        script = root / package / "scripts" / executable
        assert os.access(script, os.X_OK)
        text = script.read_text()
        assert text.startswith(f"#!{sys.executable}\n") and repr(module) in text
        assert repr(str((tmp_path / "counts").resolve())) in text
        assert (repr(PORT) in text) == (executable == "serial_node.py")
        compile(text, str(script), "exec")
    # A second start writes them afresh (the board's pty may differ).
    write_packages(root, tmp_path / "counts", "/dev/pts/8", sys.executable)
    assert "'/dev/pts/8'" in (root / "rosserial_python" / "scripts" / "serial_node.py").read_text()


def test_a_counts_file_belongs_to_the_newest_process_of_its_node(tmp_path: Path) -> None:
    path = tmp_path / "franka_control.json"
    counts = CountsFile(path, "/franka_control")
    counts.add("twists")
    counts.flush()
    assert read_json(path)["twists"] == 1
    # Another process of the node, started later (a launch over the twin's own node), wrote the file,
    # holding the owner's lock as every writer does (this process's writer thread may be mid-flush).
    newer = {"node": "/franka_control", "pid": os.getpid() + 1, "started_ns": time.time_ns() + 10 ** 9, "twists": 7}
    with owner_lock(path):
        write_json_atomic(path, newer)
    counts.add("twists")
    counts.flush()
    counts.close(stopped=True)  # not even its last counts
    assert read_json(path) == newer and counts.superseded


def test_a_flush_waits_for_the_owner_lock_and_then_yields_to_the_newer_process(tmp_path: Path) -> None:
    path = tmp_path / "franka_gripper.json"
    counts = CountsFile(path, "/franka_gripper", flush_period_s=3600.0)
    counts.add("goals")
    newer = {"node": "/franka_gripper", "pid": os.getpid() + 1, "started_ns": time.time_ns() + 10 ** 9, "goals": 4}
    with owner_lock(path):  # another process is between reading the owner and writing
        flusher = threading.Thread(target=counts.flush)
        flusher.start()
        flusher.join(timeout=0.2)
        assert flusher.is_alive()  # it waits for the lock instead of writing
        write_json_atomic(path, newer)
    flusher.join(timeout=30.0)
    assert read_json(path) == newer and counts.superseded
    counts.close()


def test_a_counts_file_of_an_older_process_is_taken_over(tmp_path: Path) -> None:
    path = tmp_path / "serial_node.json"
    write_json_atomic(path, {"node": "/serial_node", "pid": os.getpid() + 1, "started_ns": 1, "stopped": True})
    counts = CountsFile(path, "/serial_node")
    counts.close()
    data = read_json(path)
    assert data["pid"] == os.getpid() and "stopped" not in data and not counts.superseded


def test_the_user_stop_lives_in_the_folder_released_unless_engaged(tmp_path: Path) -> None:
    assert read_activated(tmp_path) is True
    write_activated(tmp_path, False)
    assert read_activated(tmp_path) is False
    write_activated(tmp_path, True)
    assert read_activated(tmp_path) is True


def _counts(folder: Path, node: str, **values: object) -> None:
    write_json_atomic(counts_path(folder, node), {"node": node, "pid": 100 + NODES.index(node), **values})


def test_the_report_tells_nodes_a_launch_started_from_the_twins_own_replaced_ones(tmp_path: Path) -> None:
    _counts(tmp_path, "/franka_control", package="franka_control", twists=3)
    _counts(tmp_path, "/franka_gripper", package="franka_control", stopped=True)  # the launch ended
    _counts(tmp_path, "/serial_node")  # the twin's own
    launched = read_report(tmp_path, ["/serial_node"], [], [], registered=["/franka_control", "/serial_node"])
    assert (launched.launched, launched.replaced, launched.stopped) == (["/franka_control"], [], [])
    assert launched.missing == ["/franka_gripper", "/joint_state_publisher"] and launched.twists == 3
    said = news(launched)
    assert said == ["/franka_control runs from the twin's installed packages (pid 100)"]
    assert "from the installed packages (a launch): /franka_control" in launched.lines()[-1]

    over = read_report(tmp_path, [], ["/franka_control"], ["/franka_control"], registered=list(NODES))
    assert (over.launched, over.replaced, over.stopped) == (["/franka_control"], ["/franka_control"],
                                                            ["/franka_control"])
    assert news(over)[0].startswith("/franka_control replaced by another node of that name")


def test_a_real_franka_control_earlier_on_the_path_is_named(tmp_path: Path) -> None:
    root = write_packages(tmp_path / "packages", tmp_path / "counts", PORT, sys.executable)
    assert found_elsewhere(root, str(root)) == []
    real = tmp_path / "opt" / "franka_control"
    real.mkdir(parents=True)
    (real / "package.xml").write_text((root / "franka_control" / "package.xml").read_text())
    assert found_elsewhere(root, f"{tmp_path / 'opt'}:{root}") == [f"franka_control at {real}"]
