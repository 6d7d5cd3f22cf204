"""What reached the lab twin: its nodes' counts files read into one typed record.

:class:`TwinReport` is what a test or a rehearsal asks: twists the robot received, gripper goals,
error recoveries, the board's counts on ``/pub_force`` and who publishes it, and where each lab node
comes from: the twin's own ``replaced`` (another node took its name) or ``stopped``, ``launched``
from the twin's installed packages (never called replaced), or ``missing`` from the master.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.ros.lab_twin.counts import counts_path, read_json

__all__ = ["NODES", "BOARD", "TwinReport", "read_report"]

#: The twin's ROS nodes: the lab's names.
NODES = ("/franka_control", "/franka_gripper", "/joint_state_publisher", "/serial_node")
#: The board's counts file (not a node).
BOARD = "board"
PUB_FORCE = "/pub_force"


def _int(data: Mapping[str, Any], key: str) -> int:
    value = data.get(key, 0)
    return int(value) if isinstance(value, (int, float)) else 0


def _table(data: Mapping[str, Any], key: str) -> Dict[str, int]:
    value = data.get(key, {})
    return {str(k): int(v) for k, v in value.items()} if isinstance(value, dict) else {}


def _vector(data: Mapping[str, Any], key: str) -> Optional[Tuple[float, ...]]:
    value = data.get(key)
    return tuple(float(v) for v in value) if isinstance(value, list) else None


@dataclass(frozen=True)
class TwinReport:
    """The twin's counts at one moment (each node's raw counts in ``nodes``, the board's in ``board``).

    Where the lab's nodes come from: ``replaced`` names a node the twin itself started whose name
    another node took (the master's ``lookupNode`` no longer gives the twin process's URI),
    ``stopped`` one whose process is gone -- only the twin's own nodes are ever either. ``launched``
    names a node running from the twin's installed packages (a launch or ``rosrun``), counting into
    the same files: on a bare twin a student's launch makes these; over a running twin's node it is
    both replaced and launched. ``missing``: a lab node no running process registered on the master.
    """

    twists: int = 0
    nonzero_twists: int = 0
    ignored_twists: int = 0
    error_recoveries: int = 0
    activated: Optional[bool] = None
    arm_position_m: Optional[Tuple[float, ...]] = None
    arm_start_position_m: Optional[Tuple[float, ...]] = None
    gripper_goals: Dict[str, int] = field(default_factory=dict)
    gripper_width_m: Optional[float] = None
    joint_states_published: int = 0
    pub_force_published: int = 0
    board_period_ms: int = 0
    board_samples_sent: int = 0
    board_last_count: int = 0
    board_presses: int = 0
    board_port: str = ""
    pub_force_publishers: List[str] = field(default_factory=list)
    pids: Dict[str, int] = field(default_factory=dict)
    replaced: List[str] = field(default_factory=list)
    stopped: List[str] = field(default_factory=list)
    launched: List[str] = field(default_factory=list)
    missing: List[str] = field(default_factory=list)
    nodes: Dict[str, Dict[str, Any]] = field(default_factory=dict)
    board: Dict[str, Any] = field(default_factory=dict)

    @property
    def arm_moved_m(self) -> float:
        """How far the end effector is from where it started (m; 0 before the first position)."""
        if self.arm_position_m is None or self.arm_start_position_m is None:
            return 0.0
        return float(sum((a - b) ** 2 for a, b in zip(self.arm_position_m, self.arm_start_position_m)) ** 0.5)

    @property
    def board_rate_hz(self) -> Optional[float]:
        """Counts per second by the board's own send times (None before two counts)."""
        first, last = self.board.get("first_sample_s"), self.board.get("last_sample_s")
        sent = self.board_samples_sent
        if not isinstance(first, (int, float)) or not isinstance(last, (int, float)) or sent < 2 or last <= first:
            return None
        return (sent - 1) / (last - first)

    def lines(self) -> List[str]:
        """The report for a person, a few lines."""
        goals = ", ".join(f"{action} {n}" for action, n in sorted(self.gripper_goals.items())) or "none"
        moved = f"{self.arm_moved_m * 100:.1f} cm from its start"
        return [
            f"robot    {self.twists} twists received, {self.nonzero_twists} non-zero"
            f"{'' if self.activated is not False else ' (user stop engaged: the arm stays)'}; arm {moved}; "
            f"{self.error_recoveries} error recoveries",
            f"gripper  goals: {goals}; width {self.gripper_width_m or 0.0:.4f} m",
            f"board    {self.pub_force_published} counts on /pub_force by {', '.join(self.pub_force_publishers) or 'nobody'}"
            f" (every {self.board_period_ms} ms, last {self.board_last_count}, {self.board_presses} presses)",
            f"nodes    replaced: {', '.join(self.replaced) or 'none'}; stopped: {', '.join(self.stopped) or 'none'}; "
            f"from the installed packages (a launch): {', '.join(self.launched) or 'none'}; "
            f"not on the master: {', '.join(self.missing) or 'none'}",
        ]


def read_report(folder: Path, pub_force_publishers: Sequence[str], replaced: Sequence[str],
                stopped: Sequence[str], registered: Sequence[str] = NODES) -> TwinReport:
    """The counts files in ``folder`` with what the caller found on the master (the lab nodes
    ``registered`` there) and of the twin's own processes."""
    nodes = {name: read_json(counts_path(folder, name)) for name in NODES}
    launched = [name for name in NODES if name in registered and nodes[name].get("package")
                and not nodes[name].get("stopped")]
    board = read_json(counts_path(folder, BOARD))
    control, gripper = nodes["/franka_control"], nodes["/franka_gripper"]
    width = gripper.get("width_m")
    activated = control.get("activated")
    return TwinReport(
        twists=_int(control, "twists"), nonzero_twists=_int(control, "nonzero_twists"),
        ignored_twists=_int(control, "ignored_twists"), error_recoveries=_int(control, "error_recoveries"),
        activated=activated if isinstance(activated, bool) else None,
        arm_position_m=_vector(control, "position_m"), arm_start_position_m=_vector(control, "start_position_m"),
        gripper_goals=_table(gripper, "goals"), gripper_width_m=float(width) if isinstance(width, (int, float)) else None,
        joint_states_published=_int(nodes["/joint_state_publisher"], "published"),
        pub_force_published=_table(nodes["/serial_node"], "published").get(PUB_FORCE, 0),
        board_period_ms=_int(board, "period_ms"), board_samples_sent=_int(board, "samples_sent"),
        board_last_count=_int(board, "last_count"), board_presses=_int(board, "presses"),
        board_port=str(board.get("port", "")),
        pub_force_publishers=list(pub_force_publishers),
        pids={name: _int(data, "pid") for name, data in {**nodes, BOARD: board}.items() if data},
        replaced=list(replaced), stopped=list(stopped), launched=launched,
        missing=[name for name in NODES if name not in registered], nodes=nodes, board=board)
