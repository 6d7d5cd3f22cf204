"""Ex. 14's trials: plan a group's, record one with its metadata, rehearse a session, analyse a folder.

A trial must be started, recorded and stopped the same way every time, with who, what and which
condition stored with the bag, or the analysis cannot tell trials apart. ``record`` launches
teleoperation.launch with the condition on a private or the lab's master and writes bag and sidecar;
``rehearse`` runs a whole session in the simulated lab. Masters and checks: docs/experiment.md.

    python -m hri_teleop.apps.trial {plan,record,outcome,tlx,rehearse,analyse} --help
"""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import yaml

from hri_teleop.core.checks import is_calibration_count
from hri_teleop.core.experiment.analysis import (
    CSV_NAME,
    FIGURE_NAME,
    LoadedTrial,
    StudyResult,
    analyse_trials,
    default_trials_folder,
    measure_trial,
)
from hri_teleop.core.experiment.metrics import MetricsError, TrialMeta
from hri_teleop.core.experiment.plan import counterbalanced_plan, trial_seed, write_plan
from hri_teleop.core.experiment.sidecar import (
    META_KEYS,
    meta_from_sidecar,
    read_sidecar,
    sidecar_data,
    write_sidecar,
)
from hri_teleop.core.experiment.tlx import optional_tlx
from hri_teleop.core.modes import HARDWARE_NODES, NODE_DEFAULT_PAD, Start, decide_mode, start_refusal
from hri_teleop.core.run_record import LabRecord
from hri_teleop.plots.study import save_result_figure
from hri_teleop.ros.bags import BagError
from hri_teleop.ros.launch_inspect import LaunchInspectError, declared_args
from hri_teleop.ros.master import MasterError, PrivateMaster, RunningMaster, started_here
from hri_teleop.ros.teleop_demo import DEFAULT_TIMEOUT_S, record_from_bag, record_teleop_launch
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.operators import study_scenario

__all__ = ["METADATA_TOPIC", "PADS", "trial_stem", "trial_seed", "record_trial", "load_trial", "load_trials", "analyse_folder",
           "lab_master",
           "launch_nodes", "rehearse", "describe_trial"]

METADATA_TOPIC = "/trial/metadata"
#: How a rehearsal's participant operates: a simulated study participant (a seeded pad
#: script on the virtual pad), or you at a real pad.
PADS = ("script", "pygame")

Progress = Callable[[str], None]


def trial_stem(meta: TrialMeta) -> str:
    """File name stem of a trial: ``P01_t03``."""
    return f"{meta.participant}_t{meta.trial:02d}"


# --------------------------------------------------------------------------- masters


def lab_master(uri: Optional[str] = None, base_env: Optional[Mapping[str, str]] = None) -> RunningMaster:
    """The running master at ``uri`` (default ``$ROS_MASTER_URI``), checked to answer."""
    env = dict(base_env if base_env is not None else os.environ)
    uri = uri or env.get("ROS_MASTER_URI", "")
    if not uri:
        raise MasterError("ROS_MASTER_URI is not set: source the lab's ROS setup (or tools/env.sh) in this terminal, "
                          "or give the master with --master-uri http://localhost:11311/")
    return RunningMaster(uri, base_env=env).start()


_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def launch_nodes(master: PrivateMaster, args: Mapping[str, object]) -> List[str]:
    """The node names ``teleoperation.launch`` with ``args`` would start (``roslaunch --nodes``; no master needed)."""
    argv = ["roslaunch", "--nodes", "hri_lab", "teleoperation.launch"] + [f"{k}:={v}" for k, v in args.items()]
    try:
        proc = subprocess.run(argv, env=master.env, capture_output=True, text=True, timeout=60)
    except FileNotFoundError:
        raise MasterError("roslaunch not found on PATH: run 'make setup' (it installs ROS 1) or source tools/env.sh") \
            from None
    if proc.returncode != 0:
        text = _ANSI.sub("", proc.stderr + proc.stdout)
        first = next((line.strip() for line in text.splitlines() if line.strip() and not line.startswith("ROS path")),
                     f"exit {proc.returncode}")
        raise MasterError(f"teleoperation.launch cannot start with {' '.join(argv[4:])}: {first}; fix the launch "
                          "arguments (--launch-arg) or ROS_PACKAGE_PATH (source tools/env.sh)")
    return [line.strip() for line in proc.stdout.splitlines() if line.strip().startswith("/")]


