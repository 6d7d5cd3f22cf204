"""The 3D arm view for real: JupyterLab in headless Chromium, meshcat's WebGL canvas, /joint_states moving the hand.

A notebook cell shows ``widgets.ArmView().live()`` on the hri-teleop kernel, joined to a private
roscore of this test. The meshcat iframe must load the Panda's meshes and paint them (a screenshot
of the iframe: the arm's white links on meshcat's blue background), say in one line that nothing
arrives, then follow a JointState published here: the hand's pose in the browser's scene is the
one forward kinematics gives, the line says where the hand is, and the picture changes. Everything
started is stopped and checked by pid: browser, server, kernel, meshcat server, publisher.
"""

from __future__ import annotations

import io
import os
import re
import shutil
import signal
import time

import numpy as np
import pytest
from jupyterlab_session import JupyterLab, needs_browser, output_text, process_gone, wait, write_notebook

from hri_teleop.core.joints import JOINT_NAMES
from hri_teleop.ros.master import PrivateMaster

pytestmark = pytest.mark.ros

#: The published pose: joint 1 turned 0.8 rad, the elbow bent further; the hand half open.
Q = (0.8, -0.2, 0.0, -1.9, 0.0, 1.7, 0.785)
WIDTH_M = 0.04
CELLS = [
    "import os\nprint('kernel pid', os.getpid())\nfrom hri_teleop.course import ensure_ros, widgets\nros = ensure_ros()",
    "view = widgets.ArmView().live()\nprint(f'built in {view.build_s:.2f} s; server pid {view.server.process.popen.pid}')"
    "\nview",
]
_HAND = "viewer.scene_tree.find(['meshcat', 'panda', 'visuals', 'panda_hand_0']).object"
_SCENE = f"""
const hand = {_HAND};
const meshes = [];
hand.traverse(o => {{ if (o.isMesh) meshes.push(o); }});
const canvas = document.querySelector('canvas');
return {{meshes: meshes.length, matrix: hand.matrixWorld.elements,
         canvas: canvas ? [canvas.width, canvas.height, !!canvas.getContext('webgl2') || !!canvas.getContext('webgl')] : null}};
"""


def _arm_pixels(png: bytes) -> int:
    """Pixels of the arm's white and light grey links (meshcat's background is a saturated blue gradient)."""
    from PIL import Image

    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)
    return int(((rgb.min(axis=2) > 150) & (rgb.max(axis=2) - rgb.min(axis=2) < 40)).sum())


def _expected_hand() -> np.ndarray:
    """The hand link's pose (base frame) for Q by forward kinematics, in three.js's y-up world as meshcat draws it."""
    import pinocchio as pin

    from hri_teleop.sim.kinematics import panda_urdf

    model = pin.buildModelFromUrdf(str(panda_urdf()))
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.array([*Q, WIDTH_M / 2, WIDTH_M / 2]))
    z_up_to_y_up = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], dtype=float)
    return z_up_to_y_up @ data.oMf[model.getFrameId("panda_hand")].homogeneous


