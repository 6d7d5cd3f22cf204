"""widgets.BrowserPad for real: a pad seen by headless Chromium drives teleoperation.py, its rumble reaches the pad.

JupyterLab shows ``widgets.BrowserPad()`` on the hri-teleop kernel, joined to this test's roscore, where
teleoperation.py runs with pad:=virtual and /force_mapped is pressed. The Gamepad API is stood in at the
page: ``navigator.getGamepads`` returns a standard-mapped pad whose values the test sets and whose
vibrationActuator records every playEffect. Pushing the left stick up moves the twist forward (+x) at
k_trans; the pad rumbles through playEffect; unplugging it brings the twist to zero and the page says why.
"""

from __future__ import annotations

import os
import re
import signal
import time
from pathlib import Path

import pytest
from jupyterlab_session import JupyterLab, needs_browser, output_text, process_gone, wait, write_notebook

from hri_teleop.core.config import load_teleop_config
from hri_teleop.ros.master import ManagedProcess
from hri_teleop.ros.master_api import NO_MASTER_URI

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
TELEOP = REPO / "hri_lab" / "scripts" / "teleoperation.py"
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
TWIST = CONFIG.twist_topic
CELLS = [
    "import os\nprint('kernel pid', os.getpid())\nfrom hri_teleop.course import ensure_ros, widgets\nros = ensure_ros()",
    "pad = widgets.BrowserPad()\npad",
]
#: The stand-in: a DualSense as Chrome maps it ("standard"), 4 axes and 17 buttons, with a dual-rumble actuator.
FAKE_PAD = """
const button = () => ({pressed: false, touched: false, value: 0});
window.__effects = [];
window.__pad = {
  id: 'DualSense Wireless Controller (STANDARD GAMEPAD Vendor: 054c Product: 0ce6)', index: 0, connected: true,
  mapping: 'standard', timestamp: 0, axes: [0, 0, 0, 0], buttons: Array.from({length: 17}, button),
  vibrationActuator: {type: 'dual-rumble', effects: ['dual-rumble', 'trigger-rumble'],
    playEffect(type, params) { window.__effects.push([type, params]); return Promise.resolve('complete'); },
    reset() { window.__effects.push(['reset', {}]); return Promise.resolve('complete'); }},
};
window.__pads = [window.__pad, null, null, null];
Object.defineProperty(Navigator.prototype, 'getGamepads', {value: () => window.__pads, configurable: true});
"""
PAD_STATUS = "const s = document.querySelector('.hri-bp-status'); return s ? s.textContent : '';"


def _values(echo) -> list:
    """The floats ``rostopic echo <topic>/linear/x`` printed so far."""
    return [float(line) for line in echo.output().splitlines() if re.fullmatch(r"-?\d+(\.\d+)?(e-?\d+)?", line.strip())]


