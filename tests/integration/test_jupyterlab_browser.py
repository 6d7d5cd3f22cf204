"""`make lab` for real: JupyterLab in headless Chromium runs a notebook; a widget and plots render.

What a student sees when `make lab` works: the FSR explorer's slider and its ipympl figure
(a <canvas> the browser paints from the kernel's PNGs), and a figure shown as an image
widget (<img>). The notebook runs through JupyterLab's own "run all cells" command, on the
"hri-teleop" kernel that `make lab` registers. Everything the test starts is stopped: the
browser, the server and -- checked by its pid -- the kernel.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import time
import urllib.request
from pathlib import Path

import pytest

from hri_teleop.ros.kernel import KERNEL_NAME, install_kernelspec
from hri_teleop.ros.master import ManagedProcess, free_port

REPO = Path(__file__).resolve().parents[2]
PYTHON = str(REPO / ".venv" / "bin" / "python")
CHROMIUM, CHROMEDRIVER = "/usr/bin/chromium", "/usr/bin/chromedriver"
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
                  "--window-size=1400,1800"]

CELLS = [
    "import os\nprint('kernel pid', os.getpid())\n%matplotlib widget\n"
    "from hri_teleop.course.widgets._base import current_cell_id\nprint('cell id known', bool(current_cell_id()))",
    "from hri_teleop.course.widgets import FsrExplorer\nexplorer = FsrExplorer(4.0)\nexplorer",
    "from hri_teleop.course.widgets import DeadzoneExplorer\nDeadzoneExplorer(figure='image')",
]


def _needs_browser() -> None:
    if Path(CHROMIUM).exists() and Path(CHROMEDRIVER).exists():
        return
    debian = "ID=debian" in Path("/etc/os-release").read_text() if Path("/etc/os-release").exists() else False
    message = "chromium and chromedriver are missing: run `make setup` (it installs chromium chromium-driver)"
    if debian:
        pytest.fail(message)
    pytest.skip("no Debian chromium here (Ubuntu ships it as a snap); " + message)


def _notebook(path: Path) -> None:
    nbformat = pytest.importorskip("nbformat")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(source) for source in CELLS]
    nb.metadata["kernelspec"] = {"name": KERNEL_NAME, "display_name": KERNEL_NAME, "language": "python"}
    nbformat.write(nb, str(path))


def _wait(condition, timeout_s, what, poll_s=0.25):
    deadline = time.monotonic() + timeout_s
    last = None
    while time.monotonic() < deadline:
        last = condition()
        if last:
            return last
        time.sleep(poll_s)
    raise AssertionError(f"timed out after {timeout_s:.0f} s waiting for {what} (last: {last!r})")


def _server_up(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=2) as response:
            return response.status == 200
    except OSError:
        return False


_KERNEL_STATUS = """
const app = window.jupyterapp;
if (!app) return 'no app';
const panel = app.shell.currentWidget;
if (!panel || !panel.sessionContext) return 'no notebook';
const kernel = panel.sessionContext.session && panel.sessionContext.session.kernel;
return kernel ? kernel.status + ' ' + kernel.name : 'no kernel';
"""

_RENDERED = """
const out = {};
const slider = document.querySelector('.jp-OutputArea-output .widget-slider');
out.slider = !!slider && slider.getBoundingClientRect().width > 100;
out.slider_label = slider ? slider.textContent : '';
const canvas = document.querySelector('.jp-OutputArea-output .jupyter-matplotlib-canvas-div canvas');
out.canvas = canvas ? [canvas.width, canvas.height] : null;
out.canvas_painted = 0;
if (canvas && canvas.width > 0) {
  const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
  for (let i = 0; i < data.length; i += 4 * 97) { if (data[i + 3] > 0 && data[i] < 200) out.canvas_painted++; }
}
const img = document.querySelector('.jp-OutputArea-output img.widget-image');
out.img = img ? [img.naturalWidth, img.naturalHeight] : null;
out.text = Array.from(document.querySelectorAll('.jp-OutputArea-output')).map(e => e.innerText).join('\\n');
out.errors = document.querySelectorAll('.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"]').length;
return out;
"""


def test_jupyterlab_runs_a_notebook_and_renders_the_fsr_explorers_slider_and_plots(tmp_path):
    _needs_browser()
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    started = time.monotonic()
    install_kernelspec()  # what `make lab` does (idempotent)
    root = tmp_path / "notebooks"
    root.mkdir()
    _notebook(root / "lab_check.ipynb")
    port, token = free_port(), "hri-" + os.urandom(8).hex()
    env = dict(os.environ)
    for name, sub in (("JUPYTER_CONFIG_DIR", "config"), ("JUPYTER_DATA_DIR", "data"),
                      ("JUPYTER_RUNTIME_DIR", "runtime"), ("JUPYTERLAB_SETTINGS_DIR", "settings"),
                      ("JUPYTERLAB_WORKSPACES_DIR", "workspaces"), ("IPYTHONDIR", "ipython")):
        env[name] = str(tmp_path / sub)
    env.pop("ROS_MASTER_URI", None)
    server = ManagedProcess([PYTHON, "-m", "jupyterlab", "--no-browser", f"--port={port}", "--ServerApp.ip=127.0.0.1",
                             f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={root}",
                             "--ServerApp.port_retries=0", "--LabApp.expose_app_in_browser=True",
                             "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
                             f"--MultiKernelManager.default_kernel_name={KERNEL_NAME}"]
                            + (["--allow-root"] if os.geteuid() == 0 else []),
                            env, tmp_path / "jupyterlab.log", cwd=root)
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in CHROMIUM_FLAGS + [f"--user-data-dir={tmp_path / 'chromium'}"]:
        options.add_argument(flag)
    driver = None
    kernel_pid = None
    try:
        _wait(lambda: not server.running or _server_up(f"http://127.0.0.1:{port}/api/status?token={token}"), 60,
              "JupyterLab to answer")
        assert server.running, f"JupyterLab exited: {server.output()[-1500:]}"
        server_up_s = time.monotonic() - started
        driver = webdriver.Chrome(service=Service(CHROMEDRIVER, log_output=str(tmp_path / "chromedriver.log")),
                                  options=options)
        driver.set_script_timeout(30)
        driver.get(f"http://127.0.0.1:{port}/lab/tree/lab_check.ipynb?token={token}")
        _wait(lambda: driver.execute_script(_KERNEL_STATUS) == f"idle {KERNEL_NAME}", 60,
              "the notebook's hri-teleop kernel to be idle", poll_s=0.5)
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        rendered = _wait(lambda: (lambda r: r if r["slider"] and r["canvas_painted"] > 20 and r["img"]
                                  and r["img"][0] > 0 else None)(driver.execute_script(_RENDERED)), 60,
                         "the slider, the ipympl canvas and the image to render", poll_s=0.5)
        driver.save_screenshot(str(tmp_path / "jupyterlab.png"))
        assert "force (N)" in rendered["slider_label"]
        assert rendered["canvas"][0] > 300 and rendered["canvas"][1] > 100
        assert rendered["img"][0] > 300
        assert "count" in rendered["text"] and "Traceback" not in rendered["text"]
        assert "cell id known True" in rendered["text"], "re-running a cell could not replace its live widgets"
        match = re.search(r"kernel pid (\d+)", rendered["text"])
        assert match, rendered["text"][:500]
        kernel_pid = int(match.group(1))
        print(f"\nbrowser test: server up {server_up_s:.1f} s, all rendered {time.monotonic() - started:.1f} s "
              f"after start; {json.dumps({k: rendered[k] for k in ('canvas', 'img', 'canvas_painted')})}")
    finally:
        if driver is not None:
            driver.quit()
        server.stop(timeout_s=15.0)
        if kernel_pid is not None:
            try:
                _wait(lambda: not Path(f"/proc/{kernel_pid}").exists(), 10, "the kernel to exit")
            except AssertionError:
                os.kill(kernel_pid, signal.SIGKILL)  # ours: started by the server this test started
                raise
        shutil.rmtree(tmp_path / "chromium", ignore_errors=True)
    assert time.monotonic() - started < 90
