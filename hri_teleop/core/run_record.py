"""What a teleoperation run did, as the demo and the tests report it.

Why: ``make demo`` (a real ROS run, read back from its bag), the offline runner
(:mod:`hri_teleop.sim.lab`) and the integration tests all answer the same questions --
was the object grasped, lifted, crushed; how hard was it squeezed; how long did the pad
rumble; did the Franka see a single limit violation -- so the answers are computed once,
here, from plain time series.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

__all__ = ["LIFTED_M", "Series", "LabRecord", "LabSummary", "summarize", "format_summary"]

#: An object this far above the table counts as lifted (m).
LIFTED_M = 0.005
#: (time s, value) pairs in time order.
Series = List[Tuple[float, float]]


@dataclass
class LabRecord:
    """Time series of one run (times in seconds on one clock) and the world's final word.

    ``count``/``mapped``: /pub_force and /force_mapped; ``rumble``: the intensity the
    teleoperation node asked of the pad each tick; ``width_target``: /gripper_width;
    ``width``: the hand's width; ``speed``: the end effector's translational speed (m/s);
    ``grip_force``: force between the fingers (N); ``object_height``: above the table (m).
    """

    count: Series = field(default_factory=list)
    mapped: Series = field(default_factory=list)
    rumble: Series = field(default_factory=list)
    width_target: Series = field(default_factory=list)
    width: Series = field(default_factory=list)
    speed: Series = field(default_factory=list)
    grip_force: Series = field(default_factory=list)
    object_height: Series = field(default_factory=list)
    object_name: str = ""
    grasped: bool = False
    lifted: bool = False  # at the end of the run
    crushed: bool = False
    violations: int = 0
    violation_counts: Dict[str, int] = field(default_factory=dict)
    peak_grip_force_n: Optional[float] = None  # from the world, if it kept one
    reflex_explanation: List[str] = field(default_factory=list)  # core.reflex.explain_reflex of the run's
    ended_by: str = ""  # "quit", "timeout", ...
    wall_s: float = 0.0

    def start_s(self) -> float:
        """The earliest time in any series (0.0 if all are empty)."""
        firsts = [s[0][0] for s in (self.count, self.mapped, self.rumble, self.width_target, self.width,
                                    self.speed, self.grip_force, self.object_height) if s]
        return min(firsts) if firsts else 0.0

    def duration_s(self) -> float:
        lasts = [s[-1][0] for s in (self.count, self.mapped, self.rumble, self.width_target, self.width,
                                    self.speed, self.grip_force, self.object_height) if s]
        return (max(lasts) - self.start_s()) if lasts else 0.0


@dataclass(frozen=True)
class LabSummary:
    """The demo's answer, one field per line of its printout."""

    object_name: str
    grasped: bool
    lifted: bool
    crushed: bool
    peak_force_n: float
    peak_force_mapped: float
    rumble_s: float
    violations: int
    violation_counts: Dict[str, int]
    duration_s: float
    ended_by: str
    reflex_explanation: Tuple[str, ...] = ()

    @property
    def outcome(self) -> str:
        """One word for the run: crushed, lifted, grasped or missed."""
        if self.crushed:
            return "crushed"
        if self.lifted:
            return "lifted"
        if self.grasped:
            return "grasped"
        return "missed"


def _peak(series: Sequence[Tuple[float, float]]) -> float:
    return max((v for _, v in series), default=0.0)


def time_above(series: Sequence[Tuple[float, float]], threshold: float = 0.0) -> float:
    """Seconds a sampled signal spent above ``threshold``: each sample holds until the next."""
    total = 0.0
    for (t, v), (t_next, _) in zip(series, series[1:]):
        if v > threshold:
            total += t_next - t
    return total


def summarize(record: LabRecord) -> LabSummary:
    """The numbers the demo prints (see :class:`LabSummary`)."""
    peak = record.peak_grip_force_n if record.peak_grip_force_n is not None else _peak(record.grip_force)
    return LabSummary(
        object_name=record.object_name or "none",
        grasped=record.grasped,
        lifted=record.lifted,
        crushed=record.crushed,
        peak_force_n=float(peak),
        peak_force_mapped=float(_peak(record.mapped)),
        rumble_s=time_above(record.rumble, 0.0),
        violations=int(record.violations),
        violation_counts=dict(record.violation_counts),
        duration_s=record.duration_s(),
        ended_by=record.ended_by,
        reflex_explanation=tuple(record.reflex_explanation),
    )


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def format_summary(summary: LabSummary) -> List[str]:
    """The summary as printable lines (no trailing newlines)."""
    counts = ", ".join(f"{name}: {n}" for name, n in sorted(summary.violation_counts.items()))
    return [
        f"object            {summary.object_name}: {summary.outcome}",
        f"grasped           {_yes(summary.grasped)}",
        f"lifted            {_yes(summary.lifted)}",
        f"crushed           {_yes(summary.crushed)}",
        f"peak grip force   {summary.peak_force_n:.2f} N",
        f"peak /force_mapped {summary.peak_force_mapped:.3f}",
        f"pad rumbled       {summary.rumble_s:.2f} s",
        f"Franka limit violations {summary.violations}" + (f" ({counts})" if counts else ""),
        f"run               {summary.duration_s:.1f} s, ended by {summary.ended_by or '?'}",
    ] + [f"  {line}" for line in summary.reflex_explanation]
