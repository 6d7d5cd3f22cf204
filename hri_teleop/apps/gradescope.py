"""``python -m hri_teleop.apps.gradescope build [--out DIR] [--checks a,b]``: the autograder zip."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

from hri_teleop.core.paths import OUT
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.gradescope.build import build_zip
from hri_teleop.grading.results import GradingError


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hri_teleop.apps.gradescope",
                                     description="Build the Gradescope autograder zip (grading/README.md, Gradescope).")
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="write autograder.zip")
    b.add_argument("--out", default=str(OUT / "gradescope"), help="folder (default: out/gradescope)")
    b.add_argument("--checks", default="", help=f"comma-separated checks this assignment grades (default: all: "
                                                f"{','.join(CHECKS)})")
    b.add_argument("--unsandboxed", action="store_true",
                   help="grade uploaded notebooks with the grader's rights (where bubblewrap cannot run there)")
    args = parser.parse_args(argv)
    checks = [c.strip() for c in args.checks.split(",") if c.strip()] or list(CHECKS)
    try:
        target = build_zip(Path(args.out), checks, unsandboxed=args.unsandboxed)
    except (GradingError, OSError) as exc:
        print(f"make gradescope: {exc}", file=sys.stderr)
        return 2
    print(f"{target} ({target.stat().st_size / 2**20:.1f} MB; checks: {', '.join(checks)}"
          + ("; notebooks UNSANDBOXED" if args.unsandboxed else "") + "); upload it as the "
          "assignment's autograder on Gradescope (grading/README.md, Gradescope)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
