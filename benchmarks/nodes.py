"""The nodes under test, started for real: mapping_node and teleoperation on a private master.

Both latency and command timing measure these two nodes exactly as the lab runs them
(``roslaunch`` of the package's scripts with its teleop.yaml), with the virtual pad in
place of the gamepad: a pad script with nothing to do, so the node polls a connected,
idle pad every tick, and ``~rumble_log`` time-stamps every request the pad receives.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Sequence
from xml.sax.saxutils import quoteattr

from benchmarks.report import BenchError
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, lab_max_sensor_force
from hri_teleop.ros.master import ManagedProcess, MasterError, PrivateMaster, lab_shell_env

#: The calibration the probe's counts are mapped with (the lab's typical /max_sensor_force).
MAX_SENSOR_FORCE = lab_max_sensor_force()
#: An idle operator: one step far in the future, so the script never ends and the pad stays connected.
IDLE_SCRIPT = "- {t: 86400.0, release: south}\n"


def _launch_xml(pad_script: Path, rumble_log: Path) -> str:
    return f"""<launch>
  <param name="max_sensor_force" value="{MAX_SENSOR_FORCE}"/>
  <node name="mapping_node" pkg="hri_lab" type="mapping_node.py" required="true"/>
  <node name="teleoperation" pkg="hri_lab" type="teleoperation.py" required="true">
    <param name="pad" value="virtual"/>
    <param name="pad_script" value={quoteattr(str(pad_script))}/>
    <param name="script_wait_s" value="0.0"/>
    <param name="rumble_log" value={quoteattr(str(rumble_log))}/>
  </node>
</launch>
"""


class MeasuredNodes:
    """A private master with mapping_node and teleoperation launched on it; a context manager."""

    def __init__(self, work_dir: Path) -> None:
        self.work_dir = Path(work_dir)
        self.work_dir.mkdir(parents=True, exist_ok=True)
        self.rumble_log = self.work_dir / "rumble.log"
        self.master = PrivateMaster(base_env=lab_shell_env(), work_dir=self.work_dir / "ros")
        self.launch: ManagedProcess

    def __enter__(self) -> "MeasuredNodes":
        script = self.work_dir / "idle_pad.yaml"
        script.write_text(IDLE_SCRIPT)
        launch_file = self.work_dir / "measured_nodes.launch"
        launch_file.write_text(_launch_xml(script, self.rumble_log))
        self.rumble_log.unlink(missing_ok=True)
        try:
            self.master.start()
            self.launch = self.master.run(["roslaunch", "--wait", str(launch_file)], "measured_nodes")
            self.master.wait_for(lambda: bool(self.master.publishers(DEFAULT_TWIST_TOPIC)) and
                                 bool(self.master.subscribers("/pub_force")) and
                                 bool(self.master.subscribers("/force_mapped")) or not self.launch.running,
                                 30.0, "mapping_node and teleoperation to come up")
        except MasterError as exc:
            self.master.stop()
            raise BenchError(f"could not start the measured nodes: {exc}") from None
        if not self.launch.running:
            output = self.launch.output().strip().splitlines()[-5:]
            self.master.stop()
            raise BenchError("roslaunch of mapping_node and teleoperation ended: " + " | ".join(output))
        return self

    def __exit__(self, *exc: object) -> None:
        self.master.stop()

    def probe(self, args: Sequence[str], name: str, timeout_s: float) -> Dict[str, Any]:
        """Run ``python -m benchmarks.probe ARGS --out FILE`` on this master; its JSON result."""
        out = self.work_dir / f"{name}.json"
        out.unlink(missing_ok=True)
        proc = self.master.run([sys.executable, "-m", "benchmarks.probe", *args, "--out", str(out)], name)
        code = proc.wait(timeout_s)
        if code is None:
            proc.stop()
            raise BenchError(f"the {name} probe did not finish within {timeout_s:.0f} s; its log: {proc.log_path}")
        if code != 0 or not out.exists():
            tail: List[str] = proc.output().strip().splitlines()[-3:]
            raise BenchError(f"the {name} probe failed (exit {code}): {' | '.join(tail)}")
        if not self.launch.running:
            raise BenchError(f"the measured nodes stopped during the {name} probe; log: {self.launch.log_path}")
        return json.loads(out.read_text())
