"""tools/env.sh's ROS_PACKAGE_PATH: the project's hri_lab in this checkout; in the student bundle, the
hri_lab of the assignment folder it is sourced in (preparation/ or lab/), else the toolkit's.

Only bash and the file itself: the bundle's layout is built here from empty packages.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _sourced(env_sh: Path, cwd: Path, *, before: str = "", environ: dict = None) -> list:
    """ROS_PACKAGE_PATH's entries and HRI_STUDENT_PACKAGE after ``. env.sh`` in ``cwd``."""
    env = {k: v for k, v in (environ or os.environ).items() if not k.startswith(("ROS_", "HRI_"))}
    script = f'{before}\n. "{env_sh}" && printf "%s\\n%s\\n" "$ROS_PACKAGE_PATH" "${{HRI_STUDENT_PACKAGE-unset}}"'
    done = subprocess.run(["bash", "-c", script], cwd=cwd, env=env, capture_output=True, text=True, timeout=60,
                          check=True)
    path, student = done.stdout.splitlines()[-2:]
    system = ("/usr/share", str(env_sh.parents[1] / ".venv" / "share" / "hri-ros-msgs"))  # Debian's, make setup's
    return [e for e in path.split(":") if e not in system] + [student]


def _bundle(tmp_path: Path) -> Path:
    top = tmp_path / "task4"
    for package in ("toolkit/hri_lab", "preparation/hri_lab", "lab/hri_lab"):
        (top / package).mkdir(parents=True)
        (top / package / "package.xml").write_text("<package><name>hri_lab</name></package>\n")
    (top / "toolkit" / "tools").mkdir()
    shutil.copy(REPO / "tools" / "env.sh", top / "toolkit" / "tools" / "env.sh")
    return top


def test_in_the_checkout_the_projects_hri_lab_comes_first_wherever_it_is_sourced():
    env_sh = REPO / "tools" / "env.sh"
    assert _sourced(env_sh, REPO) == [str(REPO / "hri_lab"), "unset"]
    # notebooks/source/preparation holds an hri_lab (the link to the answer key): not the student bundle
    assert _sourced(env_sh, REPO / "notebooks" / "source" / "preparation") == [str(REPO / "hri_lab"), "unset"]


def test_in_an_assignment_folder_of_the_bundle_the_students_hri_lab_comes_first(tmp_path):
    top = _bundle(tmp_path)
    env_sh = top / "toolkit" / "tools" / "env.sh"
    prep, lab, toolkit = (str((top / f / "hri_lab").resolve()) for f in ("preparation", "lab", "toolkit"))
    assert _sourced(env_sh, top / "preparation") == [prep, toolkit, prep]
    assert _sourced(env_sh, top) == [toolkit, "unset"]


def test_sourced_again_in_another_folder_it_swaps_the_students_package(tmp_path):
    top = _bundle(tmp_path)
    env_sh = top / "toolkit" / "tools" / "env.sh"
    prep, lab, toolkit = (str((top / f / "hri_lab").resolve()) for f in ("preparation", "lab", "toolkit"))
    first = f'cd ../preparation && . "{env_sh}" && cd ../lab'
    assert _sourced(env_sh, top / "lab", before=first) == [lab, toolkit, lab]
    assert _sourced(env_sh, top / "lab", before=first + f' && . "{env_sh}"') == [lab, toolkit, lab]
    # from the top folder (the bundle's Makefile: make doctor, make check) the toolkit's comes back first
    assert _sourced(env_sh, top, before=f'cd preparation && . "{env_sh}" && cd ..') == [toolkit, "unset"]


def test_the_notebooks_kernel_keeps_the_toolkits_hri_lab_first_in_an_assignment_folder(tmp_path):
    top = _bundle(tmp_path)
    env_sh = top / "toolkit" / "tools" / "env.sh"
    toolkit = str((top / "toolkit" / "hri_lab").resolve())
    assert _sourced(env_sh, top / "lab", before="HRI_ENV_TOOLKIT_FIRST=1") == [toolkit, "unset"]
    # also when Jupyter was started from a terminal sourced in the assignment
    inherited = f'cd ../preparation && . "{env_sh}" && cd ../lab && HRI_ENV_TOOLKIT_FIRST=1'
    assert _sourced(env_sh, top / "lab", before=inherited) == [toolkit, "unset"]
    assert "HRI_ENV_TOOLKIT_FIRST=1" in (REPO / "tools" / "kernel.sh").read_text()


@pytest.mark.skipif(Path("/opt/ros/noetic/setup.sh").exists(), reason="Noetic's std_msgs has its package.xml")
def test_make_setups_manifests_of_debians_message_definitions_come_after_usr_share(tmp_path):
    top = _bundle(tmp_path)
    manifests = top / "toolkit" / ".venv" / "share" / "hri-ros-msgs"
    manifests.mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "HRI_"))}
    script = f'. "{top / "toolkit" / "tools" / "env.sh"}" && . "{top / "toolkit" / "tools" / "env.sh"}" && echo "$ROS_PACKAGE_PATH"'
    path = subprocess.run(["bash", "-c", script], cwd=top, env=env, capture_output=True, text=True, timeout=60,
                          check=True).stdout.split()[-1].split(":")
    assert path[-2:] == ["/usr/share", str(manifests)]
    assert path.count(str(manifests)) == 1
