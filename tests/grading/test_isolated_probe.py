"""Probes and sessions start isolated: no module in the working folder stands in for the grader's.

A probe runs with the student's folder as its working folder. Started as ``python -m``, that folder
came first on ``sys.path``, and a package ``hri_teleop/grading/run/probe.py`` there ran in place of
the grader's probe. :func:`isolated_module_argv` starts ``python -I``; what ``PYTHONPATH`` names
outside the folder (ROS under /opt/ros) still imports, after the toolkit.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from hri_teleop.grading.judge.harness import isolated_module_argv


def _shadowing_folder(folder: Path) -> None:
    for package in ("hri_teleop", "hri_teleop/grading", "hri_teleop/grading/run"):
        (folder / package).mkdir(parents=True, exist_ok=True)
        (folder / package / "__init__.py").write_text("")
    (folder / "hri_teleop" / "grading" / "run" / "probe.py").write_text("print('SHADOWED')\n")
    (folder / "rosparam.py").write_text("print('SHADOWED rosparam')\n")


def test_a_module_in_the_working_folder_does_not_replace_the_probe(tmp_path: Path) -> None:
    _shadowing_folder(tmp_path)
    plain = subprocess.run([sys.executable, "-m", "hri_teleop.grading.run.probe"], cwd=tmp_path,
                           capture_output=True, text=True, timeout=120)
    assert "SHADOWED" in plain.stdout  # what -m did: the reason for -I
    isolated = subprocess.run(isolated_module_argv("hri_teleop.grading.run.probe", []), cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
    assert "SHADOWED" not in isolated.stdout + isolated.stderr
    assert isolated.returncode == 2 and "What runs inside a student sandbox" in isolated.stderr


def test_pythonpath_outside_the_folder_is_appended_and_inside_it_is_dropped(tmp_path: Path) -> None:
    folder, ros = tmp_path / "student", tmp_path / "opt_ros"
    _shadowing_folder(folder)
    ros.mkdir()
    (ros / "fake_ros_module.py").write_text("VALUE = 'from /opt/ros'\n")
    (ros / "sitecustomize.py").write_text("print('SHADOWED sitecustomize')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(folder), str(ros)]))
    code = ("import sys, fake_ros_module, hri_teleop\n"
            "print(fake_ros_module.VALUE)\n"
            "print(hri_teleop.__file__)\n"
            "site = max(i for i, p in enumerate(sys.path) if p.endswith('-packages'))\n"
            f"print({str(folder)!r} in sys.path, sys.path.index({str(ros)!r}) > site)\n")
    (tmp_path / "probe_here.py").write_text(code)
    argv = isolated_module_argv("probe_here", [])
    env["PYTHONPATH"] += os.pathsep + str(tmp_path)
    proc = subprocess.run(argv, cwd=folder, env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert "SHADOWED" not in proc.stdout
    assert lines[0] == "from /opt/ros"
    assert not lines[1].startswith(str(folder))
    assert lines[2] == "False True"  # the folder's entry dropped; /opt/ros's after the Python's own packages


def _launch_parse(folder: Path, text: str) -> dict:
    import json

    (folder / "x.launch").write_text(text)
    proc = subprocess.run(isolated_module_argv("hri_teleop.grading.run.probe", ["launch-parse", "x.launch", "out.json"]),
                          cwd=folder, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads((folder / "out.json").read_text())


def test_a_rosparam_block_in_a_launch_file_runs_no_eval_in_the_probe(tmp_path: Path) -> None:
    owned = tmp_path / "OWNED"
    evil = _launch_parse(tmp_path, "<launch><rosparam>\n  ok: !radians pi/2\n"
                                   f"  evil: !radians __import__('os').system('touch {owned}')\n</rosparam></launch>\n")
    assert not owned.exists()
    assert not evil["ok"] and "invalid radian expression" in evil["error"]
    honest = _launch_parse(tmp_path, "<launch><rosparam>\n  ok: !radians pi/2\n  d: !degrees 90\n"
                                     "  r: rad(2*pi)\n</rosparam></launch>\n")
    assert honest["ok"], honest["error"]
    assert honest["params"] == {"/ok": 1.5707963267948966, "/d": 1.5707963267948966, "/r": 6.283185307179586}
