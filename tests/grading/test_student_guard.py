"""The reference guard at run time (hri_teleop.grading.run.student_guard): each way around it, refused.

A student's node runs in a process with the guard's policy in its environment and its sitecustomize on
PYTHONPATH, as the grader starts it. Each attack is a script of the student's package; the honest uses
(the student API, rospy, a child Python, the lab's own node the grader placed) still run.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import hri_teleop
from hri_teleop.grading.run.student_guard import (
    GUARD_ENV,
    REFERENCE_RULES,
    SITE_DIR,
    guard_policy,
    refused_spawn,
)

TOOLKIT = os.path.dirname(hri_teleop.__file__)
MAPPING = os.path.join(TOOLKIT, "core", "mapping.py")


@pytest.fixture
def package(tmp_path):
    pkg = tmp_path / "ws" / "hri_lab"
    (pkg / "scripts").mkdir(parents=True)
    placed = pkg / "scripts" / "teleoperation.py"
    placed.write_text("#!/usr/bin/env python3\nimport hri_teleop.core.teleop as t\nprint('the lab ran', t.GRIPPER_MAX_WIDTH_M)\n")
    return pkg


def _env(pkg: Path) -> dict:
    policy = guard_policy(str(pkg), [str(pkg / "scripts" / "teleoperation.py")], TOOLKIT)
    return dict(os.environ, **{GUARD_ENV: policy, "PYTHONPATH": os.pathsep.join(
        [SITE_DIR, os.environ.get("PYTHONPATH", "")])})


def _run(pkg: Path, code: str, name: str = "student_node.py") -> subprocess.CompletedProcess:
    script = pkg / "scripts" / name
    script.write_text(code)
    return subprocess.run([sys.executable, str(script)], env=_env(pkg), capture_output=True, text=True,
                          cwd=str(pkg), timeout=60, stdin=subprocess.DEVNULL)


ATTACKS = {
    "importlib_computed_name": "import importlib\nm = importlib.import_module('hri_teleop.core.' + 'mapping')\n",
    "import_statement": "from hri_teleop.core.mapping import map_force\n",
    "teleop_rule": "import hri_teleop.core.teleop\n",
    "grader_cases": "import hri_teleop.grading.cases.inputs\n",
    "exec_of_the_rule_file": f"exec(open({MAPPING!r}).read())\n",
    "spec_from_file": ("import importlib.util\n"
                       f"s = importlib.util.spec_from_file_location('x', {MAPPING!r})\n"
                       "m = importlib.util.module_from_spec(s)\ns.loader.exec_module(m)\n"),
    "finder_removed": "import sys, importlib\nsys.meta_path.pop(0)\nimportlib.import_module('hri_teleop.core.mapping')\n",
    "read_the_placed_node": "import os\nprint(open(os.path.join(os.path.dirname(__file__), 'teleoperation.py')).read())\n",
    "hard_link_to_the_placed_node": "import os\nos.link(os.path.join(os.path.dirname(__file__), 'teleoperation.py'), 'x.py')\n",
    "rename_the_placed_node": "import os\nd = os.path.dirname(__file__)\nos.rename(os.path.join(d, 'teleoperation.py'), 'y.py')\n",
    "isolated_child": "import subprocess, sys\nsubprocess.run([sys.executable, '-I', '-c', 'import hri_teleop.core.mapping'])\n",
    "combined_flags_child": "import subprocess, sys\nsubprocess.run([sys.executable, '-sE', '-c', 'print(1)'])\n",
    "shell": "import subprocess\nsubprocess.run('cat /etc/hostname', shell=True)\n",
    "os_system": "import os\nos.system('true')\n",
    "child_without_the_environment": ("import os, subprocess, sys\ne = dict(os.environ)\ne.pop('PYTHONPATH')\n"
                                      "subprocess.run([sys.executable, '-c', 'print(1)'], env=e)\n"),
    "ctypes_libc": "import ctypes\nctypes.CDLL(None)\n",
    "ctypes_pythonapi": "import ctypes\nctypes.pythonapi.Py_IsInitialized()\n",
    "compile_posing_as_the_toolkit": f"exec(compile('x = 1', {MAPPING!r}, 'exec'))\n",
    "compile_through_the_stdlib": f"import codeop\nexec(codeop.compile_command('x = 1', {MAPPING!r}, 'exec'))\n",
    "a_ros_tool_started_by_the_student": "import subprocess\nsubprocess.run(['/usr/bin/rosversion', '-d'])\n",
    "proc_mem": "open('/proc/self/mem', 'rb')\n",
    "gc_digging": "import gc\ngc.get_objects()\n",
}


@pytest.mark.parametrize("name", sorted(ATTACKS))
def test_each_way_to_the_reference_rule_is_refused_with_a_reason(package, name):
    proc = _run(package, ATTACKS[name] + "print('GOT THROUGH')\n", f"attack_{name}.py")
    assert proc.returncode != 0 and "GOT THROUGH" not in proc.stdout, proc.stdout + proc.stderr
    last = proc.stderr.strip().splitlines()[-1]
    assert "the grader refuses" in last, proc.stderr[-2000:]
    assert "the lab ran" not in proc.stdout
    assert (package / "scripts" / "teleoperation.py").is_file()


@pytest.mark.parametrize("code", [
    "import hri_teleop.student as s\nprint('OK', s.normalize_analog_input(0.5, 0.1))\n",
    "import rospy\nfrom std_msgs.msg import Float32, Int16\nprint('OK', Float32(0.5).data)\n",
    "import numpy as np\nprint('OK', float(np.clip(2.0, 0.0, 1.0)))\n",
    "import subprocess, sys\nprint('OK', subprocess.check_output([sys.executable, '-c', 'import hri_teleop.student; print(2)']))\n",
    "import json, yaml\nprint('OK', yaml.safe_load('a: 1'), json.dumps(compile('1 + 1', '<student>', 'eval').co_filename))\n",
])
def test_honest_nodes_run_under_the_guard(package, code):
    proc = _run(package, code)
    assert proc.returncode == 0 and "OK" in proc.stdout, proc.stderr[-2000:]


def test_the_lab_s_own_node_placed_by_the_grader_runs_unguarded_but_not_once_changed(package):
    env = _env(package)
    placed = package / "scripts" / "teleoperation.py"
    proc = subprocess.run([sys.executable, str(placed)], env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and "the lab ran 0.08" in proc.stdout, proc.stderr[-2000:]
    placed.write_text(placed.read_text() + "# changed\n")  # no longer the file the grader placed
    proc = subprocess.run([sys.executable, str(placed)], env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "the lab ran" not in proc.stdout, proc.stdout + proc.stderr  # its file: refused


def test_a_student_node_started_by_the_guarded_roslaunch_way_is_allowed(package):
    """roslaunch starts a node as its script, with a plain python3 first line and the inherited environment."""
    node = package / "scripts" / "mine.py"
    node.write_text("#!/usr/bin/env python3\nprint('node')\n")
    node.chmod(0o755)
    env = _env(package)
    policy = env[GUARD_ENV]
    assert refused_spawn(str(node), [str(node), "__name:=x"], env, sys.executable, SITE_DIR, policy) == ""
    for first_line in ("#!/usr/bin/python3 -I", "#!/bin/sh", "#!/usr/bin/env -S python3 -I"):
        node.write_text(first_line + "\nprint('node')\n")
        assert refused_spawn(str(node), [str(node)], env, sys.executable, SITE_DIR, policy), first_line
    assert refused_spawn("/usr/bin/cat", ["cat", str(node)], env, sys.executable, SITE_DIR, policy)  # launch-prefix
    assert refused_spawn(sys.executable, [sys.executable, "-u", str(node)], env, sys.executable, SITE_DIR, policy) == ""
    assert refused_spawn(sys.executable, [sys.executable, "-E", str(node)], env, sys.executable, SITE_DIR, policy)


def test_the_refused_modules_are_the_rules_and_the_grader_but_not_what_a_node_needs():
    for rule in ("hri_teleop.core.mapping", "hri_teleop.core.teleop", "hri_teleop.core.paramfile",
                 "hri_teleop.grading.cases", "hri_teleop.grading.judge"):
        assert rule in REFERENCE_RULES
    for needed in ("hri_teleop.student", "hri_teleop.core.gripper", "hri_teleop.grading.run"):
        assert not any(needed == r or needed.startswith(r + ".") for r in REFERENCE_RULES), needed


def test_what_a_student_node_imports_loads_no_reference_rule():
    """The student API and what the grader runs in the student's processes stay clear of the rules, so
    nothing of them is in sys.modules for a student's code to pick up."""
    code = ("import sys, hri_teleop.student, hri_teleop.grading.run.standins, hri_teleop.grading.run.clock_sleep\n"
            "import hri_teleop.hardware.sim.rosserial_board\n"
            f"rules = {REFERENCE_RULES!r}\n"
            "print([m for m in sys.modules if any(m == r or m.startswith(r + '.') for r in rules)])\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_roslaunch_may_start_ros_s_own_tools_but_the_student_may_not(package, tmp_path):
    """roslaunch runs ``rosversion -d`` where ROS_DISTRO is not set; code outside the student's package asks."""
    if not os.path.exists("/usr/bin/rosversion"):
        pytest.skip("no /usr/bin/rosversion here")
    helper = tmp_path / "launcher_like.py"  # outside the student's package, as roslaunch's own code is
    helper.write_text("import subprocess\n\ndef distro():\n    return subprocess.run(['/usr/bin/rosversion', '-d'], "
                      "capture_output=True, text=True).returncode\n")
    proc = _run(package, f"import importlib.util\nspec = importlib.util.spec_from_file_location('h', {str(helper)!r})\n"
                         "h = importlib.util.module_from_spec(spec)\nspec.loader.exec_module(h)\nprint('OK', h.distro())\n")
    assert proc.returncode == 0 and "OK 0" in proc.stdout, proc.stderr[-2000:]
    env = _env(package)
    env.pop("PYTHONPATH")  # not even roslaunch starts it without the guard's environment
    assert refused_spawn("/usr/bin/rosversion", ["rosversion", "-d"], env, sys.executable, SITE_DIR, env[GUARD_ENV],
                         ros_tool=True)


def test_the_guard_and_the_grader_s_clock_start_together_and_chain_to_the_next_sitecustomize(package, tmp_path):
    """Both folders' sitecustomize run the next one on the path: each must skip the other, or they run each
    other for ever (roslaunch under the grader's clock hung at its start in Gradescope's layout)."""
    from hri_teleop.grading.run.clock_sleep import SITE_DIR as CLOCK_SITE

    last = tmp_path / "last"
    last.mkdir()
    (last / "sitecustomize.py").write_text("import builtins\nbuiltins.LAST_SITE_RAN = True\n")
    env = _env(package)
    env["PYTHONPATH"] = os.pathsep.join([SITE_DIR, str(CLOCK_SITE), str(last), os.environ.get("PYTHONPATH", "")])
    script = package / "scripts" / "both.py"
    script.write_text("import builtins, sys\nprint('OK', getattr(builtins, 'LAST_SITE_RAN', False), "
                      "any(type(f).__name__ == '_Finder' for f in sys.meta_path))\n")
    proc = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and "OK True True" in proc.stdout, proc.stderr[-2000:]


def test_the_system_python_without_the_toolkit_on_its_path_is_guarded_too(package):
    """roslaunch and a node whose first line is #!/usr/bin/python3 run the system's Python: the guard is
    loaded from its file there (it once failed to import, and Python went on without it)."""
    if not os.path.exists("/usr/bin/python3"):
        pytest.skip("no system python3")
    script = package / "scripts" / "system_python.py"
    script.write_text(ATTACKS["exec_of_the_rule_file"] + "print('GOT THROUGH')\n")
    env = _env(package)
    env["PYTHONPATH"] = SITE_DIR  # nothing of the toolkit
    proc = subprocess.run(["/usr/bin/python3", str(script)], env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "GOT THROUGH" not in proc.stdout, proc.stdout + proc.stderr
    assert "the grader refuses to open" in proc.stderr, proc.stderr[-2000:]


def test_a_process_the_guard_cannot_start_in_ends_at_once_with_the_reason(package):
    env = _env(package)
    env[GUARD_ENV] = "{not json"
    proc = subprocess.run([sys.executable, "-c", "print('RAN')"], env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 3 and "RAN" not in proc.stdout, proc.stdout + proc.stderr
    assert "the reference guard could not start" in proc.stderr and "no student code" in proc.stderr


def test_roslaunch_may_start_the_lab_s_node_it_cannot_read(package, tmp_path):
    """The lab's node the grader placed is secret to student code, guard included, yet roslaunch starts it."""
    helper = tmp_path / "launcher_like.py"
    placed = package / "scripts" / "teleoperation.py"
    placed.chmod(0o755)
    helper.write_text(f"import subprocess\n\ndef start():\n    return subprocess.run([{str(placed)!r}], "
                      "capture_output=True, text=True).stdout\n")
    proc = _run(package, f"import importlib.util\nspec = importlib.util.spec_from_file_location('h', {str(helper)!r})\n"
                         "h = importlib.util.module_from_spec(spec)\nspec.loader.exec_module(h)\nprint('OK', h.start())\n")
    assert proc.returncode == 0 and "OK the lab ran" in proc.stdout, proc.stderr[-2000:]
