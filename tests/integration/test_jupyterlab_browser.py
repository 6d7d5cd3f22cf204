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
from pathlib import Path

from jupyterlab_session import JupyterLab, needs_browser, wait, write_notebook

CELLS = [
    "import os\nprint('kernel pid', os.getpid())\n%matplotlib widget\n"
    "from hri_teleop.course.widgets._base import current_cell_id\nprint('cell id known', bool(current_cell_id()))",
    "from hri_teleop.course.widgets import FsrExplorer\nexplorer = FsrExplorer(4.0)\nexplorer",
    "from hri_teleop.course.widgets import DeadzoneExplorer\nDeadzoneExplorer(figure='image')",
]


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
    needs_browser()
    started = time.monotonic()
    root = tmp_path / "notebooks"
    root.mkdir()
    write_notebook(root / "lab_check.ipynb", CELLS)
    env = dict(os.environ)
    env.pop("ROS_MASTER_URI", None)
    lab = JupyterLab(tmp_path, root, env)
    kernel_pid = None
    try:
        server_up_s = time.monotonic() - started
        driver = lab.open("lab_check.ipynb")
        driver.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells');")
        rendered = wait(lambda: (lambda r: r if r["slider"] and r["canvas_painted"] > 20 and r["img"]
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
        lab.stop()
        if kernel_pid is not None:
            try:
                wait(lambda: not Path(f"/proc/{kernel_pid}").exists(), 10, "the kernel to exit")
            except AssertionError:
                os.kill(kernel_pid, signal.SIGKILL)  # ours: started by the server this test started
                raise
        shutil.rmtree(tmp_path / "chromium", ignore_errors=True)