def test_an_arm_view_cell_draws_the_panda_in_webgl_and_follows_joint_states(tmp_path):
    needs_browser()
    pytest.importorskip("selenium.webdriver")
    from conftest import _ros_env  # tests/conftest.py, on sys.path under pytest
    from selenium.webdriver.common.by import By

    started = time.monotonic()
    root = tmp_path / "notebooks"
    root.mkdir()
    write_notebook(root / "arm.ipynb", CELLS)
    master = PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros").start()
    lab = None
    pids = {}
    try:
        lab = JupyterLab(tmp_path, root, master.env)
        # WebGL without a GPU: Chromium falls back to SwiftShader, which it now only allows when asked.
        driver = lab.open("arm.ipynb", ["--enable-unsafe-swiftshader"])
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        text = wait(lambda: (lambda t: t if "server pid" in t or "Error" in t else None)(output_text(driver)), 90,
                     "the ArmView cell to run", poll_s=0.5)
        assert "Traceback" not in text and "Error" not in text, text[-2000:]
        pids = {name: int(re.search(rf"{name} pid (\d+)", text).group(1)) for name in ("kernel", "server")}
        build_s = float(re.search(r"built in ([\d.]+) s", text).group(1))
        kernel_node = wait(lambda: [n for n in master.subscribers("/joint_states") if n.startswith("/hri_notebook")],
                            30, "the kernel's node to subscribe to /joint_states")[0]
        silent = wait(lambda: (lambda t: t if "nothing on /joint_states" in t else None)(output_text(driver)), 30,
                       "the line that says nothing arrives", poll_s=0.5)
        assert "lab.start_robot()" in silent

        iframe = wait(lambda: driver.find_elements(By.CSS_SELECTOR, ".jp-OutputArea-output iframe"), 30,
                       "the meshcat iframe")[0]
        driver.switch_to.frame(iframe)
        scene = wait(lambda: (lambda s: s if s["meshes"] > 0 else None)(driver.execute_script(_SCENE)), 60,
                      "meshcat to load the hand's mesh", poll_s=0.5)
        assert scene["canvas"] and scene["canvas"][0] > 300 and scene["canvas"][2], scene
        loaded_s = time.monotonic() - started
        driver.switch_to.default_content()
        time.sleep(0.5)  # one more frame after the last mesh: nothing to wait for but the next paint
        ready_png = iframe.screenshot_as_png
        assert _arm_pixels(ready_png) > 2000, "the WebGL canvas shows no arm"

        joints = list(JOINT_NAMES) + ["panda_finger_joint1", "panda_finger_joint2"]
        message = f"{{name: {joints}, position: {list(Q) + [WIDTH_M / 2] * 2}}}"
        publisher = master.run(["rostopic", "pub", "-r", "30", "/joint_states", "sensor_msgs/JointState", message],
                               "joint_states")
        master.wait_for(lambda: master.connections(kernel_node, "/joint_states") >= 1, 30,
                        "the kernel's subscriber to connect to the publisher")
        line = wait(lambda: (lambda t: t if re.search(r"live /joint_states: [1-9]\d* Hz received, [1-9]\d* Hz drawn", t)
                              else None)(output_text(driver)), 30, "the line to say the view follows the arm",
                     poll_s=0.5)
        hand = np.array([float(v) for v in re.search(r"hand at \(([-\d.]+), ([-\d.]+), ([-\d.]+)\) m",
                                                     line).groups()])
        assert np.linalg.norm(hand - (0.307, 0.0, 0.487)) > 0.2, f"the hand did not move from the ready pose: {line}"
        received_hz, drawn_hz = (int(v) for v in re.search(r"(\d+) Hz received, (\d+) Hz drawn", line).groups())
        assert received_hz > 0 and drawn_hz > 0, line  # how fast it follows: printed below, not judged

        driver.switch_to.frame(iframe)
        expected = _expected_hand()
        matrix = wait(lambda: (lambda m: m if np.allclose(np.array(m).reshape(4, 4).T, expected, atol=1e-6)
                                else None)(driver.execute_script(_SCENE)["matrix"]), 10,
                       "the browser's hand to reach the pose forward kinematics gives")
        driver.switch_to.default_content()
        time.sleep(0.5)
        moved_png = iframe.screenshot_as_png
        from PIL import Image, ImageChops

        before, after = (Image.open(io.BytesIO(p)).convert("RGB") for p in (ready_png, moved_png))
        changed = int((np.asarray(ImageChops.difference(before, after)).max(axis=2) > 40).sum())
        assert changed > 1000 and _arm_pixels(moved_png) > 2000, f"the picture did not follow: {changed} pixels"
        (tmp_path / "arm_ready.png").write_bytes(ready_png)
        (tmp_path / "arm_moved.png").write_bytes(moved_png)
        publisher.stop()
        print(f"\narm view: built in {build_s:.2f} s in the kernel, meshes in the browser {loaded_s:.1f} s after "
              f"start; live {received_hz} Hz received, {drawn_hz} Hz drawn; {changed} pixels changed; hand "
              f"{hand}; matrix ok {len(matrix) == 16}")
    finally:
        if lab is not None:
            lab.stop()  # the kernel as JupyterLab's "Shut Down Kernel" does: its exit hooks run
        master.stop()
        for name, pid in pids.items():
            try:
                wait(lambda pid=pid: process_gone(pid), 10, f"the {name} to exit")
            except AssertionError:
                os.kill(pid, signal.SIGKILL)  # ours: started by the server this test started
                raise
        shutil.rmtree(tmp_path / "chromium", ignore_errors=True)
    assert pids.keys() == {"kernel", "server"}
