"""Benchmark 1: from a force on /pub_force to the rumble the pad receives.

The probe publishes counts as the Arduino does; mapping_node and the teleoperation node turn them
into rumble requests to the virtual pad, time-stamped in its ``~rumble_log``. Three rows: the nodes
alone (against one rospy hop of the same messages, the floor of any ROS stage), and end to end with
a board sampling every 10 ms or 300 ms, where a step waits for the next sample (docs/benchmarks.md).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Dict, List, Optional

import numpy as np

from benchmarks.nodes import MeasuredNodes
from benchmarks.report import BenchError, BenchOptions, BenchRow
from benchmarks.stats import ForceStep, Summary, match_rumbles, summarise_ms
from hri_teleop.plots.common import latency_cdf
from hri_teleop.sim.virtual_pad import read_rumble_log

#: Force steps per phase (full run, smoke run). The smoke run's 20 direct steps take ~2 s
#: and make its median a fair test of "answered at once, not at the next tick".
STEPS = {False: 200, True: 20}
#: The handout's sketch waits 300 ms per loop; ours publishes every 10 ms.
BOARD_PERIODS_MS = (0.0, 10.0, 300.0)
#: Steps of the board phases (~0.1 s and ~0.6 s each): fewer of them in the smoke run.
BOARD_PHASE_STEPS = {(10.0, False): 200, (10.0, True): 6, (300.0, False): 60, (300.0, True): 4}


def _phase_latencies(phase: Dict, rumbles) -> List[Optional[float]]:
    steps = [ForceStep(float(t), bool(on)) for t, on in phase["steps"]]
    return match_rumbles(steps, [(r.time_s, r.intensity) for r in rumbles])


def _hops(sent: List[float], arrived: List[float], what: str) -> List[float]:
    """Arrival - send of the same messages (TCP keeps their order; a count mismatch is a loss)."""
    if len(arrived) != len(sent):
        raise BenchError(f"{len(sent)} force messages were published but {len(arrived)} arrived at {what}: "
                         "messages were lost, the figures would mislead")
    return list(np.asarray(arrived) - np.asarray(sent))


def measure(options: BenchOptions, progress: Callable[[str], None]) -> Dict[str, object]:
    """Run the probe over the real nodes; per phase the latencies (s), plus the hop floors."""
    steps = STEPS[options.smoke]
    with MeasuredNodes(options.out_dir / "latency") as nodes:
        results: Dict[str, object] = {}
        for period_ms in BOARD_PERIODS_MS:
            n = steps if period_ms == 0.0 else BOARD_PHASE_STEPS[(period_ms, options.smoke)]
            progress(f"latency: {n} force steps, board period {period_ms:g} ms")
            data = nodes.probe(["latency", "--rumble-log", str(nodes.rumble_log), "--steps", str(n),
                                "--board-periods-ms", f"{period_ms:g}"], f"probe-latency-{period_ms:g}ms",
                               timeout_s=60.0 + n * (3 * period_ms / 1e3 + 0.5))
            phase = data["phases"][0]
            rumbles = read_rumble_log(nodes.rumble_log)
            results[f"board_{period_ms:g}ms"] = _phase_latencies(phase, rumbles)
            if period_ms == 0.0:
                results["hop_s"] = _hops(phase["publish_s"], phase["own_arrivals_s"], "the probe's own subscriber")
                results["mapped_s"] = _hops(phase["publish_s"], phase["mapped_arrivals_s"], "/force_mapped")
    return results


def _answered(latencies: List[Optional[float]], what: str) -> List[float]:
    got = [v for v in latencies if v is not None]
    if not got:
        raise BenchError(f"{what}: the pad never answered a force step; see the rumble log in the bench folder")
    return got


def rows_from(results: Dict[str, object]) -> List[BenchRow]:
    hop = summarise_ms(results["hop_s"], "hops")  # type: ignore[arg-type]
    mapped = summarise_ms(results["mapped_s"], "mapped forces")  # type: ignore[arg-type]
    rows: List[BenchRow] = []
    previous: Optional[Summary] = None
    previous_name = ""
    for period_ms in BOARD_PERIODS_MS:
        key = f"board_{period_ms:g}ms"
        latencies = results[key]  # type: ignore[assignment]
        missed = sum(v is None for v in latencies)  # type: ignore[union-attr]
        got = summarise_ms(_answered(latencies, key), "rumble latencies")  # type: ignore[arg-type]
        values = {"p50_ms": got.p50_ms, "p99_ms": got.p99_ms, "max_ms": got.max_ms, "steps": float(got.n + missed),
                  "missed_steps": float(missed)}
        figure = f"{got.text()} (n={got.n}{f', {missed} missed' if missed else ''})"
        if period_ms == 0.0:
            values.update({"hop_p50_ms": hop.p50_ms, "hop_p99_ms": hop.p99_ms, "mapped_p50_ms": mapped.p50_ms,
                           "mapped_p99_ms": mapped.p99_ms})
            rows.append(BenchRow("force → rumble, nodes only", figure,
                                 f"one rospy hop {hop.text()}; /force_mapped p50 {mapped.p50_ms:.2f} ms",
                                 got.p50_ms / hop.p50_ms, "p50 / hop p50", values))
        else:
            assert previous is not None
            rows.append(BenchRow(f"force → rumble, board every {period_ms:g} ms", figure,
                                 f"{previous_name} p50 {previous.p50_ms:.2f} ms", got.p50_ms / previous.p50_ms,
                                 f"p50 / {previous_name} p50", values))
        previous, previous_name = got, ("nodes only" if period_ms == 0.0 else f"{period_ms:g} ms board")
    return rows


def plot(results: Dict[str, object], path: Path) -> Path:
    """The CDF of every phase beside the hop floor (latency.png next to the results)."""
    curves = [("one rospy hop (floor)", results["hop_s"]), ("/force_mapped (two hops)", results["mapped_s"])]
    for period_ms in BOARD_PERIODS_MS:
        latencies = [v for v in results[f"board_{period_ms:g}ms"] if v is not None]  # type: ignore[union-attr]
        curves.append(("rumble, nodes only" if period_ms == 0.0 else f"rumble, board every {period_ms:g} ms",
                       latencies))
    return latency_cdf(curves, path, "force step on /pub_force -> rumble request at the pad")  # type: ignore[arg-type]


def run(options: BenchOptions, progress: Callable[[str], None]) -> List[BenchRow]:
    results = measure(options, progress)
    rows = rows_from(results)
    progress(f"latency: plot in {plot(results, options.out_dir / 'latency.png')}")
    return rows
