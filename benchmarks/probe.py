"""The ROS side of the timing benchmarks, run as its own node: ``python -m benchmarks.probe``.

A separate process, because rospy allows one node per process and the probe must be an outsider to
the nodes it measures, as the Arduino and the robot are. ``latency`` publishes force steps on
/pub_force (at once, or through a simulated board every P ms) and writes their monotonic times;
``timing`` records the arrival of every twist. Phases and options: docs/benchmarks.md.

    python -m benchmarks.probe {latency,timing} --help
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import threading
import time
from typing import Any, Dict, List

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float32, Int16

#: The count a force step goes to: 500/700 = 0.71 mapped force, well above the rumble threshold.
ON_COUNT = 500
#: Between phases the force rests at 0 this long (s), so that one phase's rumble has ended.
REST_S = 0.4
#: A step's answer (the pad's rumble turning on or off) is awaited this long at most (s) before the
#: next step: a hang guard. The next step waits for the answer, so a busy machine makes the steps
#: later, never overlapping: a step with no answer is one the nodes lost, not one they were slow for.
ANSWER_TIMEOUT_S = 10.0


class RumbleLogTail:
    """The rumble requests the teleoperation node appends to its ``~rumble_log`` (line-buffered)."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.offset = 0
        self.partial = ""
        self.records: List[Any] = []  # (time_s, intensity)

    def poll(self) -> None:
        with open(self.path, encoding="utf-8") as fh:
            fh.seek(self.offset)
            text = fh.read()
            self.offset = fh.tell()
        lines = (self.partial + text).split("\n")
        self.partial = lines.pop()
        for line in lines:
            fields = line.split()
            if len(fields) >= 2 and not line.startswith("#"):
                self.records.append((float(fields[0]), float(fields[1])))

    def answered(self, since_s: float, on: bool) -> bool:
        """Whether a request at or after ``since_s`` agrees with a step to ``on``."""
        self.poll()
        return any(t >= since_s and (intensity > 0.0) == on for t, intensity in reversed(self.records))


def _wait(condition, timeout_s: float, what: str) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline or rospy.is_shutdown():
            raise SystemExit(f"probe: timed out after {timeout_s:.0f} s waiting for {what}")
        time.sleep(0.02)


def _step_gaps_s(period_s: float, rng: random.Random) -> float:
    """Random time from a step's answer to the next force step, not a multiple of any loop period,
    so steps fall at every phase of the node's loop."""
    lo = period_s + 0.05
    return rng.uniform(lo, lo + period_s + 0.05)


def latency(args: argparse.Namespace) -> Dict[str, Any]:
    rng = random.Random(args.seed)
    lock = threading.Lock()
    own_arrivals: List[float] = []
    mapped_arrivals: List[float] = []

    def on_own(_msg: Int16) -> None:
        now = time.monotonic()
        with lock:
            own_arrivals.append(now)

    def on_mapped(_msg: Float32) -> None:
        now = time.monotonic()
        with lock:
            mapped_arrivals.append(now)

    pub = rospy.Publisher("/pub_force", Int16, queue_size=100)
    rospy.Subscriber("/pub_force", Int16, on_own, queue_size=100)
    mapped_sub = rospy.Subscriber("/force_mapped", Float32, on_mapped, queue_size=100)
    _wait(lambda: pub.get_num_connections() >= 2 and mapped_sub.get_num_connections() >= 1, 30.0,
          "mapping_node and the probe's own subscriber on /pub_force")
    _wait(lambda: open(args.rumble_log).read().startswith("#"), 30.0, f"the rumble log {args.rumble_log}")
    rumbles = RumbleLogTail(args.rumble_log)
    for _ in range(5):  # warm the connections up (first messages pay for lazy setup)
        pub.publish(Int16(data=0))
        time.sleep(0.02)
    time.sleep(REST_S)

    phases = []
    for period_ms in args.board_periods_ms:
        period_s = period_ms / 1e3
        steps: List[List[Any]] = []
        publish_times: List[float] = []
        with lock:
            own_arrivals.clear()
            mapped_arrivals.clear()
        count = [0]
        stop = threading.Event()
        board = None
        if period_s > 0:
            # Its own stop, count and period: a loop that outlives its phase's join must not
            # pick up the next phase's (a new Event, never set).
            def board_loop(stop: threading.Event, count: List[int], period_s: float) -> None:
                next_t = time.monotonic()
                while not stop.is_set():
                    pub.publish(Int16(data=count[0]))
                    next_t += period_s
                    delay = next_t - time.monotonic()
                    if delay > 0:
                        time.sleep(delay)
                    else:
                        next_t = time.monotonic()  # late: restart the schedule, as a firmware loop would
            board = threading.Thread(target=board_loop, args=(stop, count, period_s), daemon=True)
            board.start()
        for k in range(args.steps):
            time.sleep(_step_gaps_s(period_s, rng))
            on = k % 2 == 0
            now = time.monotonic()
            if board is None:
                pub.publish(Int16(data=ON_COUNT if on else 0))
                publish_times.append(now)
            else:
                count[0] = ON_COUNT if on else 0
            steps.append([now, on])
            deadline = now + ANSWER_TIMEOUT_S
            while not rumbles.answered(now, on) and time.monotonic() < deadline and not rospy.is_shutdown():
                time.sleep(0.001)
        time.sleep(_step_gaps_s(period_s, rng))
        stop.set()
        if board is not None:
            board.join(1.0)
        time.sleep(REST_S)
        with lock:
            phase = {"board_period_ms": period_ms, "steps": steps, "publish_s": publish_times,
                     "own_arrivals_s": list(own_arrivals), "mapped_arrivals_s": list(mapped_arrivals)}
        phases.append(phase)
    return {"phases": phases}


def timing(args: argparse.Namespace) -> Dict[str, Any]:
    arrivals: List[float] = []
    sub = rospy.Subscriber(args.topic, Twist, lambda _m: arrivals.append(time.monotonic()), queue_size=100)
    _wait(lambda: sub.get_num_connections() >= 1 and len(arrivals) > 5, 30.0, f"messages on {args.topic}")
    start = len(arrivals)
    time.sleep(args.seconds)
    return {"arrivals_s": arrivals[start:]}


def main(argv: List[str] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.probe")
    sub = parser.add_subparsers(dest="mode", required=True)
    lat = sub.add_parser("latency")
    lat.add_argument("--out", required=True)
    lat.add_argument("--rumble-log", required=True)
    lat.add_argument("--steps", type=int, default=60)
    lat.add_argument("--board-periods-ms", type=lambda s: [float(v) for v in s.split(",")], default=[0.0, 10.0, 300.0])
    lat.add_argument("--seed", type=int, default=1)
    tim = sub.add_parser("timing")
    tim.add_argument("--out", required=True)
    tim.add_argument("--topic", required=True)
    tim.add_argument("--seconds", type=float, default=20.0)
    args = parser.parse_args(argv)
    if args.mode == "latency" and args.steps % 2:
        args.steps += 1  # every phase ends with the force off

    rospy.init_node("bench_probe", anonymous=True)
    result = latency(args) if args.mode == "latency" else timing(args)
    with open(args.out, "w") as f:
        json.dump(result, f)
    rospy.signal_shutdown("probe done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
