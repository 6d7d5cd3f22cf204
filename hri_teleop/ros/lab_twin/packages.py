"""The lab PC's installed ``franka_control`` and ``rosserial_python``, as the lab twin carries them.

A student's teleoperation.launch (the handout *Task 4: Teleoperation*, Ex. 12-13) starts
``rosserial_python/serial_node.py`` and includes franka_control's ``franka_control_cartesian_velocity.launch``;
Debian has neither. :func:`write_packages` writes both into the twin's folder at each start, their
executables running the twin's nodes with this twin's paths baked in (interpreter, checkout, counts
folder, board); ``LabTwin.env`` puts them last on ``ROS_PACKAGE_PATH``, as an installed ROS.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Dict, List, Mapping, Tuple
from xml.sax.saxutils import escape

from hri_teleop.core.paths import REPO
from hri_teleop.ros.lab_twin.counts import TWIN_BOARD_PORT_ENV, TWIN_DIR_ENV, TWIN_PACKAGE_ENV
from hri_teleop.ros.master import MasterError

__all__ = ["PACKAGES_DIR", "PACKAGES", "ROBOT_IP", "EXECUTABLES", "CARTESIAN_VELOCITY_LAUNCH", "write_packages",
           "found_elsewhere"]

#: The twin's installed packages go to ``<twin's work folder>/packages``.
PACKAGES_DIR = "packages"
#: The packages the lab PC has installed and Debian has not.
PACKAGES = ("franka_control", "rosserial_python")
#: The robot's address, the default of franka_control_cartesian_velocity.launch's ``robot_ip``.
ROBOT_IP = "172.16.0.2"
#: (package, executable) -> the twin's node module it runs.
EXECUTABLES: Dict[Tuple[str, str], str] = {
    ("franka_control", "franka_control_node"): "hri_teleop.ros.lab_twin.franka_control",
    ("franka_control", "franka_gripper_node"): "hri_teleop.ros.lab_twin.franka_gripper",
    ("franka_control", "joint_state_publisher"): "hri_teleop.ros.lab_twin.joint_state_publisher",
    ("rosserial_python", "serial_node.py"): "hri_teleop.ros.lab_twin.serial_node",
}
#: The launch file of franka_control that teleoperation.launch includes.
CARTESIAN_VELOCITY_LAUNCH = "franka_control_cartesian_velocity.launch"

_DESCRIPTIONS = {
    "franka_control": "The lab twin's franka_control: the robot's launch file and its nodes, which run the twin's "
                      "simulated arm and hand and count what reaches them (hri_teleop.ros.lab_twin).",
    "rosserial_python": "The lab twin's rosserial_python: serial_node.py speaks rosserial to the twin's board stand-in "
                        "on its pty, whatever ~port says (hri_teleop.ros.lab_twin).",
}

_LAUNCH = """<?xml version="1.0"?>
<!-- The lab twin's franka_control_cartesian_velocity.launch, written at each start of the twin
     (hri_teleop.ros.lab_twin.packages): the lab PC's file's arguments, the nodes under franka_ros's
     names. franka_control runs the twin's simulated arm behind the Cartesian velocity controller's
     command topic, franka_gripper its hand, joint_state_publisher merges both on /joint_states. -->
<launch>
  <arg name="robot_ip" default="{robot_ip}" doc="the robot's address (the twin's arm answers at any)"/>
  <arg name="load_gripper" default="true" doc="true: start franka_gripper (the Franka Hand) too"/>

  <node name="franka_control" pkg="franka_control" type="franka_control_node" output="screen" required="true">
    <param name="robot_ip" value="$(arg robot_ip)"/>
  </node>
  <node if="$(arg load_gripper)" name="franka_gripper" pkg="franka_control" type="franka_gripper_node"
        output="screen">
    <param name="robot_ip" value="$(arg robot_ip)"/>
  </node>
  <node name="joint_state_publisher" pkg="franka_control" type="joint_state_publisher" output="screen"/>
</launch>
"""


def _manifest(name: str) -> str:
    return ('<?xml version="1.0"?>\n<package format="2">\n'
            f"  <name>{name}</name>\n  <version>0.0.0</version>\n"
            f"  <description>{escape(_DESCRIPTIONS[name])}</description>\n"
            '  <maintainer email="lab@example.org">hri-lab</maintainer>\n  <license>BSD</license>\n</package>\n')


def _script(package: str, executable: str, module: str, python: str, env: Mapping[str, str]) -> str:
    settings = "".join(f"os.environ[{key!r}] = {value!r}\n" for key, value in env.items())
    return (f"#!{python}\n"
            f'"""The lab twin\'s {executable} of {package} (written by hri_teleop.ros.lab_twin.packages at the '
            f'twin\'s start): runs {module}."""\n'
            "import os\nimport runpy\nimport sys\n\n"
            f"{settings}"
            f"os.environ[{TWIN_PACKAGE_ENV!r}] = {package!r}\n"
            f"sys.path.insert(0, {str(REPO)!r})\n"
            f"runpy.run_module({module!r}, run_name='__main__', alter_sys=True)\n")


def write_packages(root: Path, folder: Path, board_port: str, python: str) -> Path:
    """Write the two packages under ``root`` (replacing what a former start left), their nodes
    reporting into the counts ``folder`` and serial_node opening ``board_port``; returns ``root``."""
    root = Path(root)
    if any(ch.isspace() for ch in python):
        raise MasterError(f"{python!r}: a '#!' line cannot hold a path with spaces; run the twin from a "
                         "Python whose path has none (e.g. the project's .venv)")
    for package in PACKAGES:
        shutil.rmtree(root / package, ignore_errors=True)
        (root / package).mkdir(parents=True)
        (root / package / "package.xml").write_text(_manifest(package), encoding="utf-8")
    (root / "franka_control" / "launch").mkdir()
    (root / "franka_control" / "launch" / CARTESIAN_VELOCITY_LAUNCH).write_text(
        _LAUNCH.format(robot_ip=ROBOT_IP), encoding="utf-8")
    for (package, executable), module in EXECUTABLES.items():
        env = {TWIN_DIR_ENV: str(Path(folder).resolve())}
        if package == "rosserial_python":
            env[TWIN_BOARD_PORT_ENV] = board_port
        path = root / package / "scripts" / executable
        path.parent.mkdir(exist_ok=True)
        path.write_text(_script(package, executable, module, python, env), encoding="utf-8")
        path.chmod(0o755)
    return root


def found_elsewhere(root: Path, ros_package_path: str) -> List[str]:
    """The packages rospack finds somewhere before ``root`` on ``ros_package_path`` (a machine with
    franka_ros or rosserial installed: those are the ones a launch then starts), as ``name at path``."""
    import rospkg  # noqa: PLC0415 - only when a person asks what runs

    paths = [entry for entry in ros_package_path.split(":") if entry and Path(entry).resolve() != Path(root).resolve()]
    finder = rospkg.RosPack(ros_paths=paths)
    found = []
    for package in PACKAGES:
        try:
            found.append(f"{package} at {finder.get_path(package)}")
        except rospkg.ResourceNotFound:
            continue
    return found
