"""ArmView: the Panda's links drawn where forward kinematics puts them, joints by name, replay, nothing left behind.

What the view sends to its meshcat server is read back from ``view.window`` (the last transform per
path, every object set); forward kinematics is computed here on a model of its own, and the hand's
TCP against the simulation's ``PandaKinematics``. A real meshcat server runs in each test.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
import time
import xml.etree.ElementTree as ET
from types import SimpleNamespace

import numpy as np
import pytest

from hri_teleop.core.joints import JOINT_NAMES, READY_POSE_RAD, ROBOT_JOINT_LIMITS
from hri_teleop.course.widgets.arm3d import (
    ArmView,
    ArmViewError,
    joint_config,
    live_status,
    ready_config,
    replay_frames,
)
from hri_teleop.ros.proc_table import descendants
from hri_teleop.sim.kinematics import PandaKinematics, panda_urdf

pin = pytest.importorskip("pinocchio")
FINGERS = ("panda_finger_joint1", "panda_finger_joint2")


@pytest.fixture
def view():
    arm = ArmView()
    try:
        yield arm
    finally:
        arm.close()


def _joint_state(names, positions):
    return SimpleNamespace(name=list(names), position=list(positions))


def _visual_origins():
    """Each link with a visual, and the visual's origin in the link's frame (4 x 4), read from the URDF."""
    origins = {}
    for link in ET.parse(str(panda_urdf())).getroot().iter("link"):
        visual = link.find("visual")
        if visual is None:
            continue
        origin = visual.find("origin")
        xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = pin.rpy.rpyToMatrix(*rpy), xyz
        origins[link.get("name")] = pose
    return origins


def _forward_kinematics(q9):
    """Each visual's 4 x 4 pose in the base frame: a model built here (not the view's), the URDF's visual origins."""
    model = pin.buildModelFromUrdf(str(panda_urdf()))
    data = model.createData()
    pin.forwardKinematics(model, data, np.asarray(q9, dtype=float))
    pin.updateFramePlacements(model, data)
    return {link: data.oMf[model.getFrameId(link)].homogeneous @ origin for link, origin in _visual_origins().items()}


def _visual_links():
    return sorted(_visual_origins())


def _path(link):
    return f"/meshcat/panda/visuals/{link}_0"


def _some_pose():
    low, high = np.array(ROBOT_JOINT_LIMITS.position_min_rad), np.array(ROBOT_JOINT_LIMITS.position_max_rad)
    return tuple(float(v) for v in low + np.array([0.3, 0.6, 0.45, 0.7, 0.35, 0.55, 0.8]) * (high - low))


def test_the_scene_is_built_from_the_pandas_urdf_with_every_link_that_has_a_visual(view):
    links = _visual_links()
    assert len(links) == 11 and "panda_hand" in links and "panda_leftfinger" in links
    assert sorted(view.window.objects) == sorted(_path(link) for link in links)
    assert view.drawn and view.server.running and "11 links" in view.status.value
    assert f'src="{view.server.web_url}"' in view.frame.value and view.build_s > 0.0  # the time is printed, not judged


def test_it_starts_at_the_ready_pose_with_the_hand_open(view):
    expected = _forward_kinematics(ready_config(0.08))
    for link in _visual_links():
        np.testing.assert_allclose(view.window.transforms[_path(link)], expected[link], atol=1e-9)
    assert view.hand_position_m() == pytest.approx((0.307, 0.0, 0.487), abs=1e-3)


def test_show_moves_every_link_where_forward_kinematics_puts_it(view):
    q = _some_pose()
    before = view.hand_transform().copy()
    view.show(q, width_m=0.03)
    expected = _forward_kinematics([*q, 0.015, 0.015])
    for link in _visual_links():
        np.testing.assert_allclose(view.window.transforms[_path(link)], expected[link], atol=1e-9, err_msg=link)
    assert np.abs(view.hand_transform() - before).max() > 0.05
    fingers = view.window.transforms[_path("panda_leftfinger")][:3, 3] - view.window.transforms[_path(
        "panda_rightfinger")][:3, 3]
    assert np.linalg.norm(fingers) == pytest.approx(0.03, abs=1e-9)  # each finger at half the width
    position, _orientation = PandaKinematics().pose(q)  # the simulation's kinematics agree on the TCP
    assert view.hand_position_m() == pytest.approx(position, abs=1e-9)


