"""``make demo``: the whole teleoperation lab, simulated and headless, on a private roscore.

Records the lab's topics while ``roslaunch hri_lab teleoperation.launch sim:=true`` runs the lab's
own nodes with lab_sim in place of the Franka, the egg and the Arduino and the default scenario in
place of the student, until the scenario quits. Then it prints what happened (grasped, lifted,
crushed, peak grip force in N, peak /force_mapped, rumble time, limit violations) and draws a PNG
timeline. With a real pad: ``roslaunch hri_lab teleoperation.launch sim:=true pad:=pygame``.
"""

from __future__ import annotations

import math
import re
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gripper import width_from_joint_positions_m
from hri_teleop.core.run_record import LabRecord, format_summary, summarize
from hri_teleop.core.yamlfile import read_yaml
from hri_teleop.plots.common import lab_timeline
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master import MasterError, PrivateMaster

#: What the demo records: the lab's topics (the twist as commanded, and as the simulated
#: arm moved, /lab_sim/ee_twist) and the simulation's view of the object and the judge.
TOPICS = (
    DEFAULT_TWIST_TOPIC,
    "/pub_force",
    "/force_mapped",
    "/gripper_width",
    "/teleoperation/rumble",
    "/franka_gripper/joint_states",
    "/lab_sim/ee_twist",
    "/lab_sim/grip_force",
    "/lab_sim/object",
    "/lab_sim/violations",
    "/lab_sim/arm_status",
    "/joy",
)
#: Recorded too, for a replay of the arm in 3D (``widgets.ArmView().replay``); the LabRecord leaves them out.
REPLAY_TOPICS = ("/joint_states",)

#: The demo must end by itself within a minute, whatever happens.
DEFAULT_TIMEOUT_S = 60.0



def robot_ran() -> str:
    """The robot lab_sim ran: the lab's sim.yaml read as lab_sim reads it (its robot:, else HRI_ROBOT's)."""
    from hri_teleop.sim.config import SimConfigError, default_sim_yaml, load_world_config  # noqa: PLC0415 - pinocchio

    path = default_sim_yaml()
    if path is None:
        return "unknown (no sim.yaml in hri_lab/config)"
    try:
        robot = load_world_config(path).robot
    except SimConfigError as exc:
        return f"unknown ({exc})"
    return f"{robot.name}: {robot.description}"

def _values(msg: Any) -> Dict[str, str]:
    return {kv.key: kv.value for kv in msg.values}


def _flag(values: Mapping[str, str], key: str) -> bool:
    return values.get(key, "false").strip().lower() == "true"


def record_from_bag(bag_path: Path) -> LabRecord:
    """The run recorded in ``bag_path`` as a :class:`LabRecord` (receive times of rosbag)."""
    topics = read_topics(bag_path, TOPICS)
    rec = LabRecord()
    rec.count = [(t, float(m.data)) for t, m in topics["/pub_force"]]
    rec.mapped = [(t, float(m.data)) for t, m in topics["/force_mapped"]]
    rec.width_target = [(t, float(m.data)) for t, m in topics["/gripper_width"]]
    rec.rumble = [(t, float(m.data)) for t, m in topics["/teleoperation/rumble"]]
    widths = ((t, width_from_joint_positions_m(m.position)) for t, m in topics["/franka_gripper/joint_states"])
    rec.width = [(t, w) for t, w in widths if w is not None]
    rec.speed = [(t, math.sqrt(m.twist.linear.x ** 2 + m.twist.linear.y ** 2 + m.twist.linear.z ** 2))
                 for t, m in topics["/lab_sim/ee_twist"]]
    rec.grip_force = [(t, float(m.data)) for t, m in topics["/lab_sim/grip_force"]]
    objects = topics["/lab_sim/object"]
    rec.object_height = [(t, float(_values(m).get("height_m", 0.0))) for t, m in objects]
    if objects:
        last = _values(objects[-1][1])
        rec.object_name = last.get("name", "")
        rec.grasped = _flag(last, "ever_grasped")
        rec.lifted = _flag(last, "lifted")
        rec.crushed = _flag(last, "crushed")
        rec.peak_grip_force_n = float(last.get("peak_grip_force_n", 0.0))
    violations = topics["/lab_sim/violations"]
    rec.violations = int(violations[-1][1].data) if violations else 0
    statuses = topics["/lab_sim/arm_status"]
    if statuses:
        last = _values(statuses[-1][1])
        rec.violation_counts = {k: int(v) for k, v in last.items()
                                if k.startswith("cartesian_") and v.isdigit() and int(v) > 0}
        explained = [_values(m).get("explanation", "") for _, m in statuses]
        rec.reflex_explanation = next((e.split("\n") for e in reversed(explained) if e), [])
    return rec


