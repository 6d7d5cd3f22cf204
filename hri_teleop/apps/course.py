"""``python -m hri_teleop.apps.course COMMAND``: release, link, strip, check, check-bundle."""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from typing import List, Optional

from hri_teleop.course.errors import CourseError
from hri_teleop.course.release import (
    COURSE_DIR,
    build_release,
    bundle_leaks,
    check_course,
    link_answer_key,
    source_notebooks,
    strip_outputs,
)
from hri_teleop.grading.assignments import ASSIGNMENTS

__all__ = ["main"]


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hri_teleop.apps.course", description="The nbgrader course of Task 4: release and check.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    r = sub.add_parser("release", help="student versions + templates into notebooks/release/, checked, packed")
    r.add_argument("--archive", default=None, help="the .tar.gz (default: out/task4-student-bundle.tar.gz)")
    sub.add_parser("link", help="link source/<assignment>/hri_lab to solutions/hri_lab")
    s = sub.add_parser("strip", help="remove outputs and execution counts from the source notebooks")
    s.add_argument("paths", nargs="*", help="notebooks (default: every source notebook)")
    k = sub.add_parser("check", help="run every notebook: the answer key must pass, the student version fail")
    k.add_argument("--jobs", type=int, default=2, help="notebooks at a time (default 2)")
    c = sub.add_parser("check-bundle", help="find solution text in a student bundle folder")
    c.add_argument("path", nargs="?", default=str(COURSE_DIR / "release"))
    args = parser.parse_args(argv)
    try:
        if args.command == "release":
            release, archive = build_release(archive=args.archive)
            for assignment in ASSIGNMENTS:
                files = sorted(p.relative_to(release) for p in (release / assignment).rglob("*") if p.is_file())
                print(f"{release / assignment}: {len(files)} files")
                for f in files:
                    print(f"  {f}")
            print(f"no solution text in the bundle; packed into {archive}")
            return 0
        if args.command == "link":
            for link in link_answer_key():
                print(f"{link} -> {os.readlink(link)}")
            return 0
        if args.command == "strip":
            for path in strip_outputs(args.paths or source_notebooks()):
                print(f"stripped {path}")
            return 0
        if args.command == "check":
            failed = 0
            with tempfile.TemporaryDirectory(prefix="hri-course-check-") as work:
                for name, result in check_course(work, jobs=args.jobs).items():
                    source, release = result["source"], result["release"]
                    short = {g: v for g, v in source["grades"].items() if v[0] != v[1]}
                    bad = bool(source["errors"] or short or release.get("passed") or release.get("changed"))
                    failed += bad
                    print(f"{'FAIL' if bad else 'ok  '} {name}: answer key {sum(v[0] for v in source['grades'].values()):g}/"
                          f"{sum(v[1] for v in source['grades'].values()):g} in {source['seconds']:.0f} s, "
                          f"student version passes {len(release.get('passed', []))} autograded cell(s) "
                          f"in {release['seconds']:.0f} s")
                    for line in source["errors"] + [f"passes: {c['source']}" for c in release.get("passed", [])]:
                        print(f"       {line}")
            return 1 if failed else 0
        if args.command == "check-bundle":
            leaks = bundle_leaks(args.path)
            print("\n".join(leaks) if leaks else f"{args.path}: no solution text")
            return 1 if leaks else 0
        parser.print_help()
        return 2
    except CourseError as exc:
        print(f"course: {exc}", file=sys.stderr)
        return 1



if __name__ == "__main__":
    sys.exit(main())
