"""Read the Arduino's counts while the piston is pressed, and print the /max_sensor_force to use (Ex. 11).

    python -m hri_teleop.apps.calibrate [--port /dev/ttyACM0] [--seconds 10]
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from hri_teleop.core.serial_protocol import BAUD
from hri_teleop.hardware.real.calibrate import CalibrateError, calibration_max, read_counts


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", default="/dev/ttyACM0", help="the board's serial port (default /dev/ttyACM0)")
    parser.add_argument("--seconds", type=float, default=10.0, help="how long to read, s (default 10)")
    parser.add_argument("--baud", type=int, default=BAUD, help=f"the sketch's baud rate (default {BAUD})")
    args = parser.parse_args(argv)
    if not 0.0 < args.seconds <= 3600.0:
        print(f"calibrate: --seconds must be in (0, 3600], got {args.seconds:g}; e.g. --seconds 10", file=sys.stderr)
        return 2
    print(f"calibrate: reading {args.port} for {args.seconds:g} s: press the piston level with the housing, "
          "a few times", flush=True)
    try:
        counts = read_counts(args.port, args.seconds, args.baud)
        maximum = calibration_max(counts)
    except CalibrateError as exc:
        print(f"calibrate: {exc}", file=sys.stderr)
        return 1
    print(f"calibrate: {len(counts)} samples, maximum count {maximum}")
    print(f"use it as /max_sensor_force: roslaunch hri_lab teleoperation.launch max_sensor_force:={maximum}")
    print(f"  (or `rosparam set /max_sensor_force {maximum}` while mapping_node runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
