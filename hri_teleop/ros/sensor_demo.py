"""``make demo`` (sensor stage): the handout's Ex. 6 pipeline on a private master.

Starts a roscore on a free port, ``roslaunch hri_lab sensor.launch`` (FSR_sensor.py and
mapping_node.py with /max_sensor_force), records /pub_force and /force_mapped with
``rosbag record`` for a few seconds, stops everything and prints what arrived: rates,
the range of /force_mapped, whether every value equals the mapping of its count, and the
/pub_force -> /force_mapped latency.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, List, Mapping, Tuple

import numpy as np

from hri_teleop.core.mapping import map_force
from hri_teleop.core.traces import pair_outputs, percentile_ms, rate_hz
from hri_teleop.plots.common import sensor_timeline
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master import MasterError, PrivateMaster


@dataclass(frozen=True)
class SensorRecording:
    """What a run of sensor.launch published, as plain (receive time s, value) traces."""

    topic_types: Dict[str, str]
    counts: List[Tuple[float, float]]   # /pub_force
    mapped: List[Tuple[float, float]]   # /force_mapped
    bag_path: Path


def record_sensor_launch(master: PrivateMaster, bag_path: Path, duration_s: float,
                         launch_args: Mapping[str, object], progress: Callable[[str], None] = lambda _m: None
                         ) -> SensorRecording:
    """roslaunch hri_lab sensor.launch on ``master``, rosbag-record both topics, stop, read.

    The demo and the integration tests share this, so both judge the same pipeline.
    """
    launch = master.roslaunch("hri_lab", "sensor.launch", launch_args)
    try:
        master.wait_for(lambda: bool(master.publishers("/force_mapped")) or not launch.running,
                        20, "mapping_node to advertise /force_mapped")
        if not launch.running:
            raise MasterError("sensor.launch exited early: " + launch.output()[-2000:])
        recorder = master.record(bag_path, ["/pub_force", "/force_mapped"])
        progress(f"recording /pub_force and /force_mapped for {duration_s:.0f} s")
        deadline = time.monotonic() + duration_s
        while time.monotonic() < deadline:
            time.sleep(min(1.0, max(0.0, deadline - time.monotonic())))
            progress(".")
        recorder.stop()
        types = master.topic_types()
    finally:
        launch.stop()
    topics = read_topics(bag_path, ["/pub_force", "/force_mapped"])
    return SensorRecording(
        topic_types=types,
        counts=[(t, float(m.data)) for t, m in topics["/pub_force"]],
        mapped=[(t, float(m.data)) for t, m in topics["/force_mapped"]],
        bag_path=Path(bag_path),
    )


def _progress(message: str) -> None:
    if message == ".":
        print(".", end="", flush=True)
    else:
        print(f"[demo] {message}", flush=True)


def run(duration_s: float, max_sensor_force: int, rate_hz_param: float, out_dir: Path,
        press_max_count: int = 800) -> int:
    out_dir.mkdir(parents=True, exist_ok=True)
    bag_path = out_dir / "sensor_demo.bag"
    if bag_path.exists():
        bag_path.unlink()  # the demo's own output from an earlier run
    started = time.monotonic()
    with PrivateMaster() as master:
        _progress(f"roscore up on port {master.port}")
        rec = record_sensor_launch(master, bag_path, duration_s, {
            "max_sensor_force": max_sensor_force, "rate_hz": rate_hz_param, "max_value": press_max_count,
        }, _progress)
        print(flush=True)
    _progress(f"stopped roscore and nodes ({time.monotonic() - started:.1f} s in all)")

    counts, mapped = rec.counts, rec.mapped
    if len(mapped) < 2 or len(counts) < 2:
        print(f"demo: only {len(counts)} message(s) on /pub_force and {len(mapped)} on /force_mapped; "
              "see the node output above", file=sys.stderr)
        return 1
    pairing = pair_outputs(counts, mapped, lambda c: float(map_force(c, max_sensor_force)), tolerance=1e-6)
    values = np.array([v for _, v in mapped])
    lines: List[str] = [
        "",
        "Sensor pipeline (handout Ex. 6): FSR_sensor.py -> /pub_force -> mapping_node.py -> /force_mapped",
        f"  /max_sensor_force      {max_sensor_force}",
        f"  /pub_force             {len(counts)} msgs, {rate_hz(counts):.1f} Hz, counts {min(v for _, v in counts):.0f}..{max(v for _, v in counts):.0f} ({rec.topic_types.get('/pub_force')})",
        f"  /force_mapped          {len(mapped)} msgs, {rate_hz(mapped):.1f} Hz, values {values.min():.3f}..{values.max():.3f} ({rec.topic_types.get('/force_mapped')})",
        f"  equal to map(count)    {len(pairing.pairs)}/{len(mapped)} within 1e-6, {pairing.unmatched_outputs} wrong",
    ]
    if len(pairing.pairs):
        lat = pairing.latencies_s
        lines.append(f"  latency pub->mapped   p50 {percentile_ms(lat, 50):.2f} ms, p99 {percentile_ms(lat, 99):.2f} ms, "
                     f"max {lat.max() * 1e3:.2f} ms (rosbag receive times)")
    png = sensor_timeline(counts, mapped, max_sensor_force, out_dir / "sensor_demo.png")
    lines.append(f"  bag                   {bag_path}")
    lines.append(f"  timeline plot         {png}")
    print("\n".join(lines))
    ok = pairing.pairs and pairing.unmatched_outputs == 0 and 0.0 <= values.min() and values.max() <= 1.0
    return 0 if ok else 1