def test_a_pad_in_the_browser_drives_the_node_rumbles_and_stops_the_robot_when_unplugged(ros_master, tmp_path):
    needs_browser()
    pytest.importorskip("selenium.webdriver")
    started = time.monotonic()
    root = tmp_path / "notebooks"
    root.mkdir()
    write_notebook(root / "pad.ipynb", CELLS)
    unbuffered = {"PYTHONUNBUFFERED": "1"}
    node = ros_master.run([str(TELEOP), "_pad:=virtual"], "teleoperation")
    force = ros_master.run(["rostopic", "pub", "-r", "20", "/force_mapped", "std_msgs/Float32", "data: 0.8"], "force")
    echo = ros_master.run(["rostopic", "echo", f"{TWIST}/linear/x"], "twist_x", extra_env=unbuffered)
    lab = None
    kernel_pid = None
    try:
        lab = JupyterLab(tmp_path, root, ros_master.env)
        driver = lab.open("pad.ipynb")
        driver.execute_script(FAKE_PAD)
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        text = wait(lambda: (lambda t: t if "kernel pid" in t and ("gamepad" in t or "Error" in t) else None)(
            output_text(driver)), 60, "the BrowserPad cell to show the pad", poll_s=0.25)
        assert "Traceback" not in text and "Error" not in text, text[-2000:]
        kernel_pid = int(re.search(r"kernel pid (\d+)", text).group(1))
        ros_master.wait_for(lambda: ros_master.connections("/teleoperation", "/teleoperation/virtual_joy") >= 1
                            or not node.running, 30, "the node to connect to the widget's virtual_joy")
        assert node.running, node.output()
        status = wait(lambda: (lambda s: s if "drives /teleoperation" in s else None)(driver.execute_script(PAD_STATUS)),
                      10, "the page to say the pad drives the node")
        assert "DualSense" in status and "on the pad" in status
        wait(lambda: _values(echo), 10, "the twist on " + TWIST)
        assert max(abs(v) for v in _values(echo)) == 0.0, "the twist moved before the stick did"

        pushed_at = time.monotonic()
        driver.execute_script("window.__pad.axes[1] = -1.0;")  # the browser reads up as -1
        wait(lambda: _values(echo)[-1] == pytest.approx(CONFIG.params.k_trans), 10,
             "the twist to reach k_trans forward (+x)")
        full_s = time.monotonic() - pushed_at
        assert min(_values(echo)) >= -1e-9, "the twist went backwards for a stick pushed up"
        effects = wait(lambda: [e for e in driver.execute_script("return window.__effects;")
                                if e[0] == "dual-rumble" and e[1]["strongMagnitude"] > 0.0], 10,
                       "the node's rumble to reach the pad's playEffect")
        assert 0.0 < effects[-1][1]["strongMagnitude"] <= 1.0 and effects[-1][1]["duration"] > 0
        bar = driver.execute_script("return document.querySelector('.hri-bp-bar').style.width;")
        assert bar not in ("", "0%"), bar

        count = len(_values(echo))
        unplugged_at = time.monotonic()
        driver.execute_script("window.__pad.connected = false; window.__pads = [null, null, null, null];")
        wait(lambda: _values(echo)[-1] == 0.0, 10, "the twist to come to rest after the pad was unplugged")
        stop_s = time.monotonic() - unplugged_at
        assert all(v >= -1e-9 for v in _values(echo)[count:]), "the ramp down overshot"
        said = wait(lambda: (lambda s: s if "no gamepad" in s else None)(driver.execute_script(PAD_STATUS)), 10,
                    "the page to say there is no gamepad")
        round_trip = driver.execute_script("return document.querySelector('.hri-browser-pad').dataset.roundTripMs;")
        assert node.running, node.output()
        print(f"\nbrowser pad: stick to full twist {full_s:.2f} s, unplugged to rest {stop_s:.2f} s, page -> "
              f"kernel -> page {round_trip} ms, {len(effects)} rumble effects; {said!r}; {time.monotonic() - started:.0f} s")
    finally:
        if lab is not None:
            lab.stop()
        for proc in (echo, force, node):
            proc.stop()
        if kernel_pid is not None:
            try:
                wait(lambda: process_gone(kernel_pid), 10, "the kernel to exit")
            except AssertionError:
                os.kill(kernel_pid, signal.SIGKILL)  # ours: started by the server this test started
                raise


# -- the student's route: PAD = "browser" in a notebook at home (the kernel's own master) ---------------------
ANSWER_KEY = REPO / "solutions" / "hri_lab"  # the answer key's node stands in as the student's
STUDENT_CELLS = [
    "import os\nimport rospy\nfrom std_msgs.msg import Float32\nfrom hri_teleop.course import ensure_ros, lab\n"
    "ros = ensure_ros()\nprint('kernel pid', os.getpid(), 'master', os.environ['ROS_MASTER_URI'], ros.mode)",
    # the piston pressed: the student's node rumbles with /force_mapped
    "force = rospy.Publisher('/force_mapped', Float32, queue_size=1)\n"
    "pressing = rospy.Timer(rospy.Duration(0.05), lambda _event: force.publish(Float32(0.8)))",
    "PAD = 'browser'\nrobot = lab.start_robot(object='none')\n"
    f"node = lab.run_student({str(ANSWER_KEY / 'scripts' / 'teleoperation.py')!r}, 'teleoperation', "
    "**lab.pad_params(PAD))\nlab.browser_pad(PAD)",
]


def _heights(echo: ManagedProcess) -> list:
    """The hand's heights ``rostopic echo /lab_sim/ee_pose/pose/position/z`` printed so far."""
    return [float(line) for line in echo.output().splitlines() if re.fullmatch(r"-?\d+\.\d+(e-?\d+)?", line.strip())]


