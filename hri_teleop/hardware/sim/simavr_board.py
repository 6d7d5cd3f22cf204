"""The compiled ``fsr_serial`` firmware on a simulated Uno (simavr), its A0 fed from the FSR model.

The sketch, the serial bridge and the calibration must be tested with the bytes a real board
sends, without a board: ``firmware/sim/uno_sim`` runs the very ELF image behind a pty
(firmware/README.md). Here :func:`force_profile` turns forces into A0 voltages through
:mod:`hri_teleop.core.fsr`, and :class:`SimulatedUno` starts, unplugs, replugs and stops it.

    python -m hri_teleop.apps.simavr_board --link /tmp/ttyFSR   # presses every few seconds
"""

from __future__ import annotations

import fcntl
import math
import os
import shutil
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, List, Optional, Sequence, Tuple

from hri_teleop.core.checks import is_calibration_count
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.fsr import (
    FSR402,
    PULLDOWN_OHM,
    SUPPLY_V,
    PowerLaw,
    count_to_force,
    force_to_resistance,
    resistance_to_voltage,
    voltage_to_count,
)
from hri_teleop.core.paths import FIRMWARE

__all__ = [
    "SimavrBoardError",
    "ProfilePoint",
    "force_profile",
    "press_forces",
    "staircase_forces",
    "write_profile",
    "toolchain_problem",
    "setup_installs_toolchain",
    "build_firmware",
    "SimulatedUno",
    "FIRMWARE_DIR",
    "FSR_SERIAL_ELF",
    "UNO_SIM",
]

FIRMWARE_DIR = FIRMWARE
FSR_SERIAL_ELF = FIRMWARE_DIR / "build" / "fsr_serial" / "fsr_serial.elf"
UNO_SIM = FIRMWARE_DIR / "build" / "sim" / "uno_sim"

#: What `make firmware` needs, and the Debian packages that bring it.
TOOLS = ("avr-gcc", "avr-g++", "avr-objcopy", "avr-size", "cc", "make")
HEADERS = (Path("/usr/share/arduino/hardware/arduino/avr/cores/arduino/Arduino.h"),
           Path("/usr/include/simavr/sim_avr.h"))
APT_PACKAGES = "gcc-avr avr-libc binutils-avr arduino-core-avr simavr libsimavr-dev gcc make"


class SimavrBoardError(HriTeleopError, RuntimeError):
    """The simulated board could not be built, started or driven (one line with the fix)."""


@dataclass(frozen=True)
class ProfilePoint:
    """From ``t_us`` (board time, µs) on, A0 is at ``microvolts``."""

    t_us: int
    microvolts: int

    @property
    def count(self) -> int:
        """The count the FSR model (and a real Uno's ADC) gives for this voltage."""
        return int(voltage_to_count(self.microvolts / 1e6))


def force_profile(times_s: Sequence[float], forces_n: Sequence[float], *, law: PowerLaw = FSR402,
                  pulldown_ohm: float = PULLDOWN_OHM, supply_v: float = SUPPLY_V) -> List[ProfilePoint]:
    """Profile points for forces (N) applied from the given times (s), through the FSR divider.

    Voltages are rounded *up* to whole microvolts, so that a force on the lower edge of an
    ADC step (e.g. ``count_to_force(700)``) keeps its count.
    """
    if len(times_s) != len(forces_n) or not len(times_s):
        raise SimavrBoardError(f"force_profile needs as many times as forces (got {len(times_s)} and "
                               f"{len(forces_n)}), at least one; pass matching sequences")
    points: List[ProfilePoint] = []
    last_us = -1
    for t_s, force in zip(times_s, forces_n):
        t_us = int(round(float(t_s) * 1e6))
        if t_us < max(last_us, 0):
            raise SimavrBoardError(f"profile times must be >= 0 and ascending, got {t_s!r} s after {last_us / 1e6} s; "
                                   "sort them")
        last_us = t_us
        volts = float(resistance_to_voltage(force_to_resistance(force, law), pulldown_ohm, supply_v))
        microvolts = min(int(math.ceil(volts * 1e6 - 1e-6)), int(round(supply_v * 1e6)))
        points.append(ProfilePoint(t_us=t_us, microvolts=max(0, microvolts)))
    return points