def _refuse_running_launch(master: PrivateMaster, args: Mapping[str, object]) -> None:
    clash = sorted(set(launch_nodes(master, args)) & master.node_names())
    if clash:
        hint = (" (franka_control started separately? add --launch-arg robot:=false)"
                if any("franka" in n for n in clash) else "")
        raise MasterError(f"{', '.join(clash)} already running on {master.uri}: stop that launch first (Ctrl-C in "
                          f"its terminal); the trial starts teleoperation.launch itself, feedback:={args['feedback']}"
                          f"{hint}")


#: Launch arguments the lab's file declares and a student's file need not: the node's parameter, or
#: the master's, carries them instead.
_OPTIONAL_ARGS = ("feedback", "max_sensor_force")


def _fit_to_launch_file(master: PrivateMaster, args: Dict[str, object]) -> None:
    """The condition as the node's ``~feedback`` parameter, set before the launch, so that a
    student's own teleoperation.launch (Ex. 12-13, no ``<arg>`` of the lab's) records a trial too;
    the optional arguments it does not declare are left out (roslaunch refuses an unused one)."""
    master.set_param("/teleoperation/feedback", str(args.get("feedback", "true")).lower() == "true")
    try:
        declared = declared_args(["hri_lab", "teleoperation.launch"], master.env)
    except LaunchInspectError as exc:
        raise MasterError(str(exc)) from None
    for name in _OPTIONAL_ARGS:
        if name in args and name not in declared:
            del args[name]


def _param(master: PrivateMaster, name: str) -> Any:
    try:
        return master.get_param(name)
    except (MasterError, OSError):
        return None


# --------------------------------------------------------------------------- one trial


def _add_metadata(bag_path: Path, meta: TrialMeta) -> None:
    """Append the metadata to the bag itself, so a bag that travels alone still says what it is."""
    import rosbag  # noqa: PLC0415 - course.widgets and the study analysis import this module without ROS
    import rospy  # noqa: PLC0415 - as rosbag
    from std_msgs.msg import String  # noqa: PLC0415 - as rosbag

    with rosbag.Bag(str(bag_path), "a") as bag:
        start = bag.get_start_time() if bag.get_message_count() else 0.0
        bag.write(METADATA_TOPIC, String(data=yaml.safe_dump(sidecar_data(meta, {}), sort_keys=False)),
                  rospy.Time.from_sec(start))


def _set_aside(bag: Path) -> Optional[Path]:
    """A failed trial's partial bag is kept as ``<stem>.bag.failed`` (for the logs), out of the way of a retry."""
    if not bag.exists():
        return None
    failed = bag.with_name(bag.name + ".failed")
    os.replace(bag, failed)
    return failed


