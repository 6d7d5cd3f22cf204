"""``make demo`` (sensor stage): the handout's Ex. 6 pipeline on a private master.

Starts a roscore on a free port, ``roslaunch hri_lab sensor.launch`` (FSR_sensor.py and
mapping_node.py with /max_sensor_force), records /pub_force and /force_mapped with
``rosbag record`` for a few seconds, stops everything and prints what arrived: rates,
the range of /force_mapped, whether every value equals the mapping of its count, and the
/pub_force -> /force_mapped latency.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import List, Optional

import numpy as np

from hri_teleop.mapping import map_force
from hri_teleop.plots import sensor_timeline
from hri_teleop.traces import pair_outputs, percentile_ms, rate_hz
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master import MasterError, PrivateMaster


def _progress(message: str) -> None:
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
        launch = master.roslaunch("hri_lab", "sensor.launch",
                                  {"max_sensor_force": max_sensor_force, "rate_hz": rate_hz_param,
                                   "max_value": press_max_count})
        master.wait_for(lambda: bool(master.publishers("/force_mapped")) or not launch.running,
                        20, "mapping_node to advertise /force_mapped")
        if not launch.running:
            print("demo: sensor.launch exited early:\n" + launch.output()[-2000:], file=sys.stderr)
            return 1
        recorder = master.record(bag_path, ["/pub_force", "/force_mapped"])
        _progress(f"recording /pub_force and /force_mapped for {duration_s:.0f} s")
        for _ in range(int(duration_s)):
            time.sleep(1.0)
            print(".", end="", flush=True)
        time.sleep(duration_s - int(duration_s))
        print(flush=True)
        recorder.stop()
        launch.stop()
    _progress(f"stopped roscore and nodes ({time.monotonic() - started:.1f} s in all)")

    topics = read_topics(bag_path, ["/pub_force", "/force_mapped"])
    counts = [(t, float(m.data)) for t, m in topics["/pub_force"]]
    mapped = [(t, float(m.data)) for t, m in topics["/force_mapped"]]
    if len(mapped) < 2:
        print(f"demo: only {len(mapped)} message(s) on /force_mapped; see the node logs above", file=sys.stderr)
        return 1
    pairing = pair_outputs(counts, mapped, lambda c: float(map_force(c, max_sensor_force)), tolerance=1e-6)
    values = np.array([v for _, v in mapped])
    lines: List[str] = [
        "",
        "Sensor pipeline (handout Ex. 6): FSR_sensor.py -> /pub_force -> mapping_node.py -> /force_mapped",
        f"  /max_sensor_force      {max_sensor_force}",
        f"  /pub_force             {len(counts)} msgs, {rate_hz(counts):.1f} Hz, counts {min(v for _, v in counts):.0f}..{max(v for _, v in counts):.0f}",
        f"  /force_mapped          {len(mapped)} msgs, {rate_hz(mapped):.1f} Hz, values {values.min():.3f}..{values.max():.3f} (std_msgs/Float32)",
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
    return 0 if pairing.unmatched_outputs == 0 and 0.0 <= values.min() and values.max() <= 1.0 else 1


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=5.0, help="recording time, s")
    parser.add_argument("--max-sensor-force", type=int, default=700, help="/max_sensor_force, ADC counts")
    parser.add_argument("--rate", type=float, default=50.0, help="FSR_sensor.py publish rate, Hz")
    parser.add_argument("--press-max", type=int, default=800,
                        help="top count of a simulated press; above --max-sensor-force shows the clipping")
    parser.add_argument("--out", type=Path, default=Path("out"), help="folder for the bag and the plot")
    args = parser.parse_args(argv)
    try:
        return run(args.duration, args.max_sensor_force, args.rate, args.out, args.press_max)
    except MasterError as exc:
        print(f"demo: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("demo: interrupted; everything it started has been stopped", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
