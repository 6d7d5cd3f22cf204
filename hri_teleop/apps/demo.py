"""``make demo``: the whole lab simulated, teleoperation.launch sim:=true with a scenario, then its summary.

    python -m hri_teleop.apps.demo [--scenario FILE] [--object egg] [--out out]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

from hri_teleop.ros.master import run_reporting
from hri_teleop.ros.teleop_demo import DEFAULT_TIMEOUT_S, run


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=None,
                        help="operator scenario YAML (default: hri_lab/scenarios/default.yaml)")
    parser.add_argument("--object", default="", help="egg | block | heavy_block | sponge (default: the scenario's)")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, help="give up after this many s")
    parser.add_argument("--out", type=Path, default=Path("out"), help="folder for the bag and the plot")
    args = parser.parse_args(argv)
    if args.scenario is not None and not args.scenario.is_file():
        print(f"demo: no scenario file {args.scenario}; give the path of a scenario YAML "
              "(see hri_lab/scenarios/)", file=sys.stderr)
        return 2
    extra = {"object": args.object} if args.object else {}
    return run_reporting(lambda: run(args.scenario, args.out, args.timeout, extra), "demo")


if __name__ == "__main__":
    sys.exit(main())
