"""Ex. 14's trials: record one with its metadata, plan a group's, load a folder of them.

Why one command: a trial must be started, recorded and stopped the same way every time,
with who/what/which condition stored *with* the recording, or the analysis cannot tell
trials apart.  ``record`` starts a private roscore, ``rosbag record`` of the topics that
matter and ``roslaunch hri_lab teleoperation.launch feedback:=...`` (``--sim``: the
simulated lab, the object from the simulation's set), waits until the participant quits
(square ends the launch), stops everything, and writes ``<folder>/<P>_t<NN>.bag`` plus
``<P>_t<NN>.yaml`` with the metadata (also inside the bag, on ``/trial/metadata``).

    python -m hri_teleop.ros.trial plan --participants P01 P02 P03 P04 --objects egg sponge --out plan.csv
    python -m hri_teleop.ros.trial record --participant P01 --trial 1 --object egg --condition no_feedback --sim
    python -m hri_teleop.ros.trial outcome trials/P01_t01.yaml --lifted yes --crushed no   # in the lab

This first version records on a private roscore, as the demo does; using the lab PC's
running master is left for the experiment issue.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import asdict
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import yaml

from hri_teleop.experiment.metrics import CONDITIONS, MetricsError, TrialMeta
from hri_teleop.experiment.plan import counterbalanced_plan, write_plan
from hri_teleop.ros.master import PrivateMaster, run_reporting
from hri_teleop.ros.teleop_demo import DEFAULT_TIMEOUT_S, record_from_bag, record_teleop_launch
from hri_teleop.sim.report import LabRecord

__all__ = ["trial_stem", "record_trial", "load_trials", "main"]

METADATA_TOPIC = "/trial/metadata"


def trial_stem(meta: TrialMeta) -> str:
    """File name stem of a trial: ``P01_t03``."""
    return f"{meta.participant}_t{meta.trial:02d}"


def _write_sidecar(path: Path, meta: TrialMeta, extra: Dict[str, object]) -> None:
    data = dict(asdict(meta))
    data.update(extra)
    path.write_text(yaml.safe_dump(data, sort_keys=False))


def record_trial(meta: TrialMeta, folder: Path, *, sim: bool = True, scenario: Optional[Path] = None,
                 launch_args: Optional[Dict[str, str]] = None, timeout_s: float = DEFAULT_TIMEOUT_S,
                 progress=lambda _m: None) -> Tuple[Path, LabRecord]:
    """Run and record one trial (see the module doc); refuses to overwrite an earlier one."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    bag = folder / f"{trial_stem(meta)}.bag"
    sidecar = bag.with_suffix(".yaml")
    if bag.exists() or sidecar.exists():
        raise MetricsError(f"{bag} exists: trial {meta.trial} of {meta.participant} is already recorded; "
                           "give the next trial number or move the old files away")
    args: Dict[str, object] = {"feedback": "true" if meta.condition == "feedback" else "false"}
    if sim:
        args.update({"sim": "true", "object": meta.object_name})
        if scenario is not None:
            args["scenario"] = str(Path(scenario).resolve())
    args.update(launch_args or {})
    with PrivateMaster() as master:
        progress(f"{meta.label}: roscore on port {master.port}, recording to {bag}")
        record = record_teleop_launch(master, bag, args, timeout_s, progress)
    _add_metadata(bag, meta)
    _write_sidecar(sidecar, meta, {"sim": sim, "launch_args": {k: str(v) for k, v in args.items()},
                                   "ended_by": record.ended_by})
    return bag, record


def _add_metadata(bag_path: Path, meta: TrialMeta) -> None:
    """Append the metadata to the bag itself, so a bag that travels alone still says what it is."""
    import rosbag
    import rospy
    from std_msgs.msg import String

    with rosbag.Bag(str(bag_path), "a") as bag:
        start = bag.get_start_time() if bag.get_message_count() else 0.0
        bag.write(METADATA_TOPIC, String(data=yaml.safe_dump(asdict(meta), sort_keys=False)),
                  rospy.Time.from_sec(start))