def staircase_forces(forces_n: Sequence[float], step_s: float) -> Tuple[List[float], List[float]]:
    """Each force held for ``step_s`` seconds, one after the other: (times in s, forces in N)."""
    if not step_s > 0:
        raise SimavrBoardError(f"step_s must be a positive duration in s, got {step_s!r}; e.g. 0.3")
    return [i * float(step_s) for i in range(len(forces_n))], [float(f) for f in forces_n]


def press_forces(max_count: int, period_s: float, *, press_fraction: float = 0.6, hold_s: float = 0.2,
                 step_s: float = 0.001) -> Tuple[List[float], List[float]]:
    """One smooth press of the piston per ``period_s``, held at the top for ``hold_s``.

    As in Ex. 11: the piston is pushed in (half a raised cosine, no jumps), held level with
    the housing, and released, over ``press_fraction`` of the period; then it rests. The top
    force is the smallest that reads ``max_count``, so a board sampling during the hold
    reports exactly ``max_count``. Sampled every ``step_s`` s. Returns (times in s, forces in N).
    """
    if not is_calibration_count(int(max_count)):
        raise SimavrBoardError(f"max_count must be a count in 1..1023, got {max_count!r}; e.g. 700")
    press_s = period_s * press_fraction
    if not (period_s > 0 and 0 < press_fraction <= 1 and 0 <= hold_s < press_s and 0 < step_s < period_s):
        raise SimavrBoardError("need period_s > 0, 0 < press_fraction <= 1, 0 <= hold_s < period_s * press_fraction "
                               "and 0 < step_s < period_s; e.g. period_s=2.0, press_fraction=0.6, hold_s=0.2")
    peak_n = float(count_to_force(int(max_count)))
    ramp_s = (press_s - hold_s) / 2.0
    times: List[float] = []
    forces: List[float] = []
    for i in range(int(round(period_s / step_s))):
        t_s = i * step_s
        if t_s < ramp_s:
            shape = 0.5 - 0.5 * math.cos(math.pi * t_s / ramp_s)
        elif t_s < ramp_s + hold_s:
            shape = 1.0
        elif t_s < press_s:
            shape = 0.5 + 0.5 * math.cos(math.pi * (t_s - ramp_s - hold_s) / ramp_s)
        else:
            shape = 0.0
        times.append(t_s)
        forces.append(peak_n * shape)
    return times, forces


def write_profile(points: Sequence[ProfilePoint], path: Path) -> Path:
    """The harness's ``--profile`` file: ``<t_us> <microvolts>`` per line."""
    path = Path(path)
    lines = ["# t_us microvolts (A0), written by hri_teleop.hardware.sim.simavr_board"]
    lines += [f"{p.t_us} {p.microvolts}" for p in points]
    path.write_text("\n".join(lines) + "\n")
    return path


def toolchain_problem() -> Optional[str]:
    """Why ``make firmware`` cannot run here, or None when it can."""
    missing = [t for t in TOOLS if shutil.which(t) is None] + [str(h) for h in HEADERS if not h.exists()]
    if not missing:
        return None
    return f"missing {', '.join(missing)}: run 'make setup' (Debian: sudo apt-get install {APT_PACKAGES})"


def setup_installs_toolchain() -> bool:
    """Whether ``make setup`` installs the firmware toolchain on this machine.

    It does on Debian and Ubuntu (apt-get) without ROS Noetic in /opt; on the lab PCs (ROS
    Noetic) it installs nothing from apt, so tests there skip what needs the toolchain.
    """
    return shutil.which("apt-get") is not None and not Path("/opt/ros/noetic/setup.sh").exists()


