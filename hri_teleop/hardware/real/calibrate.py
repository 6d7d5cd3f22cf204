"""Ex. 11's calibration without ROS: the largest count the plain-serial board sends.

With the ``fsr_serial`` sketch on the board, ``/max_sensor_force`` (the count with the piston
pressed level with the housing) needs no roscore: press the piston fully a few times while it
reads. :func:`calibration_max` is the rule (pure); :func:`read_counts` and :func:`main` the shell.

    python -m hri_teleop.hardware.real.calibrate --port /dev/ttyACM0 --seconds 10
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Iterable, List, Optional

import serial

from hri_teleop.core.checks import is_count
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.serial_protocol import BAUD, MAX_COUNT, BoardStream, Sample, open_error_message

__all__ = ["CalibrateError", "calibration_max", "read_counts", "main"]


class CalibrateError(HriTeleopError, RuntimeError):
    """The calibration could not read the board or got no usable sample (one line with the fix)."""


def calibration_max(counts: Iterable[int]) -> int:
    """The calibration value: the largest count seen.

    Refuses an empty reading (nothing to calibrate with) and a maximum of 0 (the piston was
    never pressed, or the FSR is not connected: /max_sensor_force must be > 0).
    """
    values = list(counts)
    if not values:
        raise CalibrateError("no samples to calibrate with: read the board for longer while pressing the piston")
    bad = [c for c in values if not is_count(c)]
    if bad:
        raise CalibrateError(f"counts must be integers 0..{MAX_COUNT}, got {bad[0]!r}; pass the board's raw counts")
    maximum = max(values)
    if maximum == 0:
        raise CalibrateError("every count was 0: press the piston fully while reading, and check the FSR's wiring "
                             "(A0, 5 V, 10 kOhm to GND)")
    return maximum


def read_counts(port: str, seconds: float, baud: int = BAUD) -> List[int]:
    """All counts the board sends in ``seconds`` (s) on ``port``, read with pyserial.

    Corrupt lines are skipped (the protocol's checksum); opening the port restarts an Uno,
    whose first line then comes after about 1.6 s of boot.
    """
    try:
        ser = serial.Serial(port, baud, timeout=0.05)
    except (serial.SerialException, OSError) as exc:
        raise CalibrateError(open_error_message(port, getattr(exc, "errno", None), str(exc), "--port ...")) from None
    stream = BoardStream()
    counts: List[int] = []
    try:
        ser.reset_input_buffer()
        deadline = time.monotonic() + float(seconds)
        while time.monotonic() < deadline:
            try:
                data = ser.read(max(1, ser.in_waiting))
            except (serial.SerialException, OSError) as exc:
                raise CalibrateError(f"lost the board on {port} while reading ({exc}): plug it back in and "
                                     "run the calibration again") from None
            for event in stream.feed(data):
                if isinstance(event, Sample):
                    counts.append(event.count)
    finally:
        ser.close()
    if not counts:
        raise CalibrateError(
            f"no valid line from {port} in {seconds:g} s ({stream.counters.corrupt} corrupt): is the fsr_serial "
            f"sketch on the board at {baud} baud? (with the rosserial sketch, use rostopic echo /pub_force)")
    return counts


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
