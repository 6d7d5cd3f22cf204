"""Benchmark 6: the same part scores, run after run, idle and with both cores busy.

The answer key and three wrong packages are each graded ``runs`` times, half on an idle machine,
half with one spinning process per core; the figure counts the packages whose part scores never
changed (the packages and the reference: docs/benchmarks.md). Smoke: one idle and one loaded run
of the answer key's teleoperation check.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Callable, Dict, List, Sequence, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.grading.cases.templates import generate_answers
from hri_teleop.grading.judge.harness import CLOCK_ENV

__all__ = ["BusyCores", "WRONG_PACKAGES", "FULL_RUNS", "package_variants", "part_scores", "run"]

Progress = Callable[[str], None]

FULL_RUNS = 20  # 10 idle, 10 loaded
SMOKE_RUNS = 2
SMOKE_CHECKS = ("teleoperation",)

#: name -> (file in hri_lab, text of the answer, what a wrong student wrote instead)
WRONG_PACKAGES: Dict[str, Tuple[str, str, str]] = {
    "mapping-no-clip": ("scripts/mapping_node.py", "return min(1.0, max(0.0, mapped))", "return mapped"),
    "teleop-no-deadzone": ("scripts/teleoperation.py", "return normalize_analog_input(value, self.deadzone)",
                           "return value"),
    "sensor-launch-no-param": ("launch/sensor.launch", '<param name="max_sensor_force" value="700"/>', ""),
}


def package_variants(target: Path) -> Dict[str, Path]:
    """The answer key's hri_lab (markers dropped) and the wrong packages, under ``target``."""
    key = generate_answers(SOLUTIONS, target / "answer-key" / "hri_lab")
    packages = {"answer-key": key}
    for name, (relative, right, wrong) in WRONG_PACKAGES.items():
        folder = target / name / "hri_lab"
        shutil.copytree(key, folder)
        text = (folder / relative).read_text(encoding="utf-8")
        if right not in text:
            raise BenchError(f"{relative}: the answer no longer holds {right!r}; update WRONG_PACKAGES")
        (folder / relative).write_text(text.replace(right, wrong), encoding="utf-8")
        packages[name] = folder
    return packages


def part_scores(results: Sequence[dict]) -> Dict[str, float]:
    """{"check: part": points} from ``hri-grade --json`` (Gradescope's tests list)."""
    return {str(test["name"]): float(test["score"]) for test in results}


def _grade(package: Path, out: Path, checks: Sequence[str], env: Dict[str, str]) -> Dict[str, float]:
    argv = [sys.executable, "-m", "hri_teleop.apps.grade", "submission", str(package), "--json", "--out", str(out)]
    if checks:
        argv += ["--checks", ",".join(checks)]
    ran = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=600, stdin=subprocess.DEVNULL)
    try:
        data = json.loads(ran.stdout)
    except ValueError:
        raise BenchError(f"hri-grade submission {package} printed no JSON (exit {ran.returncode}): "
                         f"{ran.stderr.strip()[-300:]}") from None
    return part_scores(data.get("tests", []))


class BusyCores:
    """One spinning process per core while the block runs."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.procs: List[subprocess.Popen] = []

    def __enter__(self) -> "BusyCores":
        self.procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(self.n)]
        return self

    def __exit__(self, *exc: object) -> None:
        for proc in self.procs:
            proc.kill()
            proc.wait()


def run(options: BenchOptions, progress: Progress) -> List[BenchRow]:
    work = Path(options.out_dir) / "determinism"
    shutil.rmtree(work, ignore_errors=True)
    packages = package_variants(work / "packages")
    runs, checks = (SMOKE_RUNS, SMOKE_CHECKS) if options.smoke else (FULL_RUNS, ())
    if options.smoke:
        packages = {"answer-key": packages["answer-key"]}
    env = {k: v for k, v in os.environ.items() if k != CLOCK_ENV}
    cores = options.jobs or os.cpu_count() or 1
    seen: Dict[str, List[Dict[str, float]]] = {name: [] for name in packages}
    for index in range(runs):
        loaded = index >= runs // 2
        for name, package in packages.items():
            progress(f"determinism: run {index + 1}/{runs} ({'loaded' if loaded else 'idle'}) of {name}")
            out = work / "runs" / f"{name}-{index + 1}"
            if loaded:
                with BusyCores(cores):
                    seen[name].append(_grade(package, out, checks, env))
            else:
                seen[name].append(_grade(package, out, checks, env))
    steady = [name for name, scores in seen.items() if all(s == scores[0] for s in scores)]
    differing = {name: sorted({part for s in scores for part in s if s[part] != scores[0].get(part)})
                 for name, scores in seen.items() if name not in steady}
    totals = {name: sorted({sum(s.values()) for s in scores}) for name, scores in seen.items()}
    figure = (f"{len(steady)}/{len(packages)} packages with the same part scores in all {runs} runs "
              f"({runs // 2} idle, {runs - runs // 2} with {cores} busy cores); totals "
              + ", ".join(f"{n} {'/'.join(f'{t:g}' for t in ts)}" for n, ts in totals.items()))
    if differing:
        figure += "; parts that changed: " + "; ".join(f"{n}: {', '.join(p)}" for n, p in differing.items())
    values = {"runs": float(runs), "packages": float(len(packages)), "steady_packages": float(len(steady)),
              "busy_cores": float(cores)}
    return [BenchRow(benchmark="grading determinism", figure=figure, reference=f"{len(packages)} packages",
                     ratio=len(steady) / len(packages), ratio_means="packages with identical part scores / packages",
                     values=values)]