def record_teleop_launch(master: PrivateMaster, bag_path: Path, launch_args: Mapping[str, object],
                         timeout_s: float = DEFAULT_TIMEOUT_S,
                         progress: Callable[[str], None] = lambda _m: None,
                         output: Optional[List[str]] = None) -> LabRecord:
    """Record a ``teleoperation.launch`` run on ``master`` until it ends (or ``timeout_s``).

    The demo and the integration tests share this, so both judge the same run. ``output``: gets the
    launch's output (its last 3000 characters), for a run that recorded nothing to show why.
    """
    recorder = master.record(bag_path, TOPICS + REPLAY_TOPICS)
    started = time.monotonic()
    launch = master.roslaunch("hri_lab", "teleoperation.launch", launch_args)
    ended_by = "timeout"
    try:
        next_note = started + 5.0
        while time.monotonic() - started < timeout_s:
            if not launch.running:
                ended_by = "quit" if launch.stop() == 0 else "launch failed"
                break
            if time.monotonic() >= next_note:
                progress(f"{time.monotonic() - started:4.0f} s  running ...")
                next_note += 5.0
            time.sleep(0.2)
    finally:
        code = launch.stop()
        recorder.stop()
        if output is not None:
            output.append(launch.output()[-3000:])
    if ended_by == "launch failed" or (ended_by == "quit" and code not in (0, None)):
        raise MasterError(f"teleoperation.launch failed (exit {code}):\n{launch.output()[-3000:]}")
    rec = record_from_bag(bag_path)
    rec.ended_by = ended_by
    rec.wall_s = time.monotonic() - started
    return rec


class ScenarioError(HriTeleopError, ValueError):
    """A scenario's ``expect:`` is unusable (one line naming the file and the fix)."""


def expected_reflex(scenario: Optional[Path]) -> Optional[str]:
    """The libfranka error a scenario's ``expect: {reflex: ...}`` says the run ends in (None: no reflex)."""
    if scenario is None:
        return None
    data = read_yaml(scenario, ScenarioError, what="scenario file")
    expect = data.get("expect") if isinstance(data, dict) else None
    if expect is None:
        return None
    if not isinstance(expect, dict) or set(expect) != {"reflex"} or not isinstance(expect["reflex"], str):
        raise ScenarioError(f"{scenario}: expect must be {{reflex: <libfranka error name>}}, got {expect!r}; "
                            "e.g. expect: {reflex: cartesian_motion_generator_joint_position_limits_violation}")
    return expect["reflex"]


def node_errors(output: str, limit: int = 8) -> List[str]:
    """The lines of a launch's ``output`` that say why a node stopped: its errors and what died (at most
    ``limit``, the last ones), terminal colours removed."""
    clean = re.sub(r"\x1b\[[0-9;]*m", "", output)
    marks = ("[ERROR]", "[FATAL]", "Error:", "error:", "process has died", "process has finished cleanly")
    lines = [line.strip() for line in clean.splitlines() if any(mark in line for mark in marks)]
    return [line if len(line) <= 300 else line[:297] + "..." for line in lines[-limit:]]


def _progress(message: str) -> None:
    print(f"[demo] {message}", flush=True)


def run(scenario: Optional[Path], out_dir: Path, timeout_s: float, extra: Mapping[str, str]) -> int:
    expected = expected_reflex(scenario)
    out_dir.mkdir(parents=True, exist_ok=True)
    bag_path = out_dir / "teleop_demo.bag"
    if bag_path.exists():
        bag_path.unlink()  # the demo's own output from an earlier run
    args: Dict[str, object] = {"sim": "true"}
    if scenario is not None:
        args["scenario"] = str(Path(scenario).resolve())
    args.update(extra)
    started = time.monotonic()
    with PrivateMaster() as master:
        _progress(f"roscore up on port {master.port}; roslaunch hri_lab teleoperation.launch "
                  + " ".join(f"{k}:={v}" for k, v in args.items()))
        said: List[str] = []
        rec = record_teleop_launch(master, bag_path, args, timeout_s, _progress, said)
    _progress(f"stopped roscore and nodes ({time.monotonic() - started:.1f} s in all)")
    if not rec.count or not rec.rumble:
        causes = node_errors("".join(said))
        print(f"demo: nothing recorded ({len(rec.count)} /pub_force, {len(rec.rumble)} rumble messages)"
              + (":\n" + "\n".join(f"  {line}" for line in causes) if causes else "; the launch said nothing "
                 "about why (run roslaunch hri_lab teleoperation.launch sim:=true to see its output)"),
              file=sys.stderr)
        return 1
    summary = summarize(rec)
    name = Path(scenario).stem if scenario is not None else "default"
    png = lab_timeline(rec, out_dir / "teleop_demo.png", f"make demo: the simulated lab, {name} scenario")
    lines: List[str] = ["", "Teleoperation lab, simulated (teleoperation.launch sim:=true):"]
    lines.append(f"  robot             {robot_ran()}")
    lines += ["  " + line for line in format_summary(summary)]
    lines += [f"  bag               {bag_path}", f"  timeline plot     {png}"]
    if expected is not None:
        lines.append(f"  expected reflex   {expected}: {'yes' if expected in summary.violation_counts else 'NO'}")
    print("\n".join(lines), flush=True)
    as_expected = summary.violations == 0 if expected is None else expected in summary.violation_counts
    return 0 if rec.ended_by == "quit" and as_expected else 1
