"""Ex. 14's experiment in the lock-step lab: a counterbalanced study of simulated participants.

The trials ``python -m hri_teleop.apps.trial rehearse`` records over ROS run here in ``run_lab``
(about 100 times faster) and are analysed by ``analyse_trials``, as recorded trials are. The Ex. 14
notebook compares the conditions with it; the analysis notebook falls back to it without recorded
trials. Participant ``i`` behaves as in a rehearsal with the same seed
(:func:`hri_teleop.core.experiment.plan.trial_seed`); ``operator`` replaces their scripts.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, List, Optional, Sequence, Union

from hri_teleop.core.config import lab_max_sensor_force
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.experiment.analysis import LoadedTrial, StudyResult, analyse_trials
from hri_teleop.core.experiment.metrics import TrialMeta
from hri_teleop.core.experiment.plan import counterbalanced_plan, trial_seed
from hri_teleop.core.run_record import LabRecord
from hri_teleop.core.teleop import TeleopParams
from hri_teleop.plots.study import save_result_figure
from hri_teleop.sim.config import world_config_from_dict
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.operators import study_scenario
from hri_teleop.sim.virtual_pad import ScriptStep, parse_script

__all__ = ["StudyError", "participant_codes", "simulate_trial", "simulate_study"]

class StudyError(HriTeleopError, ValueError):
    """A simulated study was asked for something it cannot run (the message says what to pass)."""


def participant_codes(count: int) -> List[str]:
    """``P01``, ``P02``, ... for ``count`` simulated participants (at least 2: a paired comparison needs pairs)."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 2:
        raise StudyError(f"participants must be a whole number of at least 2, got {count!r}; e.g. 6")
    return [f"P{k:02d}" for k in range(1, count + 1)]


def simulate_trial(meta: TrialMeta, seed: int, *, quick: bool = True,
                   operator: Optional[Sequence[ScriptStep]] = None) -> LabRecord:
    """One trial in the lock-step lab: the condition switches the rumble, the object is the plan's."""
    if meta.object_name not in OBJECTS:
        raise StudyError(f"object {meta.object_name!r} is not in the simulation's set; use one of "
                         f"{', '.join(sorted(OBJECTS))}")
    scenario = study_scenario(meta.condition, seed, meta.object_name, quick=quick and operator is None)
    world = world_config_from_dict(scenario["world"], f"simulated trial {meta.label}")
    steps = list(operator) if operator is not None else parse_script(scenario["steps"])
    params = TeleopParams(feedback=meta.condition == "feedback")
    return run_lab(steps, world, params, max_sensor_force=float(lab_max_sensor_force()), max_duration_s=60.0)


def simulate_study(participants: Union[int, Sequence[str]] = 6, objects: Sequence[str] = ("egg",), *,
                   seed: int = 0, quick: bool = True, operator: Optional[Sequence[ScriptStep]] = None,
                   figure: Union[str, Path, None] = None,
                   progress: Optional[Callable[[str], None]] = None) -> StudyResult:
    """Every trial of a counterbalanced plan in the lock-step lab, analysed as recorded trials are.

    ``participants``: a count (codes P01...) or the codes; ``objects``: names of the sim's
    set; ``quick``: the rehearsal's short trials (about 7 s of lab each); ``figure``: a PNG
    path for the study figure. ``progress`` gets one line per trial.
    """
    codes = participant_codes(participants) if isinstance(participants, int) else list(participants)
    if len(codes) < 2:
        raise StudyError(f"a paired comparison needs at least 2 participants, got {codes!r}")
    plan = counterbalanced_plan(codes, list(objects))
    index = {code: i for i, code in enumerate(codes)}
    trials: List[LoadedTrial] = []
    for k, meta in enumerate(plan, 1):
        record = simulate_trial(meta, trial_seed(seed, index[meta.participant], meta.trial), quick=quick,
                                operator=operator)
        trials.append(LoadedTrial(meta, record, {"max_sensor_force": float(lab_max_sensor_force()), "sim": True},
                                  Path(f"{meta.participant}_t{meta.trial:02d} (simulated)")))
        if progress is not None:
            progress(f"[study] {k}/{len(plan)} {meta.label}: {record.ended_by}, "
                     f"{record.duration_s():.1f} s of lab")
    result = analyse_trials(trials)
    return save_result_figure(result, figure) if figure is not None else result

