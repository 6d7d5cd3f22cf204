"""Ex. 8's controller view in a real browser: cross and circle act only while the pointer holds them.

Headless Chromium shows ``widgets.ControllerView("virtual")`` in JupyterLab; Selenium holds the buttons
with the mouse as a student does. A button that latched (a toggle, as before) kept the gripper closing
to 0 mm after the mouse let go: then holding circle afterwards could not open it (both held: the width
stays). Each release here -- pointer up, the pointer leaving the button, the window losing focus -- is
followed by holding circle, which must open the gripper again.
"""

from __future__ import annotations

import os
import re
import signal

import pytest
from jupyterlab_session import JupyterLab, needs_browser, output_text, process_gone, wait, write_notebook

CELLS = ["import os\nprint('kernel pid', os.getpid())\nfrom hri_teleop.course import widgets\n"
         "view = widgets.ControllerView('virtual')\nview"]
_WIDTH = ("const t = Array.from(document.querySelectorAll('.widget-label')).map(e => e.textContent)"
          ".find(t => / mm$/.test(t)); return t || '';")


def _width_mm(driver) -> float:
    text = driver.execute_script(_WIDTH)
    return float(re.match(r"([\d.]+) mm", text).group(1)) if text else -1.0


def _buttons(driver):
    return driver.find_elements("css selector", ".hri-hold-button")


def test_the_hold_buttons_act_only_while_the_pointer_holds_them(tmp_path, ros_env):
    needs_browser()
    pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.common.action_chains import ActionChains

    root = tmp_path / "notebooks"
    root.mkdir()
    write_notebook(root / "ex08.ipynb", CELLS)
    lab = None
    kernel_pid = None
    try:
        lab = JupyterLab(tmp_path, root, ros_env)
        driver = lab.open("ex08.ipynb")
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        wait(lambda: len(_buttons(driver)) == 2 and _width_mm(driver) == 80.0, 60, "the controller view")
        kernel_pid = int(re.search(r"kernel pid (\d+)", output_text(driver)).group(1))
        close, open_ = _buttons(driver)
        assert "close" in close.text and "open" in open_.text

        def held(button) -> bool:
            return button.find_element("xpath", "..").get_attribute("data-held") == "true"

        def opens_again(after_mm: float) -> None:
            """Holding circle opens the gripper: cross is not held any more (else the width would stay)."""
            ActionChains(driver).click_and_hold(open_).perform()
            wait(lambda: _width_mm(driver) > after_mm + 1.0, 10, f"circle to open the gripper above {after_mm} mm")
            ActionChains(driver).release(open_).perform()
            wait(lambda: not held(open_), 5, "circle to be let go")

        # pointer down, pointer up
        ActionChains(driver).click_and_hold(close).perform()
        wait(lambda: _width_mm(driver) < 78.0, 10, "cross held to close the gripper")
        assert held(close)
        ActionChains(driver).release(close).perform()
        wait(lambda: not held(close), 5, "cross to be let go on pointer up")
        opens_again(_width_mm(driver))

        # pointer down, then the pointer leaves the button with the mouse button still down
        start = _width_mm(driver)
        ActionChains(driver).click_and_hold(close).perform()
        wait(lambda: _width_mm(driver) < start - 2.0, 10, "cross held again")
        ActionChains(driver).move_to_element(driver.find_element("css selector", ".hri-pad")).perform()
        wait(lambda: not held(close), 5, "cross to be let go when the pointer leaves it")
        ActionChains(driver).release().perform()
        opens_again(_width_mm(driver))

        # pointer down, then the window loses focus (another window in front)
        start = _width_mm(driver)
        ActionChains(driver).click_and_hold(close).perform()
        wait(lambda: _width_mm(driver) < start - 2.0, 10, "cross held a third time")
        driver.execute_script("window.dispatchEvent(new Event('blur'));")
        wait(lambda: not held(close), 5, "cross to be let go when the window loses focus")
        ActionChains(driver).release().perform()
        opens_again(_width_mm(driver))
    finally:
        if lab is not None:
            lab.stop()
        if kernel_pid is not None:
            try:
                wait(lambda: process_gone(kernel_pid), 10, "the kernel to exit")
            except AssertionError:
                os.kill(kernel_pid, signal.SIGKILL)  # ours: started by the server this test started
                raise
