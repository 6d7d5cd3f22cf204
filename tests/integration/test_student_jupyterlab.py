"""The students' JupyterLab (the bundle's `make lab`: hri_teleop.apps.lab --notebooks): nbgrader's student
side only -- no formgrader, course list, nbgrader menu or "Create Assignment" panel -- and nbgrader finds a
configuration. The server is asked over HTTP; no browser."""

from __future__ import annotations

import json
import os
import re
import sys
import urllib.error
import urllib.request
from pathlib import Path

from jupyterlab_session import JUPYTER_HOME, server_up, wait

from hri_teleop.apps.lab import INSTRUCTOR_LABEXTENSIONS
from hri_teleop.ros.master import ManagedProcess, free_port

REPO = Path(__file__).resolve().parents[2]


def _get(url: str) -> tuple:
    try:
        with urllib.request.urlopen(url, timeout=10) as answer:
            return answer.status, answer.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as exc:
        return exc.code, ""


def test_the_students_jupyterlab_shows_only_nbgraders_student_side(tmp_path):
    folder = tmp_path / "task4"
    (folder / "preparation").mkdir(parents=True)
    port, token = free_port(), "hri-" + os.urandom(8).hex()
    env = {k: v for k, v in os.environ.items() if not k.startswith("JUPYTER")}
    env.update({name: str(tmp_path / sub) for name, sub in JUPYTER_HOME})
    server = ManagedProcess([sys.executable, "-m", "hri_teleop.apps.lab", "--notebooks", str(folder), "--no-browser",
                             f"--port={port}", "--ServerApp.ip=127.0.0.1", "--ServerApp.port_retries=0",
                             f"--IdentityProvider.token={token}",
                             "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate"],
                            env, tmp_path / "lab.log", cwd=folder)
    try:
        url = f"http://127.0.0.1:{port}/{{}}?token={token}"
        wait(lambda: not server.running or server_up(url.format("api/status")), 90, "JupyterLab to answer")
        assert server.running, server.output()[-2000:]
        status, page = _get(url.format("lab"))
        assert status == 200
        config = json.loads(re.search(r'<script id="jupyter-config-data" type="application/json">(.*?)</script>',
                                      page, re.S).group(1))
        disabled = config["disabledExtensions"]
        assert all(name in disabled for name in INSTRUCTOR_LABEXTENSIONS), disabled
        assert not any("validate-assignment" in name or "assignment-list" in name for name in disabled), disabled
        assert _get(url.format("formgrader"))[0] == 404  # the server extension is off too
        assert "No nbgrader_config.py" not in server.output(), server.output()[-2000:]
    finally:
        server.stop()
