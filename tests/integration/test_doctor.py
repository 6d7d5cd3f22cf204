"""make doctor as a lab engineer runs it: at home against the simulated lab it starts (and stops), in
lab mode refusing a simulation on the lab's master, and on serial ports with either sketch."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional

import pytest
from fake_rosserial_board import FakeRosserialBoard
from test_firmware_hil import firmware  # noqa: F401 - the fixture that builds the firmware

from hri_teleop.hardware.sim.simavr_board import SimulatedUno, force_profile, write_profile
from hri_teleop.ros.master import OWN_MASTER_ENV, free_port
from hri_teleop.ros.master_api import master_reachable

REPO = Path(__file__).resolve().parents[2]


def _doctor(env: Dict[str, str], *args: str, stdin: str = "") -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "hri_teleop.apps.doctor", *args], env=env, input=stdin,
                          capture_output=True, text=True, timeout=90, cwd=REPO)


def _env(base: Dict[str, str], mode: str, uri: Optional[str] = None) -> Dict[str, str]:
    env = dict(base)
    env["HRI_MODE"] = mode
    env["ROS_MASTER_URI"] = uri or f"http://127.0.0.1:{free_port()}/"  # nobody there, never 11311
    return env


def _line(out: str, item: str) -> str:
    return next((line for line in out.splitlines() if re.match(rf"^\S+\s+{re.escape(item)}\s", line)), "")


def _processes_on(uri: str) -> List[int]:
    """Processes of this user whose environment points at ``uri`` (what a run left behind)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if f"ROS_MASTER_URI={uri}".encode() in (entry / "environ").read_bytes().split(b"\0"):
                    found.append(int(entry.name))
            except OSError:
                continue
    return found


@pytest.mark.ros
def test_at_home_without_a_master_it_checks_the_simulated_lab_it_started_and_stops_it(ros_env):
    started = time.monotonic()
    proc = _doctor(_env(ros_env, "home"))
    out = proc.stdout
    print(f"\n{out}wall {time.monotonic() - started:.1f} s")
    assert proc.returncode == 0, out + proc.stderr
    uri = re.search(r"started the simulated lab on (\S+) ", out).group(1)
    assert _line(out, "ROS master").startswith("ok") and uri in _line(out, "ROS master")
    assert _line(out, "robot").startswith("ok") and "lab_sim" in _line(out, "robot")
    assert _line(out, "teleoperation").startswith("note") and "not running" in _line(out, "teleoperation")
    # counts arrived (how many per second is the simulated board's speed on this machine, not judged here)
    assert re.match(r"ok\s+board\s+the simulated board \(/lab_sim\) at [1-9]\d*\.\d Hz", _line(out, "board"))
    assert _line(out, "max_sensor_force").startswith("ok")
    assert _line(out, "pad").startswith("note")
    assert re.search(r"\((\d+\.\d) s\)$", out.strip()), out  # it says how long it took (make bench: doctor)
    assert not master_reachable(uri) and not _processes_on(uri), "the simulated lab was left running"


def test_in_lab_mode_without_a_master_it_fails_fast_and_starts_nothing(ros_env):
    proc = _doctor(_env(ros_env, "lab"))
    out = proc.stdout
    assert proc.returncode == 1
    assert _line(out, "ROS master").startswith("FAIL") and "lab's roscore" in _line(out, "ROS master")
    assert "simulation" not in out
    assert _line(out, "board").startswith("FAIL") or "--port" in out  # no Arduino on this machine
    assert re.search(r"doctor: \d+ of \d+ ok or noted, \d+ to fix \(\d\.\d s\)$", out.strip())


@pytest.mark.ros
def test_in_lab_mode_a_simulation_on_the_master_fails_robot_and_board_and_at_home_passes(ros_master, ros_env,
                                                                                         tmp_path):
    idle = tmp_path / "idle.yaml"  # the virtual pad waits for an hour: the node runs through every doctor run
    idle.write_text('[{"t": 3600.0, "tap": "west", "hold": 0.1}]\n')
    launch = ros_master.roslaunch("hri_lab", "teleoperation.launch", {"sim": "true", "pad_script": str(idle)})
    ros_master.wait_for(lambda: "/lab_sim" in ros_master.publishers("/pub_force") or not launch.running, 30,
                        "lab_sim")
    assert launch.running, launch.output()
    unset = _env(ros_env, "lab", ros_master.uri)
    del unset["HRI_MODE"]  # as on a lab PC where nobody set anything: a master the doctor did not start is the lab's
    proc = _doctor(unset, "--no-sim")
    out = proc.stdout
    assert proc.returncode == 1, out
    assert "lab_sim runs on the lab's master" in _line(out, "robot")
    assert _line(out, "board").startswith("FAIL") and "simulate the board" in _line(out, "board")
    assert _line(out, "ROS master").startswith("ok") and "lab mode" in _line(out, "ROS master")
    assert _line(out, "teleoperation").startswith("note") and "virtual pad" in _line(out, "teleoperation")
    own = {OWN_MASTER_ENV: ros_master.env[OWN_MASTER_ENV]}  # the doctor as a child of the master's owner
    in_lab_mode = _doctor(dict(_env(ros_env, "lab", ros_master.uri), **own), "--no-sim").stdout
    assert "private roscore" in _line(in_lab_mode, "ROS master") and _line(in_lab_mode, "ROS master").startswith("FAIL")
    at_home = _doctor(dict(_env(ros_env, "home", ros_master.uri), **own), "--no-sim").stdout  # its own master, at home
    assert _line(at_home, "teleoperation") == "ok    teleoperation     running with the virtual pad; rumble accepted"
    assert _line(at_home, "robot").startswith("ok"), at_home
    launch.stop()