def build_firmware(timeout_s: float = 600.0) -> str:
    """``make -C firmware`` (incremental: a second call only checks); returns its output."""
    problem = toolchain_problem()
    if problem:
        raise SimavrBoardError(f"cannot build the firmware: {problem}")
    # One build at a time: two test workers (or two notebooks) running make in the same
    # build folder would overwrite each other's objects.
    lock_path = FIRMWARE_DIR / "build" / ".build.lock"
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        proc = subprocess.run(["make", "--no-print-directory", "-C", str(FIRMWARE_DIR)], capture_output=True,
                              text=True, timeout=timeout_s)
    if proc.returncode != 0:
        tail = (proc.stdout + proc.stderr).strip().splitlines()[-5:]
        raise SimavrBoardError("make -C firmware failed: " + " | ".join(tail))
    return proc.stdout + proc.stderr


def _default_start(argv: List[str]) -> subprocess.Popen[bytes]:
    return subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, start_new_session=True)


class SimulatedUno:
    """The harness running ``firmware`` with its serial port at ``link``.

    ``start`` runs the program; pass e.g. ``lambda argv: master.run(argv, "uno_sim").popen``
    to have a :class:`hri_teleop.ros.master.PrivateMaster` own (and stop) the process.
    """

    def __init__(self, link: Path, profile: Optional[Path] = None, *, repeat_us: Optional[int] = None,
                 speed: float = 1.0, firmware: Path = FSR_SERIAL_ELF, harness: Path = UNO_SIM) -> None:
        self.link = Path(link)
        self.profile = profile
        self.repeat_us = repeat_us
        self.speed = speed
        self.firmware = Path(firmware)
        self.harness = Path(harness)
        self.process: Optional[subprocess.Popen[bytes]] = None

    def argv(self) -> List[str]:
        argv = [str(self.harness), "--firmware", str(self.firmware), "--link", str(self.link), "--quiet"]
        if self.profile is not None:
            argv += ["--profile", str(self.profile)]
        if self.repeat_us:
            argv += ["--repeat-us", str(int(self.repeat_us))]
        if self.speed != 1.0:
            argv += ["--speed", repr(float(self.speed))]
        return argv

    def start(self, start: Callable[[List[str]], subprocess.Popen[bytes]] = _default_start,
              timeout_s: float = 10.0) -> "SimulatedUno":
        for path, what in ((self.harness, "the simulated Uno"), (self.firmware, "the firmware")):
            if not path.exists():
                raise SimavrBoardError(f"{path} missing: build {what} with 'make firmware'")
        self.process = start(self.argv())
        self._wait(lambda: self.link.exists(), timeout_s, f"{self.link} to appear")
        return self

    def _wait(self, condition: Callable[[], bool], timeout_s: float, what: str) -> None:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if condition():
                return
            if self.process is not None and self.process.poll() is not None:
                raise SimavrBoardError(f"the simulated Uno exited ({self.process.returncode}) while waiting for {what}")
            time.sleep(0.01)
        raise SimavrBoardError(f"timed out after {timeout_s:g} s waiting for {what}")

    def _signal(self, sig: int) -> None:
        if self.process is None or self.process.poll() is not None:
            raise SimavrBoardError("the simulated Uno is not running: start() it first")
        os.kill(self.process.pid, sig)

    def unplug(self, timeout_s: float = 5.0) -> None:
        """Pull the USB cable: the port closes and vanishes, the board stops."""
        self._signal(signal.SIGUSR1)
        self._wait(lambda: not os.path.lexists(self.link), timeout_s, f"{self.link} to go away")

    def plug(self, timeout_s: float = 5.0) -> None:
        """Plug it back in: the port reappears at the same path, the board starts from reset."""
        self._signal(signal.SIGUSR2)
        self._wait(lambda: self.link.exists(), timeout_s, f"{self.link} to come back")

    def stop(self, timeout_s: float = 5.0) -> Optional[int]:
        if self.process is None:
            return None
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        return self.process.returncode

    def __enter__(self) -> "SimulatedUno":
        return self.start() if self.process is None else self

    def __exit__(self, *exc: object) -> None:
        self.stop()
