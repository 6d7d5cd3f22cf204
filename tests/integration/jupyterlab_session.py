"""JupyterLab on a free port with a private Jupyter home, and headless Chromium showing one notebook in it.

For the browser tests: ``lab = JupyterLab(tmp_path, root, env)`` starts the server (the hri-teleop
kernel by default), ``lab.open(name, flags)`` a browser on the notebook with its kernel idle,
``lab.stop()`` ends both (kernels first, through the server's API, so their exit hooks run).
"""

from __future__ import annotations

import json
import os
import time
import urllib.request
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Sequence

import pytest

from hri_teleop.ros.kernel import KERNEL_NAME, install_kernelspec
from hri_teleop.ros.master import ManagedProcess, free_port

REPO = Path(__file__).resolve().parents[2]
PYTHON = str(REPO / ".venv" / "bin" / "python")
CHROMIUM, CHROMEDRIVER = "/usr/bin/chromium", "/usr/bin/chromedriver"
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
                  "--window-size=1400,1800"]
#: The notebook panel's kernel, as JupyterLab's front end sees it.
KERNEL_STATUS = """
const app = window.jupyterapp;
if (!app) return 'no app';
const panel = app.shell.currentWidget;
if (!panel || !panel.sessionContext) return 'no notebook';
const kernel = panel.sessionContext.session && panel.sessionContext.session.kernel;
return kernel ? kernel.status + ' ' + kernel.name : 'no kernel';
"""
JUPYTER_HOME = (("JUPYTER_CONFIG_DIR", "config"), ("JUPYTER_DATA_DIR", "data"), ("JUPYTER_RUNTIME_DIR", "runtime"),
                ("JUPYTERLAB_SETTINGS_DIR", "settings"), ("JUPYTERLAB_WORKSPACES_DIR", "workspaces"),
                ("IPYTHONDIR", "ipython"))


def needs_browser() -> None:
    """Fail where make setup installs Chromium (Debian) and it is missing; skip elsewhere (Ubuntu's snap)."""
    if Path(CHROMIUM).exists() and Path(CHROMEDRIVER).exists():
        return
    debian = "ID=debian" in Path("/etc/os-release").read_text() if Path("/etc/os-release").exists() else False
    message = "chromium and chromedriver are missing: run `make setup` (it installs chromium chromium-driver)"
    if debian:
        pytest.fail(message)
    pytest.skip("no Debian chromium here (Ubuntu ships it as a snap); " + message)


def wait(condition: Callable[[], Any], timeout_s: float, what: str, poll_s: float = 0.25) -> Any:
    """Poll ``condition`` until it is true and return its value; AssertionError naming ``what`` on timeout."""
    deadline = time.monotonic() + timeout_s
    last = None
    while time.monotonic() < deadline:
        last = condition()
        if last:
            return last
        time.sleep(poll_s)
    raise AssertionError(f"timed out after {timeout_s:.0f} s waiting for {what} (last: {last!r})")


def output_text(driver: Any) -> str:
    """The text of every cell output on the page, joined by newlines."""
    return str(driver.execute_script(
        "return Array.from(document.querySelectorAll('.jp-OutputArea-output')).map(e => e.innerText).join('\\n');"))


def process_gone(pid: int) -> bool:
    """Whether the process ``pid`` has exited (gone, or a zombie its parent has not reaped yet)."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


def server_up(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=2) as response:
            return bool(response.status == 200)
    except OSError:
        return False


def write_notebook(path: Path, cells: Sequence[str]) -> None:
    """A notebook of these code cells on the hri-teleop kernel."""
    import nbformat

    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(cell) for cell in cells])
    notebook.metadata["kernelspec"] = {"name": KERNEL_NAME, "display_name": KERNEL_NAME, "language": "python"}
    nbformat.write(notebook, str(path))


class JupyterLab:
    """A JupyterLab server serving ``root``; ``env`` is the environment its kernels get."""

    def __init__(self, tmp_path: Path, root: Path, env: Mapping[str, str]) -> None:
        install_kernelspec()  # what `make lab` does (idempotent)
        self.tmp_path = tmp_path
        self.port, self.token = free_port(), "hri-" + os.urandom(8).hex()
        full = dict(env)
        full.update({name: str(tmp_path / sub) for name, sub in JUPYTER_HOME})
        self.driver: Any = None
        self.server = ManagedProcess(
            [PYTHON, "-m", "jupyterlab", "--no-browser", f"--port={self.port}", "--ServerApp.ip=127.0.0.1",
             f"--IdentityProvider.token={self.token}", f"--ServerApp.root_dir={root}", "--ServerApp.port_retries=0",
             "--LabApp.expose_app_in_browser=True", "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
             f"--MultiKernelManager.default_kernel_name={KERNEL_NAME}"] + (["--allow-root"] if os.geteuid() == 0 else []),
            full, tmp_path / "jupyterlab.log", cwd=root)
        wait(lambda: not self.server.running or server_up(self.url("api/status")), 60, "JupyterLab to answer")
        assert self.server.running, f"JupyterLab exited: {self.server.output()[-1500:]}"

    def url(self, path: str) -> str:
        return f"http://127.0.0.1:{self.port}/{path}?token={self.token}"

    def open(self, notebook: str, flags: Sequence[str] = ()) -> Any:
        """Headless Chromium on ``notebook``, returned once its kernel is idle."""
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for flag in [*CHROMIUM_FLAGS, *flags, f"--user-data-dir={self.tmp_path / 'chromium'}"]:
            options.add_argument(flag)
        self.driver = webdriver.Chrome(service=Service(CHROMEDRIVER, log_output=str(self.tmp_path / "chromedriver.log")),
                                       options=options)
        self.driver.set_script_timeout(30)
        self.driver.get(self.url(f"lab/tree/{notebook}"))
        wait(lambda: self.driver.execute_script(KERNEL_STATUS) == f"idle {KERNEL_NAME}", 60,
              "the notebook's hri-teleop kernel to be idle", poll_s=0.5)
        return self.driver

    def kernels(self) -> List[Dict[str, Any]]:
        with urllib.request.urlopen(self.url("api/kernels"), timeout=5) as answer:
            found: List[Dict[str, Any]] = json.load(answer)
        return found

    def stop(self) -> None:
        """The browser, then every kernel as JupyterLab's "Shut Down Kernel" does, then the server."""
        if self.driver is not None:
            self.driver.quit()
        try:
            for kernel in self.kernels():
                request = urllib.request.Request(self.url(f"api/kernels/{kernel['id']}"), method="DELETE")
                urllib.request.urlopen(request, timeout=15).close()
        except OSError:
            pass  # the server is gone already: its kernels notice and exit
        self.server.stop(timeout_s=15.0)
