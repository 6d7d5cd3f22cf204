"""``hri-grade``: the autograder from the command line.

    hri-grade CHECK PATH [--json] [--seed N] [--out DIR]     one check on a file or an hri_lab folder
    hri-grade submission DIR | batch DIR | traces | templates   (hri-grade COMMAND -h for each)

Exit status: 0 every check passed, 1 a check failed, 2 the grader itself could not run
(the reason on one line on stderr). ``--json`` prints the Gradescope results format.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import List, Optional, Sequence

from hri_teleop.core.paths import REPO as _REPO
from hri_teleop.grading.batch.folders import BatchError, course_layout, grade_all, refresh_folders
from hri_teleop.grading.batch.late import LateError
from hri_teleop.grading.batch.nbgrader_batch import grade_course, refresh_course
from hri_teleop.grading.cases.templates import TemplateError, generate_templates
from hri_teleop.grading.cases.tracefiles import TRACE_DIR, write_traces
from hri_teleop.grading.checks import CHECKS, default_check_jobs, grade, grade_submission
from hri_teleop.grading.exercises.registry import exercise, exercises
from hri_teleop.grading.results import CheckResult, GradingError, feedback_text, gradescope_json
from hri_teleop.grading.run.sandbox import SandboxError, sandbox_mode
from hri_teleop.grading.run.workspace import WorkspaceError

__all__ = ["main", "EXIT_PASSED", "EXIT_FAILED", "EXIT_GRADER_ERROR"]

EXIT_PASSED, EXIT_FAILED, EXIT_GRADER_ERROR = 0, 1, 2


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hri-grade", description="Autograder of the HRI lab's Task 4 (teleoperation).",
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in list(CHECKS) + ["submission"]:
        p = sub.add_parser(name, help=f"grade {'one package' if name == 'submission' else name}")
        p.add_argument("path", help="the student's file or hri_lab folder" if name != "submission"
                       else "the student's hri_lab folder (or their submission folder)")
        p.add_argument("--json", action="store_true", help="print the Gradescope results JSON")
        p.add_argument("--seed", type=int, default=None, help="seed of the hidden inputs (default: $HRI_GRADE_SEED, else from the folder)")
        p.add_argument("--out", default=None, help="where plots, logs and results go (default: a new temp folder)")
        if name == "submission" or (name in CHECKS and "graph_cache" in exercise(name).grade_kwargs):
            p.add_argument("--graph-cache", default=None,
                           help="file with the lab's live graph (read if it exists, else written)")
        if name == "submission":
            p.add_argument("--checks", default="", help="comma-separated subset of checks (default: all)")
            p.add_argument("--jobs", type=int, default=None,
                           help="checks run at once (default: the CPU count + 1; make grade gives 1, it runs submissions at once)")
    b = sub.add_parser("batch", help="grade every submission in a folder, several at once")
    b.add_argument("path", nargs="?", default=str(_REPO / "notebooks" / "submitted"),
                   help="folder of submissions, one subfolder per student (default: notebooks/submitted); "
                        "an nbgrader course's submitted/ is autograded with nbgrader")
    b.add_argument("--out", default=str(_REPO / "out" / "grades"), help="results folder (default: out/grades)")
    b.add_argument("--jobs", type=int, default=None, help="submissions graded at once (default: the CPU count)")
    b.add_argument("--checks", default="", help="comma-separated subset of the files' checks (default: all)")
    b.add_argument("--timeout", type=float, default=None,
                   help="seconds one submission may take before it is stopped and recorded as not graded "
                        "(default: 1800 for an nbgrader autograde, 600 for the files)")
    b.add_argument("--student", default=None,
                   help="regrade this student only (their folder's name); the others' rows in OUT are kept")
    b.add_argument("--report-only", action="store_true",
                   help="grade nothing: the late policy, grades.csv's totals, lms.csv and report.html again from OUT "
                        "and nbgrader's gradebook (after grading by hand, or a changed late.yaml)")
    b.add_argument("--late", default=None, help="the late policy (default: late.yaml beside the course or in the "
                   "submissions folder, when there is one; format in grading/README.md)")
    b.add_argument("--unsandboxed", action="store_true",
                   help="grade where bubblewrap cannot run, and run the notebooks' kernels with the grader's rights "
                        "(without it make grade refuses there); the output and report.html say so first")
    t = sub.add_parser("traces", help="write the public reference traces")
    t.add_argument("--out", default=None, help="folder (default: grading/traces)")
    m = sub.add_parser("templates", help="write the student templates generated from solutions/")
    m.add_argument("--solutions", default=str(_REPO / "solutions" / "hri_lab"))
    m.add_argument("--out", default=str(_REPO / "build" / "templates" / "hri_lab"))
    return parser


def _report(results: Sequence[CheckResult], as_json: bool, out_dir: Path) -> int:
    payload = gradescope_json(results)
    (out_dir / "results.json").write_text(json.dumps(payload, indent=2), encoding="utf-8")
    (out_dir / "feedback.txt").write_text(feedback_text(results) + "\n", encoding="utf-8")
    (out_dir / "checks.json").write_text(json.dumps([r.to_dict() for r in results], indent=2), encoding="utf-8")
    if as_json:
        print(json.dumps(payload, indent=2))
    else:
        print(feedback_text(results))
        print(f"(plots, logs and results in {out_dir})")
    return EXIT_PASSED if all(r.passed for r in results) else EXIT_FAILED


def main(argv: Optional[List[str]] = None) -> int:
    args = _parser().parse_args(argv)
    if not args.command:
        _parser().print_help()
        return EXIT_GRADER_ERROR

    try:
        if args.command == "traces":
            traces = {name: build for found in exercises() for name, build in found.public_traces.items()}
            for path in write_traces(Path(args.out) if args.out else TRACE_DIR, traces):
                print(path)
            return EXIT_PASSED
        if args.command == "templates":
            for item in generate_templates(args.solutions, args.out):
                print(f"{item.target}  ({item.regions} region(s) removed)")
            return EXIT_PASSED
        if args.command == "batch":
            checks = [c.strip() for c in args.checks.split(",") if c.strip()] or None
            unknown = [c for c in checks or () if c not in CHECKS]
            if unknown:
                raise GradingError(f"unknown check(s) {', '.join(unknown)}; use {', '.join(CHECKS)}")
            if args.timeout is not None and args.timeout <= 0:
                raise GradingError(f"--timeout {args.timeout:g}: give the seconds one submission may take, e.g. 1800")
            folder = Path(args.path)
            late = Path(args.late) if args.late else None
            layout = course_layout(folder) if folder.is_dir() else None
            if args.report_only:
                if layout is not None:
                    return refresh_course(layout[0], layout[1], Path(args.out), late=late)
                return refresh_folders(folder, Path(args.out), late=late)
            if layout is not None:  # an nbgrader course: nbgrader's autograde beside the files' checks
                return grade_course(layout[0], layout[1], Path(args.out), jobs=args.jobs, checks=checks,
                                    timeout_s=args.timeout, student=args.student, late=late,
                                    unsandboxed=args.unsandboxed)
            return grade_all(folder, Path(args.out), jobs=args.jobs, checks=checks, timeout_s=args.timeout,
                             student=args.student, late=late, unsandboxed=args.unsandboxed)
        if args.json:  # stdout is the results' JSON: the sandbox note, if any, goes beside it
            sandbox_mode(stream=sys.stderr)
        if not Path(args.path).expanduser().exists():
            raise GradingError(f"{args.path}: no such file or folder; give the student's file or hri_lab folder")
        out_dir = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="hri-grade-"))
        out_dir.mkdir(parents=True, exist_ok=True)
        if args.command == "submission":
            checks = [c.strip() for c in args.checks.split(",") if c.strip()]
            unknown = [c for c in checks if c not in CHECKS]
            if unknown:
                raise GradingError(f"unknown check(s) {', '.join(unknown)}; use {', '.join(CHECKS)}")
            results = grade_submission(args.path, seed=args.seed, out_dir=out_dir, checks=checks or tuple(CHECKS),
                                       graph_cache=Path(args.graph_cache) if args.graph_cache else None,
                                       jobs=args.jobs if args.jobs is not None else default_check_jobs(os.cpu_count()))
        elif "graph_cache" in exercise(args.command).grade_kwargs:
            results = [grade(args.command, args.path, seed=args.seed, out_dir=out_dir,
                             graph_cache=Path(args.graph_cache) if args.graph_cache else None)]
        else:
            results = [grade(args.command, args.path, seed=args.seed, out_dir=out_dir)]
        return _report(results, args.json, out_dir)
    except (GradingError, SandboxError, TemplateError, WorkspaceError, BatchError, LateError, OSError) as exc:
        print(f"hri-grade: {exc}", file=sys.stderr)
        return EXIT_GRADER_ERROR
    except KeyboardInterrupt:
        print("hri-grade: interrupted", file=sys.stderr)
        return EXIT_GRADER_ERROR
    except Exception as exc:  # a grader bug: one line; HRI_GRADE_DEBUG=1 shows the traceback
        if os.environ.get("HRI_GRADE_DEBUG"):
            raise
        print(f"hri-grade: internal error ({type(exc).__name__}: {exc}); rerun with HRI_GRADE_DEBUG=1 for the "
              "traceback and report it", file=sys.stderr)
        return EXIT_GRADER_ERROR


if __name__ == "__main__":
    sys.exit(main())
