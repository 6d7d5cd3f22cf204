"""A counterbalanced trial plan for a lab group.

Why: with two conditions done one after the other, whatever participants learn in the
first block helps the second.  Half the participants start with feedback, half without
(an AB/BA crossover), and the objects rotate through a Latin square, so that neither
order nor object is confounded with the condition.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import List, Sequence, Union

from hri_teleop.core.experiment.metrics import CONDITIONS, MetricsError, TrialMeta

__all__ = ["counterbalanced_plan", "trial_seed", "write_plan", "read_plan"]


def trial_seed(base_seed: int, participant_index: int, trial: int) -> int:
    """The simulated participant's seed of a trial: one per participant and trial number."""
    return int(base_seed) + 1000 * int(participant_index) + int(trial)


def counterbalanced_plan(participants: Sequence[str], objects: Sequence[str], repetitions: int = 1) -> List[TrialMeta]:
    """Every participant does every object ``repetitions`` times in each condition (see the module doc).

    Participant ``i`` does condition block AB if ``i`` is even, BA if odd; within a block
    the objects follow row ``i`` of a cyclic Latin square, repeated ``repetitions`` times.
    Trials are numbered from 1 per participant.
    """
    if not participants or len(set(participants)) != len(participants):
        raise MetricsError(f"participants must be distinct codes, got {list(participants)!r}; e.g. P01 P02 P03 P04")
    if not objects or len(set(objects)) != len(objects):
        raise MetricsError(f"objects must be distinct names, got {list(objects)!r}; e.g. egg sponge")
    if repetitions < 1:
        raise MetricsError(f"repetitions must be at least 1, got {repetitions!r}")
    plan: List[TrialMeta] = []
    for i, participant in enumerate(participants):
        order = CONDITIONS if i % 2 == 0 else tuple(reversed(CONDITIONS))
        row = [objects[(i + k) % len(objects)] for k in range(len(objects))]
        number = 1
        for condition in order:
            for _ in range(repetitions):
                for obj in row:
                    plan.append(TrialMeta(participant, obj, condition, number))
                    number += 1
    return plan


_FIELDS = ("participant", "trial", "condition", "object")


def write_plan(plan: Sequence[TrialMeta], path: Union[str, Path]) -> Path:
    """The plan as a CSV a lab assistant can print and tick off."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(_FIELDS)
        for m in plan:
            writer.writerow((m.participant, m.trial, m.condition, m.object_name))
    return path


def read_plan(path: Union[str, Path]) -> List[TrialMeta]:
    path = Path(path)
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    try:
        return [TrialMeta(r["participant"], r["object"], r["condition"], int(r["trial"])) for r in rows]
    except (KeyError, ValueError) as exc:
        raise MetricsError(f"{path}: not a trial plan ({exc}); columns are {', '.join(_FIELDS)}") from None