def record_trial(meta: TrialMeta, folder: Union[str, Path], *, sim: bool = True, scenario: Optional[Path] = None,
                 launch_args: Optional[Mapping[str, object]] = None, timeout_s: float = DEFAULT_TIMEOUT_S,
                 progress: Progress = lambda _m: None, master: Optional[PrivateMaster] = None,
                 operator: Optional[Mapping[str, Any]] = None) -> Tuple[Path, LabRecord]:
    """Run and record one trial (docs/experiment.md); refuses to overwrite an earlier one.

    ``master``: a started :class:`PrivateMaster` or :class:`RunningMaster` to record on
    (left running); None starts a private roscore for this trial only.  ``operator``:
    stored in the sidecar (who played the participant in a rehearsal: script and seed).
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    bag = folder / f"{trial_stem(meta)}.bag"
    sidecar = bag.with_suffix(".yaml")
    if bag.exists() or sidecar.exists():
        raise MetricsError(f"{bag} exists: trial {meta.trial} of {meta.participant} is already recorded; "
                           "give the next trial number or move the old files away")
    feedback = meta.condition == "feedback"
    args: Dict[str, object] = {}
    if sim:
        args.update({"sim": "true", "object": meta.object_name})
        if scenario is not None:
            args["scenario"] = str(Path(scenario).resolve())
    extra = dict(launch_args or {})
    if "feedback" in extra and str(extra["feedback"]).lower() != str(feedback).lower():
        raise MetricsError(f"launch argument feedback:={extra['feedback']} contradicts the condition "
                           f"{meta.condition}; leave feedback out, the condition sets it")
    args.update(extra)
    args["feedback"] = "true" if feedback else "false"

    def run(on: PrivateMaster) -> Tuple[LabRecord, Any, Any]:
        if isinstance(on, RunningMaster):
            start = Start(f"trial {meta.label} (teleoperation.launch {' '.join(f'{k}:={v}' for k, v in args.items())})",
                          simulated=sim, pad=str(args.get("pad", NODE_DEFAULT_PAD)))
            own = started_here(on.uri)  # a running master this process started (a rehearsal), or the lab's
            hardware = sorted(on.node_names() & set(HARDWARE_NODES))
            refusal = start_refusal(decide_mode(os.environ, own), start, hardware, own_master=own)
            if refusal:
                raise MasterError(refusal)
            _refuse_running_launch(on, args)
            session_calibration = _param(on, "/max_sensor_force")
            if "max_sensor_force" not in args and is_calibration_count(session_calibration):
                args["max_sensor_force"] = int(session_calibration)  # keep the session's Ex. 11 value
        _fit_to_launch_file(on, args)
        progress(f"{meta.label}: recording on {on.uri} to {bag}")
        try:
            record = record_teleop_launch(on, bag, args, timeout_s, progress)
        except BaseException:
            _set_aside(bag)
            raise
        return record, _param(on, "/max_sensor_force"), _param(on, "/teleoperation/feedback")

    if master is None:
        with PrivateMaster() as private:
            record, max_sensor_force, feedback_param = run(private)
        where = "private"
    else:
        record, max_sensor_force, feedback_param = run(master)
        where = "private" if not isinstance(master, RunningMaster) else master.uri
    if feedback_param is not feedback:
        failed = _set_aside(bag)
        raise MasterError(f"the teleoperation node's ~feedback was {feedback_param!r}, not {feedback} as "
                          f"{meta.condition} needs: the recording ({failed}) is not a valid trial; does your "
                          "teleoperation.launch pass feedback:= to the node (hri_lab's does)?")
    _add_metadata(bag, meta)
    data: Dict[str, Any] = {
        "sim": sim, "master": where, "launch_args": {k: str(v) for k, v in args.items()},
        "max_sensor_force": max_sensor_force, "feedback_param": feedback_param, "ended_by": record.ended_by,
        "duration_s": round(record.duration_s(), 3),
    }
    if operator:
        data["operator"] = dict(operator)
    write_sidecar(sidecar, sidecar_data(meta, data))
    return bag, record


def load_trial(sidecar: Union[str, Path]) -> LoadedTrial:
    """One trial: its sidecar and the bag beside it (MetricsError naming the file and the fix)."""
    sidecar = Path(sidecar)
    data = read_sidecar(sidecar)
    meta = meta_from_sidecar(data, sidecar)
    bag = sidecar.with_suffix(".bag")
    if not bag.exists():
        raise MetricsError(f"{sidecar}: its recording {bag.name} is missing; put it back or move the sidecar away")
    rest = {k: v for k, v in data.items() if k not in META_KEYS}
    optional_tlx(rest, str(sidecar))
    try:
        record = record_from_bag(bag)
    except BagError as exc:
        raise MetricsError(str(exc)) from None
    return LoadedTrial(meta, record, rest, sidecar)


def load_trials(folder: Union[str, Path]) -> List[LoadedTrial]:
    """Every trial in ``folder`` (each ``*.yaml`` sidecar with its ``*.bag``), in file-name order.

    A sidecar that is not a trial's, a missing or unreadable bag, or a malformed
    questionnaire is one MetricsError naming the file and the fix.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise MetricsError(f"{folder}: no such folder of trials; give the folder `trial record`/`rehearse` wrote")
    return [load_trial(sidecar) for sidecar in sorted(folder.glob("*.yaml"))]


# --------------------------------------------------------------------------- a whole session


def analyse_folder(folder: Union[str, Path, None] = None, *, figure: Union[str, Path, None, bool] = True,
                   csv_path: Union[str, Path, None, bool] = True, max_sensor_force: Optional[float] = None,
                   allow_unpaired: bool = False) -> StudyResult:
    """Load every trial in ``folder`` (default :func:`default_trials_folder`) and :func:`analyse_trials` them.

    ``figure`` / ``csv_path``: True writes ``study.png`` / ``metrics.csv`` into the folder,
    a path writes there, False or None writes nothing.
    """
    folder = Path(folder) if folder is not None else default_trials_folder()
    if not folder.is_dir():
        raise MetricsError(f"{folder}: no such folder of trials; record a session first (python -m "
                           f"hri_teleop.apps.trial rehearse --out {folder}) or give the folder the trials are in")
    trials = load_trials(folder)
    if not trials:
        raise MetricsError(f"{folder}: no trials in this folder (no *.yaml sidecar beside a *.bag); record some "
                           f"(python -m hri_teleop.apps.trial rehearse --out {folder}) or give another folder")
    figure_path = folder / FIGURE_NAME if figure is True else (Path(figure) if figure else None)
    result = analyse_trials(trials, max_sensor_force=max_sensor_force, allow_unpaired=allow_unpaired, folder=folder)
    if figure_path is not None:
        save_result_figure(result, figure_path)
    if csv_path:
        result.write_csv(folder / CSV_NAME if csv_path is True else Path(csv_path))
    return result