def test_a_pad_in_the_browser_drives_the_students_own_node_and_the_simulated_arm_and_the_rumble_comes_back(
        tmp_path, ros_env):
    needs_browser()
    pytest.importorskip("selenium.webdriver")
    started = time.monotonic()
    root = tmp_path / "notebooks"
    root.mkdir()
    write_notebook(root / "ex10.ipynb", STUDENT_CELLS)
    env = dict(ros_env, ROS_MASTER_URI=NO_MASTER_URI)  # nothing answers: the kernel starts its own (home)
    lab = echo = None
    kernel_pid = None
    try:
        lab = JupyterLab(tmp_path, root, env)
        driver = lab.open("ex10.ipynb")
        driver.execute_script(FAKE_PAD)
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        try:
            status = wait(lambda: (lambda s: s if "drives /teleoperation" in s or "Error" in output_text(driver)
                                   else None)(driver.execute_script(PAD_STATUS)), 120,
                          "the browser pad to drive the student's node", poll_s=0.5)
        except AssertionError as exc:
            raise AssertionError(f"{exc}; the notebook shows: {output_text(driver)[-2000:]}") from None
        text = output_text(driver)
        assert "Traceback" not in text and "Error" not in text and "refused" not in text, text[-2000:]
        assert "DualSense" in status and "on the pad" in status, status
        found = re.search(r"kernel pid (\d+) master (\S+) home", text)
        assert found, text[-2000:]
        kernel_pid, uri = int(found.group(1)), found.group(2)
        echo = ManagedProcess(["rostopic", "echo", "/lab_sim/ee_pose/pose/position/z"],
                              dict(env, ROS_MASTER_URI=uri, PYTHONUNBUFFERED="1"), tmp_path / "z.log")
        start_z = wait(lambda: _heights(echo), 30, "the simulated arm's hand height")[-1]
        # the piston is pressed (/force_mapped 0.8) from the start: the node's rumble comes back to the page
        effects = wait(lambda: [e for e in driver.execute_script("return window.__effects;")
                                if e[0] == "dual-rumble" and e[1]["strongMagnitude"] > 0.0], 20,
                       "the student's node's rumble to reach the pad's playEffect")
        assert effects[-1][1]["strongMagnitude"] == pytest.approx(0.8, abs=0.02), effects[-1]
        bar = driver.execute_script("return document.querySelector('.hri-bp-bar').style.width;")
        assert bar not in ("", "0%"), bar

        pushed_at = time.monotonic()
        driver.execute_script("window.__pad.axes[3] = -1.0;")  # right stick up (the browser reads up as -1): +z
        wait(lambda: _heights(echo)[-1] > start_z + 0.03, 30, "the hand to rise 3 cm through the student's node")
        rise_s = time.monotonic() - pushed_at
        wait(lambda: (lambda h: len(h) > 2 and h[-1] > h[-3])(_heights(echo)), 10, "the hand still rising")

        unplugged_at = time.monotonic()
        driver.execute_script("window.__pad.connected = false; window.__pads = [null, null, null, null];")
        wait(lambda: "no gamepad" in driver.execute_script(PAD_STATUS), 20, "the page to say there is no gamepad")

        def at_rest():
            heights = _heights(echo)
            return len(heights) > 20 and max(heights[-20:]) - min(heights[-20:]) < 1e-4
        wait(at_rest, 30, "the hand to come to rest after the pad was unplugged (input lost)")
        stop_s = time.monotonic() - unplugged_at
        print(f"\nstudent's node, browser pad: 3 cm up in {rise_s:.2f} s, unplugged to rest {stop_s:.2f} s, "
              f"{len(effects)} rumble effects ({effects[-1][1]['strongMagnitude']:.2f}); {time.monotonic() - started:.0f} s")
    finally:
        if echo is not None:
            echo.stop()
        if lab is not None:
            lab.stop()
        if kernel_pid is not None:
            try:
                wait(lambda: process_gone(kernel_pid), 20, "the kernel to exit (its nodes and roscore with it)")
            except AssertionError:
                os.kill(kernel_pid, signal.SIGKILL)  # ours: started by the server this test started
                raise