def load_trials(folder: Path) -> List[Tuple[TrialMeta, LabRecord, Dict[str, object]]]:
    """Every trial in ``folder``: (metadata, record, the sidecar's other keys such as the outcome)."""
    trials = []
    for sidecar in sorted(Path(folder).glob("*.yaml")):
        data = yaml.safe_load(sidecar.read_text()) or {}
        try:
            meta = TrialMeta(str(data["participant"]), str(data["object_name"]), str(data["condition"]),
                             int(data["trial"]))
        except (KeyError, TypeError, ValueError) as exc:
            raise MetricsError(f"{sidecar}: not a trial's metadata ({exc}); it needs participant, object_name, "
                               "condition and trial") from None
        bag = sidecar.with_suffix(".bag")
        if not bag.exists():
            raise MetricsError(f"{sidecar}: its recording {bag.name} is missing")
        rest = {k: v for k, v in data.items() if k not in ("participant", "object_name", "condition", "trial")}
        trials.append((meta, record_from_bag(bag), rest))
    return trials


def _yes_no(text: str) -> bool:
    value = text.strip().lower()
    if value not in ("yes", "no", "true", "false"):
        raise argparse.ArgumentTypeError(f"{text!r}: answer yes or no")
    return value in ("yes", "true")


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("plan", help="write a counterbalanced trial plan (CSV)")
    p.add_argument("--participants", nargs="+", required=True)
    p.add_argument("--objects", nargs="+", required=True)
    p.add_argument("--repetitions", type=int, default=1)
    p.add_argument("--out", type=Path, default=Path("trials/plan.csv"))
    r = sub.add_parser("record", help="run and record one trial")
    r.add_argument("--participant", required=True)
    r.add_argument("--trial", type=int, required=True)
    r.add_argument("--object", required=True)
    r.add_argument("--condition", choices=CONDITIONS, required=True)
    r.add_argument("--sim", action="store_true", help="the simulated lab (home rehearsal)")
    r.add_argument("--scenario", type=Path, default=None, help="with --sim: a scripted operator instead of a pad")
    r.add_argument("--pad", default="", help="pygame (a real pad) or virtual; empty: the launch's default")
    r.add_argument("--timeout", type=float, default=120.0, help="longest trial, s")
    r.add_argument("--out", type=Path, default=Path("trials"))
    o = sub.add_parser("outcome", help="store the experimenter's judgement of a lab trial")
    o.add_argument("sidecar", type=Path)
    o.add_argument("--lifted", type=_yes_no, required=True)
    o.add_argument("--crushed", type=_yes_no, required=True)
    args = parser.parse_args(argv)
    try:
        if args.command == "plan":
            path = write_plan(counterbalanced_plan(args.participants, args.objects, args.repetitions), args.out)
            print(f"trial plan: {path}")
            return 0
        if args.command == "outcome":
            data = yaml.safe_load(args.sidecar.read_text()) or {}
            data["outcome"] = {"lifted": args.lifted, "crushed": args.crushed}
            args.sidecar.write_text(yaml.safe_dump(data, sort_keys=False))
            print(f"{args.sidecar}: lifted {args.lifted}, crushed {args.crushed}")
            return 0
        meta = TrialMeta(args.participant, args.object, args.condition, args.trial)
        extra = {"pad": args.pad} if args.pad else {}

        def run() -> int:
            bag, record = record_trial(meta, args.out, sim=args.sim, scenario=args.scenario, launch_args=extra,
                                       timeout_s=args.timeout, progress=lambda m: print(f"[trial] {m}", flush=True))
            print(f"{meta.label}: {bag} ({record.duration_s():.1f} s, ended by {record.ended_by})")
            return 0

        return run_reporting(run, "trial")
    except (MetricsError, OSError) as exc:
        print(f"trial: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