def describe_trial(trial: LoadedTrial) -> str:
    m = measure_trial(trial)
    what = "crushed" if m.crushed else ("lifted, intact" if m.lifted else "not lifted")
    return f"{what}; peak {m.peak_force_n:.2f} N, rumble {m.rumble_s:.1f} s, {m.duration_s:.1f} s"


def rehearse(participants: Sequence[str], objects: Sequence[str], out: Union[str, Path], *, repetitions: int = 1,
             pad: str = "script", seed: int = 0, quick: bool = False, resume: bool = False,
             master: Optional[PrivateMaster] = None, timeout_s: float = 120.0, progress: Progress = print,
             ask: Callable[[str], str] = input, analyse: bool = True) -> Optional[StudyResult]:
    """Record a whole counterbalanced session in the simulated lab, then analyse it.

    ``pad`` ``script``: simulated study participants (:func:`hri_teleop.sim.operators.study_scenario`,
    seed :func:`trial_seed`, ``quick``: short trials); ``pygame``: you at a real pad, asked
    to press Enter before each trial.  One private roscore serves the whole session
    unless ``master`` is given.  ``resume`` skips the plan's trials already in ``out``.
    Returns the :class:`~hri_teleop.core.experiment.analysis.StudyResult` (None with
    ``analyse`` False).
    """
    if pad not in PADS:
        raise MetricsError(f"pad {pad!r} is unknown; use one of {', '.join(PADS)}")
    out = Path(out)
    plan = counterbalanced_plan(list(participants), list(objects), repetitions)
    unknown = sorted(set(objects) - set(OBJECTS))
    if unknown:
        raise MetricsError(f"object(s) {', '.join(unknown)} not in the simulation's set; "
                           f"use {', '.join(sorted(OBJECTS))}")
    done = [m for m in plan if (out / f"{trial_stem(m)}.yaml").exists() or (out / f"{trial_stem(m)}.bag").exists()]
    if done and not resume:
        raise MetricsError(f"{out / trial_stem(done[0])}.yaml exists: {out} holds an earlier session; give another "
                           "--out, or --resume to record only the missing trials")
    out.mkdir(parents=True, exist_ok=True)
    write_plan(plan, out / "plan.csv")
    index = {p: i for i, p in enumerate(participants)}
    todo = [m for m in plan if m not in done]
    progress(f"[rehearse] {len(plan)} trials ({len(todo)} to record) in {out}; plan: {out / 'plan.csv'}")

    def session(on: PrivateMaster) -> None:
        for k, meta in enumerate(todo, 1):
            launch_args: Dict[str, object] = {}
            scenario = None
            operator: Dict[str, Any] = {}
            if pad == "script":
                trial_seed_ = trial_seed(seed, index[meta.participant], meta.trial)
                data = study_scenario(meta.condition, trial_seed_, meta.object_name, quick=quick)
                scenario = out / "scenarios" / f"{trial_stem(meta)}.yaml"
                scenario.parent.mkdir(parents=True, exist_ok=True)
                scenario.write_text(yaml.safe_dump(data, sort_keys=False))
                operator = {"kind": "study_operator", "seed": trial_seed_, "quick": quick}
            else:
                launch_args["pad"] = pad
                operator = {"kind": pad}
                switch = "ON: the pad rumbles" if meta.condition == "feedback" else "OFF: no rumble"
                ask(f"[rehearse] next: {meta.participant} trial {meta.trial}, grasp the {meta.object_name}, "
                    f"feedback {switch}; square ends the trial. Press Enter to start ")
            progress(f"[rehearse] {k}/{len(todo)} {meta.label} ...")
            record_trial(meta, out, sim=True, scenario=scenario, launch_args=launch_args, timeout_s=timeout_s,
                         master=on, operator=operator)
            loaded = load_trial(out / f"{trial_stem(meta)}.yaml")
            progress(f"[rehearse] {k}/{len(todo)} {meta.label}: {describe_trial(loaded)}")

    if master is None:
        with PrivateMaster() as private:
            session(private)
    else:
        session(master)
    if not analyse:
        return None
    result = analyse_folder(out)
    progress(result.report())
    return result