def test_show_refuses_six_angles_and_a_width_the_hand_cannot_open_in_one_line(view):
    with pytest.raises(ArmViewError, match="7 joint angles") as info:
        view.show(READY_POSE_RAD[:6])
    assert "\n" not in str(info.value)
    with pytest.raises(ArmViewError, match="0 .. 0.08 m"):
        view.show(READY_POSE_RAD, width_m=0.2)


def test_joint_states_in_another_order_are_taken_by_name(view):
    q = _some_pose()
    names = list(reversed(JOINT_NAMES)) + ["panda_finger_joint2", "panda_finger_joint1"]
    positions = list(reversed(q)) + [0.01, 0.01]
    view.on_joint_state(_joint_state(names, positions))
    view.tick()
    np.testing.assert_allclose(view.q, [*q, 0.01, 0.01])
    expected = _forward_kinematics([*q, 0.01, 0.01])
    np.testing.assert_allclose(view.hand_transform(), expected["panda_hand"], atol=1e-9)


def test_missing_joints_keep_their_angles_and_the_line_names_them(view):
    view.show(READY_POSE_RAD)
    names = [n for n in JOINT_NAMES if n != "panda_joint4"]
    positions = [0.2 if n == "panda_joint1" else READY_POSE_RAD[JOINT_NAMES.index(n)] for n in names]
    view.on_joint_state(_joint_state(names, positions))
    view.tick()  # no exception: drawn with joint 4 where it was
    assert view.q[0] == pytest.approx(0.2) and view.q[3] == pytest.approx(READY_POSE_RAD[3])
    assert "lacks panda_joint4" in view.status.value and "<br" not in view.status.value


def test_joint_config_without_fingers_keeps_the_width_and_one_finger_stands_for_both():
    q, missing = joint_config(JOINT_NAMES, READY_POSE_RAD, ready_config(0.05))
    assert missing == () and tuple(q[7:]) == (0.025, 0.025)
    q, missing = joint_config(["panda_finger_joint1"], [0.01], ready_config(0.05))
    assert missing == JOINT_NAMES and tuple(q[7:]) == (0.01, 0.01)
    q, missing = joint_config(["panda_joint1"], [float("nan")], ready_config())
    assert missing == JOINT_NAMES and q[0] == 0.0


def test_silence_says_what_to_start_and_a_stream_says_its_rates():
    line, error = live_status("/joint_states", 5.0, None, 0, (), 0.0, 0.0, (0.3, 0.0, 0.5))
    assert error and "nothing on /joint_states for 5 s" in line and "lab.start_robot()" in line
    line, error = live_status("/joint_states", 5.0, None, 1, (), 0.0, 0.0, (0.3, 0.0, 0.5))
    assert error and "publisher is connected" in line
    line, error = live_status("/joint_states", 9.0, 4.0, 1, (), 0.0, 0.0, (0.3, 0.0, 0.5))
    assert error and "silent for 4 s" in line
    line, error = live_status("/joint_states", 0.5, None, 0, (), 0.0, 0.0, (0.3, 0.0, 0.5))
    assert not error and line.startswith("waiting")
    line, error = live_status("/joint_states", 9.0, 0.01, 1, (), 30.0, 29.6, (0.3071, 0.0, 0.4869))
    assert not error and "30 Hz received, 30 Hz drawn; hand at (0.307, 0.000, 0.487) m" in line


def _write_bag(path, joint_states=True, n=31, rate_hz=30.0):
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Float32

    from hri_teleop.ros.bags import write_bag

    messages = []
    for k in range(n):
        t = 100.0 + k / rate_hz
        messages.append(("/gripper_width", Float32(data=0.08), t))
        if joint_states:
            q = list(READY_POSE_RAD)
            q[0] = 0.5 * k / (n - 1)
            messages.append(("/joint_states", JointState(name=list(JOINT_NAMES) + list(FINGERS),
                                                          position=q + [0.02, 0.02]), t))
    return write_bag(path, messages)


def test_replay_plays_a_bags_joint_states_with_the_slider(view, tmp_path):
    pytest.importorskip("rosbag")
    bag = _write_bag(tmp_path / "P01_t01.bag")
    assert view.replay(bag) is view
    assert "31 joint states over 1.0 s" in view.status.value
    assert view.controls.layout.display == "" and view.slider.max == 30 and view.play.max == 30
    assert view.q[0] == pytest.approx(0.0)
    view.slider.value = 15
    assert view.q[0] == pytest.approx(0.25) and view.clock.value == "0.5 / 1.0 s"
    view.slider.value = 30
    np.testing.assert_allclose(view.q, [0.5, *READY_POSE_RAD[1:], 0.02, 0.02])
    expected = _forward_kinematics(view.q)
    np.testing.assert_allclose(view.hand_transform(), expected["panda_hand"], atol=1e-9)


