"""``python -m benchmarks [NAME ...] [--smoke] [--out DIR] [--jobs N]`` (``make bench``).

Runs the named benchmarks (default: all, in the order below), prints each table row as
soon as it is measured, and writes ``results.json`` and ``results.md`` into ``--out``.
``--smoke`` runs each with tiny sizes: it proves the benchmark works, not how fast.
Exit status 0; 2 with one line on stderr when a benchmark cannot run.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import sys
import time
from pathlib import Path
from typing import Callable, Dict, List, Optional

from benchmarks import machine as machines
from benchmarks.report import HEADER, BenchError, BenchOptions, BenchRow, format_row, write_results

#: name -> module in benchmarks with ``run(options, progress) -> List[BenchRow]``.
BENCHMARKS: Dict[str, str] = {
    "latency": "latency",      # 1. sensor-to-rumble latency (mapping_node + teleoperation)
    "timing": "timing",        # 2. period of the published twist, idle and loaded
    "sim": "sim_speed",        # 3. real-time factor of the simulation flat out
    "grading": "grading",      # 4. hri-grade submission, make grade vs nbgrader autograde
    "notebooks": "notebooks",  # 5. every notebook headless, make setup when nothing is missing
    "determinism": "determinism",  # 6. the same part scores run after run, idle and loaded
    "doctor": "doctor",        # 7. make doctor at home, beside a roscore start and stop
    "selfcheck": "selfcheck",  # 8. the student bundle's make check, whole and one exercise
}


def _progress(message: str) -> None:
    print(f"  … {message}", file=sys.stderr, flush=True)


def run(names: List[str], options: BenchOptions, progress: Callable[[str], None] = _progress,
        first: Optional[machines.Machine] = None) -> List[BenchRow]:
    """Each benchmark between two looks at the machine (``first``: the look before the first one);
    every row carries its benchmark's machine, idle or not."""
    rows: List[BenchRow] = []
    print(HEADER, flush=True)
    for k, name in enumerate(names):
        module = importlib.import_module(f"benchmarks.{BENCHMARKS[name]}")
        before = first if k == 0 and first is not None else machines.sample()
        started = time.monotonic()
        progress(f"{name}: running{' (smoke sizes)' if options.smoke else ''}")
        measured = module.run(options, progress)
        took_s = time.monotonic() - started
        machine = machines.finished(before)
        for row in measured:
            rows.append(dataclasses.replace(row, machine=machine))
            print(format_row(rows[-1]), flush=True)
        progress(f"{name}: done in {took_s:.0f} s; {'idle' if machine.idle else 'the machine was BUSY'}")
    return rows


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("names", nargs="*", metavar="NAME", help=f"benchmarks to run: {', '.join(BENCHMARKS)} (default: all)")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes: check that every benchmark runs")
    parser.add_argument("--out", default="out/bench", help="results and working files (default: out/bench)")
    parser.add_argument("--jobs", type=int, default=None, help="what 'all cores' means (default: the CPU count)")
    args = parser.parse_args(argv)
    unknown = [n for n in args.names if n not in BENCHMARKS]
    if unknown:
        print(f"bench: unknown benchmark {', '.join(unknown)}; choose from {', '.join(BENCHMARKS)}", file=sys.stderr)
        return 2
    names = args.names or list(BENCHMARKS)
    out = Path(args.out).resolve()
    options = BenchOptions(out_dir=out, smoke=args.smoke, jobs=args.jobs)
    machine = machines.sample()
    print(f"Machine: {machine.summary()}", flush=True)
    try:
        rows = run(names, options, first=machine)
    except BenchError as exc:
        print(f"bench: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("bench: interrupted; what was started is stopped", file=sys.stderr)
        return 130
    for path in write_results(rows, out, machine):
        print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
