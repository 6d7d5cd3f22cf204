"""Ex. 11's calibration without ROS: the largest count the plain-serial board sends.

With the ``fsr_serial`` sketch on the board, ``/max_sensor_force`` (the count with the piston
pressed level with the housing) needs no roscore: press the piston fully a few times while it
reads. :func:`calibration_max` is the rule (pure), :func:`read_counts` the reading; the command is
:mod:`hri_teleop.apps.calibrate`:

    python -m hri_teleop.apps.calibrate --port /dev/ttyACM0 --seconds 10
"""

from __future__ import annotations

import time
from typing import Iterable, List

import serial

from hri_teleop.core.checks import is_count
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.serial_protocol import BAUD, MAX_COUNT, BoardStream, Sample, open_error_message

__all__ = ["CalibrateError", "calibration_max", "read_counts"]


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