def test_a_bag_without_joint_states_says_so_in_one_line(view, tmp_path):
    pytest.importorskip("rosbag")
    bag = _write_bag(tmp_path / "old.bag", joint_states=False)
    view.replay(bag)
    assert "old.bag: no /joint_states in this bag" in view.status.value and view.slider.max == 0
    view.replay(tmp_path / "missing.bag")
    assert "missing.bag: no such bag" in view.status.value


def test_a_list_of_trials_is_offered_in_a_dropdown_and_the_choice_is_replayed(view, tmp_path):
    pytest.importorskip("rosbag")
    _write_bag(tmp_path / "P01_t01.bag", n=11)
    _write_bag(tmp_path / "P01_t02.bag", n=21)
    trials = [SimpleNamespace(sidecar=tmp_path / f"P01_t0{i}.yaml", meta=SimpleNamespace(label=f"P01 trial {i}"))
              for i in (1, 2)]
    view.replay(trials)
    assert view.trial.options == ("P01_t01.bag: P01 trial 1", "P01_t02.bag: P01 trial 2")
    assert "11 joint states" in view.status.value and view.trial.layout.display == ""
    view.trial.value = "P01_t02.bag: P01 trial 2"
    assert "21 joint states" in view.status.value
    view.replay([])
    assert "no trials to replay yet" in view.status.value and view.controls.layout.display == "none"


def test_replay_frames_are_thirty_a_second_each_the_newest_message_by_then():
    times = np.array([0.0, 0.01, 0.02, 0.05, 0.2])
    assert replay_frames(times).tolist() == [0, 2, 3, 3, 3, 3, 4]  # frames at 0, 1/30, 2/30 ... 0.2 s
    assert replay_frames(np.zeros(0)).tolist() == []


def _threads():
    return len(os.listdir("/proc/self/task")), sorted(t.name for t in threading.enumerate())


def test_close_stops_the_server_and_leaves_no_thread_or_process():
    ArmView().close()  # the first view may start thread pools for good (OpenBLAS): measured after it
    before = _threads()
    for _ in range(2):
        arm = ArmView()
        pid = arm.server.process.popen.pid
        assert os.path.exists(f"/proc/{pid}") and threading.active_count() >= 1
        arm.close()
        assert not os.path.exists(f"/proc/{pid}")
        assert descendants(os.getpid()) == []
        assert _threads() == before


def test_a_second_view_works_beside_the_first_with_a_server_of_its_own():
    first, second = ArmView(), ArmView()
    try:
        assert first.server.web_url != second.server.web_url
        second.show(_some_pose())
        first.show(READY_POSE_RAD)
        assert np.abs(first.hand_transform() - second.hand_transform()).max() > 0.05
    finally:
        first.close()
        second.close()
    assert descendants(os.getpid()) == []


@pytest.mark.parametrize("ending", ["pass", "os._exit(0)"], ids=["exit hooks", "killed without exit hooks"])
def test_the_server_stops_when_the_kernel_exits_without_close(ending):
    script = textwrap.dedent(f"""
        import os
        from hri_teleop.course.widgets import ArmView
        view = ArmView()
        print(view.server.process.popen.pid, flush=True)
        {ending}
    """)
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr[-2000:]
    pid = int(proc.stdout.split()[-1])
    deadline = time.monotonic() + 5.0
    while os.path.exists(f"/proc/{pid}") and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not os.path.exists(f"/proc/{pid}"), "the meshcat server outlived its kernel"
    assert proc.stderr.strip() == ""


def test_a_server_that_stops_answering_turns_the_view_into_one_line(view):
    zmq = pytest.importorskip("zmq")
    view.window._socket.setsockopt(zmq.RCVTIMEO, 300)
    view.server.process.kill()
    view.show(_some_pose())  # no exception, no hang
    assert not view.drawn and "stopped answering" in view.status.value and view.frame.value == ""


def test_without_meshcat_the_view_is_one_line_and_starts_nothing(monkeypatch):
    monkeypatch.setitem(sys.modules, "meshcat", None)
    arm = ArmView()
    try:
        assert not arm.drawn and arm.server is None
        assert "needs pinocchio and meshcat" in arm.status.value and "make setup" in arm.status.value
        arm.show(READY_POSE_RAD)  # keeps the configuration, draws nothing
        assert arm.live() is arm and arm.replay("x.bag") is arm
    finally:
        arm.close()
    assert descendants(os.getpid()) == []

