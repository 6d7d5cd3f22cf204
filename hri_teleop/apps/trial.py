"""Ex. 14's trials from a terminal: plan a group's, record one, note its outcome and TLX, rehearse, analyse.

The work is :mod:`hri_teleop.ros.trial`'s (the notebooks' widgets call the same functions).

    python -m hri_teleop.apps.trial {plan,record,outcome,tlx,rehearse,analyse} --help
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.core.experiment.metrics import CONDITIONS, MetricsError, TrialMeta
from hri_teleop.core.experiment.plan import counterbalanced_plan, write_plan
from hri_teleop.core.experiment.sidecar import update_sidecar
from hri_teleop.core.experiment.tlx import SUBSCALES, TlxRatings, store_tlx
from hri_teleop.ros.master import RunningMaster, run_reporting
from hri_teleop.ros.trial import PADS, analyse_folder, describe_trial, lab_master, load_trial, record_trial, rehearse


def _participant_codes(given: Sequence[str]) -> List[str]:
    if len(given) == 1 and given[0].isdigit():
        n = int(given[0])
        if not 1 <= n <= 99:
            raise MetricsError(f"--participants {n}: give 1..99 participants, or their codes (P01 P02 ...)")
        return [f"P{i:02d}" for i in range(1, n + 1)]
    return list(given)


def _yes_no(text: str) -> bool:
    value = text.strip().lower()
    if value not in ("yes", "no", "true", "false"):
        raise argparse.ArgumentTypeError(f"{text!r}: answer yes or no")
    return value in ("yes", "true")


def _launch_arg(text: str) -> Tuple[str, str]:
    key, sep, value = text.partition(":=")
    if not sep:
        key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError(f"{text!r}: write a launch argument as name:=value, e.g. robot_ip:=172.16.0.2")
    return key.strip(), value.strip()


def _add_master_options(p: argparse.ArgumentParser) -> None:
    group = p.add_mutually_exclusive_group()
    group.add_argument("--lab", action="store_true",
                       help="record on the running master at $ROS_MASTER_URI (the lab PC's roscore)")
    group.add_argument("--master-uri", default="", help="record on the running master at this URI")


def _master_from(args: argparse.Namespace) -> Optional[RunningMaster]:
    if args.lab or args.master_uri:
        return lab_master(args.master_uri or None)
    return None


def _parser() -> argparse.ArgumentParser:
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
    r.add_argument("--launch-arg", "-a", type=_launch_arg, action="append", default=[], metavar="NAME:=VALUE",
                   help="more teleoperation.launch arguments, e.g. robot_ip:=172.16.0.2 max_sensor_force:=690")
    r.add_argument("--timeout", type=float, default=120.0, help="longest trial, s")
    r.add_argument("--out", type=Path, default=Path("trials"))
    _add_master_options(r)
    o = sub.add_parser("outcome", help="store the experimenter's judgement of a lab trial")
    o.add_argument("sidecar", type=Path)
    o.add_argument("--lifted", type=_yes_no, required=True)
    o.add_argument("--crushed", type=_yes_no, required=True)
    t = sub.add_parser("tlx", help="store the participant's raw NASA-TLX ratings (0..100, steps of 5) of a trial")
    t.add_argument("sidecar", type=Path)
    for s in SUBSCALES:
        t.add_argument(f"--{s.key}", type=int, required=True, help=f"{s.question} (0 {s.low} .. 100 {s.high})")
    h = sub.add_parser("rehearse", help="a whole counterbalanced session in the simulated lab, then the analysis")
    h.add_argument("--participants", nargs="+", default=["3"], help="how many (P01, P02, ...) or their codes")
    h.add_argument("--objects", nargs="+", default=["egg"], help="from the simulation's set (egg, sponge, block, ...)")
    h.add_argument("--repetitions", type=int, default=1)
    h.add_argument("--pad", choices=PADS, default="script",
                   help="script: simulated participants (seeded pad scripts); pygame: you, with a real pad")
    h.add_argument("--seed", type=int, default=0, help="base seed of the simulated participants")
    h.add_argument("--quick", action="store_true",
                   help="short trials (the arm starts low; 7 s of trial instead of 16 s)")
    h.add_argument("--resume", action="store_true", help="record only the trials missing in --out")
    h.add_argument("--timeout", type=float, default=120.0, help="longest trial, s")
    h.add_argument("--out", type=Path, default=Path("trials"))
    _add_master_options(h)
    a = sub.add_parser("analyse", help="metrics table, rates, paired test and study.png of a folder of trials")
    a.add_argument("folder", type=Path, nargs="?", default=None, help="default: $HRI_TRIALS or trials/")
    a.add_argument("--figure", type=Path, default=None, help="PNG path (default: <folder>/study.png)")
    a.add_argument("--max-sensor-force", type=float, default=None, help="override every trial's calibration")
    a.add_argument("--allow-unpaired", action="store_true",
                   help="leave participants with one condition out of the test")
    return parser


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "plan":
            path = write_plan(counterbalanced_plan(args.participants, args.objects, args.repetitions), args.out)
            print(f"trial plan: {path}")
            return 0
        if args.command == "outcome":
            update_sidecar(args.sidecar, {"outcome": {"lifted": args.lifted, "crushed": args.crushed}})
            print(f"{args.sidecar}: lifted {args.lifted}, crushed {args.crushed}")
            return 0
        if args.command == "tlx":
            ratings = TlxRatings(**{s.key: getattr(args, s.key) for s in SUBSCALES})
            store_tlx(args.sidecar, ratings)
            print(f"{args.sidecar}: raw TLX {ratings.raw_tlx:.1f}")
            return 0
        if args.command == "analyse":
            result = analyse_folder(args.folder, figure=args.figure or True, max_sensor_force=args.max_sensor_force,
                                    allow_unpaired=args.allow_unpaired)
            print(result.table())
            print(result.report())
            return 0
        if args.command == "rehearse":
            codes = _participant_codes(args.participants)

            def run_session() -> int:
                master = _master_from(args)
                try:
                    rehearse(codes, args.objects, args.out, repetitions=args.repetitions, pad=args.pad,
                             seed=args.seed, quick=args.quick, resume=args.resume, master=master,
                             timeout_s=args.timeout, progress=lambda m: print(m, flush=True))
                finally:
                    if master is not None:
                        master.stop()
                return 0

            return run_reporting(run_session, "trial")
        meta = TrialMeta(args.participant, args.object, args.condition, args.trial)
        extra: Dict[str, object] = dict(args.launch_arg)
        if args.pad:
            extra["pad"] = args.pad

        def run() -> int:
            master = _master_from(args)
            try:
                bag, record = record_trial(meta, args.out, sim=args.sim, scenario=args.scenario, launch_args=extra,
                                           timeout_s=args.timeout, master=master,
                                           progress=lambda m: print(f"[trial] {m}", flush=True))
            finally:
                if master is not None:
                    master.stop()
            sidecar = bag.with_suffix(".yaml")
            print(f"{meta.label}: {bag} ({record.duration_s():.1f} s, ended by {record.ended_by})")
            if args.sim:
                print(f"  {describe_trial(load_trial(sidecar))}")
            else:
                print(f"  next: python -m hri_teleop.apps.trial outcome {sidecar} --lifted yes|no --crushed yes|no")
            print(f"  questionnaire: the TLX widget, or python -m hri_teleop.apps.trial tlx {sidecar} --mental ...")
            return 0

        return run_reporting(run, "trial")
    except (MetricsError, OSError) as exc:
        print(f"trial: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