def _measured_rate_hz(line: str, port: str, sketch: str) -> float:
    """The rate the doctor read for the board on ``port``, ok or not.

    The doctor times a board's lines on the host's clock, which is right for an Arduino; a
    simulated board (simavr, a thread on a pty) falls behind on a busy machine and catches up in
    a burst (a fresh-clone run read 116.8 Hz). So these tests take the number and bound it loosely;
    the ok/FAIL rule at 90 and 110 Hz is tests/unit/test_doctor_rules.py's, at its literal edges.
    """
    found = re.match(rf"(ok|FAIL)\s+board\s+{re.escape(port)}: {sketch} at (\d+\.\d) Hz", line)
    assert found, line
    return float(found.group(2))


def test_a_rosserial_board_on_a_port_is_found_by_its_topics_at_the_handouts_rate(ros_env):
    with FakeRosserialBoard(count=17) as board:
        proc = _doctor(_env(ros_env, "home"), "--no-sim", "--port", board.port)
        answered = board.stats.last_time, board.stats.param_answers
    line = _line(proc.stdout, "board")
    print(f"\n{line}")
    assert 1.5 <= _measured_rate_hz(line, board.port, "rosserial") <= 7.0, proc.stdout + proc.stderr  # 3.33 Hz sent
    assert "pub_force (std_msgs/Int16)" in line
    assert answered[0] is not None and answered[0][0] > 0 and answered[1] >= 1, "the probe must answer time and parameter"


def test_a_port_where_no_sketch_answers_fails_with_the_fix(ros_env):
    master, slave = os.openpty()
    try:
        proc = _doctor(_env(ros_env, "home"), "--no-sim", "--port", os.ttyname(slave))
    finally:
        os.close(master)
        os.close(slave)
    line = _line(proc.stdout, "board")
    assert line.startswith("FAIL") and "neither fsr_serial nor rosserial answers" in line and "upload" in line


def test_an_fsr_serial_board_on_a_port_is_found_with_its_rate(
        firmware, ros_env, tmp_path):  # noqa: F811 - the fixture imported above
    link = tmp_path / "ttyACM0"
    profile = write_profile(force_profile([0.0, 1.0], [0.0, 5.0]), tmp_path / "press.txt")
    with SimulatedUno(link, profile, repeat_us=1_000_000):
        proc = _doctor(_env(ros_env, "home"), "--no-sim", "--port", str(link))
    line = _line(proc.stdout, "board")
    print(f"\n{line}")
    assert 50.0 <= _measured_rate_hz(line, str(link), "fsr_serial") <= 200.0, proc.stdout  # 100 Hz sent


@pytest.mark.ros
def test_the_notebook_widget_shows_the_same_checks_in_a_table(ros_env, monkeypatch):
    from hri_teleop.course.widgets import Doctor

    for key, value in _env(ros_env, "home").items():
        monkeypatch.setenv(key, value)
    doctor = Doctor()
    try:
        assert doctor.wait(60) == 0, doctor.lines
    finally:
        doctor.close()
    items = {f.item: f.status for f in doctor.findings}
    assert items["robot"] == "ok" and items["board"] == "ok" and items["ROS master"] == "ok", doctor.lines
    assert "lab_sim" in doctor.table.value and doctor.summary.value.startswith("doctor: ")
    assert all(b.layout.display == "none" for b in doctor.answer_buttons)


@pytest.mark.ros
def test_the_widget_walk_through_skips_the_piston_when_skip_is_pressed(ros_env, monkeypatch):
    from hri_teleop.course.widgets import Doctor

    for key, value in _env(ros_env, "home").items():
        monkeypatch.setenv(key, value)
    doctor = Doctor(walk=True)
    try:
        deadline = time.monotonic() + 60
        while "piston" not in doctor.prompt.value and time.monotonic() < deadline:
            time.sleep(0.05)
        assert "piston" in doctor.prompt.value, doctor.lines
        assert all(b.layout.display == "" for b in doctor.answer_buttons)
        doctor.answer("")  # Skip
        assert doctor.wait(60) == 0, doctor.lines
    finally:
        doctor.close()
    assert "no live reading" not in " ".join(doctor.lines)
    assert {f.item for f in doctor.findings} >= {"max_sensor_force", "pad"}


@pytest.mark.ros
def test_a_bare_master_the_toolkit_did_not_start_is_one_line_with_the_cause_and_both_fixes(foreign_roscore, ros_env):
    env = dict(ros_env, ROS_MASTER_URI=foreign_roscore.uri)  # as a roscore left open on 11311 at home
    for key in ("HRI_MODE", OWN_MASTER_ENV):
        env.pop(key, None)
    proc = _doctor(env)
    out = proc.stdout
    assert proc.returncode == 1, out + proc.stderr
    failed = [line for line in out.splitlines() if line.startswith("FAIL")]
    assert failed == [_line(out, "ROS master")], out
    assert f"a ROS master at {foreign_roscore.uri} that the toolkit did not start" in failed[0]
    assert "on the lab PC this is right" in failed[0] and "at home stop that roscore" in failed[0]
    assert "started the simulated lab" not in out  # nothing simulated starts on a master that may carry the robot
    assert master_reachable(foreign_roscore.uri)
    as_the_lab = _doctor(dict(env, HRI_MODE="lab"), "--no-sim").stdout  # asked for: every lab check
    assert _line(as_the_lab, "ROS master").startswith("ok") and _line(as_the_lab, "robot").startswith("FAIL")
