"""The Arduino sketches: their logic compiled on the host, and their build for the Uno.

* The rosserial sketch's logic (firmware/arduino_code_force_node/force_node.h) is compiled
  with g++ against the stand-ins for ros.h, std_msgs/Int16.h and Arduino.h in
  firmware/test/, and each scenario of firmware/test/test_force_node.cpp runs as a test.
* Every line the plain-serial sketch formats (firmware/fsr_serial/fsr_line.h) is parsed by
  the host's parser (hri_teleop.core.serial_protocol): the two ends of the protocol agree.
* Both sketches build for the ATmega328P with Debian's toolchain and fit the Uno.

Where the toolchain is missing: on machines where `make setup` installs it that is a
failure (run make setup); elsewhere (ROS Noetic lab PCs) the test skips and says why.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from hri_teleop.core.serial_protocol import Sample, crc8, parse_line
from hri_teleop.hardware.sim.simavr_board import (
    FIRMWARE_DIR,
    build_firmware,
    setup_installs_toolchain,
    toolchain_problem,
)

TEST_DIR = FIRMWARE_DIR / "test"

SCENARIOS = [
    "initializes_the_node_and_advertises_pub_force_once",
    "spins_on_every_pass_and_publishes_nothing_before_the_host_connects",
    "reads_the_period_parameter_once_after_connecting_and_publishes_at_it",
    "falls_back_to_the_handouts_300_ms_without_the_parameter",
    "refuses_a_period_outside_5_to_10000_ms_and_uses_300_ms",
    "publishes_the_reading_of_a0_taken_when_the_sample_is_due",
    "reads_the_parameter_again_after_a_reconnect",
    "keeps_its_period_across_the_millis_wraparound",
    "does_not_burst_after_a_long_stall",
]


def _missing(what: str) -> None:
    if setup_installs_toolchain():
        pytest.fail(f"{what}: run 'make setup'")
    pytest.skip(f"{what} (make setup installs no apt packages on this machine)")


def _compile(source: Path, out: Path, *includes: Path) -> Path:
    if shutil.which("g++") is None:
        _missing("g++ not found")
    flags = ["-std=gnu++11", "-Wall", "-Wextra", "-Werror"] + [f"-I{p}" for p in includes]
    proc = subprocess.run(["g++", *flags, str(source), "-o", str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return out


@pytest.fixture(scope="module")
def force_node_test(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("host") / "test_force_node"
    return _compile(TEST_DIR / "test_force_node.cpp", out, TEST_DIR, FIRMWARE_DIR / "arduino_code_force_node")


@pytest.fixture(scope="module")
def print_lines(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("host") / "print_lines"
    return _compile(TEST_DIR / "print_lines.cpp", out, FIRMWARE_DIR / "fsr_serial")


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_rosserial_sketch_logic(force_node_test, scenario):
    proc = subprocess.run([str(force_node_test), scenario], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.strip() == f"ok {scenario}"


def test_every_host_scenario_is_run_here(force_node_test):
    proc = subprocess.run([str(force_node_test), "--list"], capture_output=True, text=True, timeout=60)
    assert proc.stdout.split() == SCENARIOS


def test_every_line_the_sketch_formats_is_parsed_back_by_the_host(print_lines):
    pairs = [(s, c) for s in (0, 1, 9, 10, 99, 100, 999, 1000, 9999, 10000, 54321, 65535)
             for c in (0, 1, 9, 10, 99, 100, 517, 999, 1000, 1023)]
    pairs += [(s, s % 1024) for s in range(0, 65536, 97)]
    stdin = "".join(f"{s} {c}\n" for s, c in pairs)
    proc = subprocess.run([str(print_lines)], input=stdin.encode(), capture_output=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines(keepends=True)
    assert [parse_line(line) for line in lines] == [Sample(seq=s, count=c) for s, c in pairs]


def test_the_sketch_sends_a_count_above_1023_as_1023(print_lines):
    proc = subprocess.run([str(print_lines)], input=b"5 2000\n", capture_output=True, timeout=60)
    assert proc.stdout == b"F 5 1023 %02X\n" % crc8(b"F 5 1023")


@pytest.fixture(scope="module")
def firmware_build() -> str:
    problem = toolchain_problem()
    if problem:
        _missing(problem)
    return build_firmware()


def _sizes(output: str):
    found = {}
    for m in re.finditer(r"^(\w+): flash (\d+) of 32768 bytes .*?, RAM (\d+) of 2048 bytes", output, re.M):
        found[m.group(1)] = (int(m.group(2)), int(m.group(3)))
    return found


def test_the_plain_serial_sketch_builds_for_the_uno_and_fits(firmware_build):
    sizes = _sizes(firmware_build)
    assert "fsr_serial" in sizes, firmware_build
    flash, ram = sizes["fsr_serial"]
    assert 0 < flash <= 32256, f"fsr_serial needs {flash} B of flash"
    # Static RAM; the stack and Serial's buffers at run time need room beside it.
    assert 0 < ram <= 1024, f"fsr_serial needs {ram} B of static RAM"
    assert (FIRMWARE_DIR / "build" / "fsr_serial" / "fsr_serial.hex").exists()


def test_the_rosserial_sketch_builds_or_is_skipped_in_one_line_naming_ros_lib(firmware_build, tmp_path):
    sizes = _sizes(firmware_build)
    skipped = [ln for ln in firmware_build.splitlines() if ln.startswith("arduino_code_force_node: skipped")]
    assert ("arduino_code_force_node" in sizes) != bool(skipped), firmware_build
    if "arduino_code_force_node" in sizes:
        flash, ram = sizes["arduino_code_force_node"]
        assert flash <= 32256 and ram <= 2048
    # Without ros_lib: one line that names the library and how to make it, and success.
    proc = subprocess.run(["make", "--no-print-directory", "-C", str(FIRMWARE_DIR), f"ROS_LIB={tmp_path}/none",
                           f"BUILD={tmp_path}/build", "force_node"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.strip().splitlines()
    assert len(lines) == 1 and "no rosserial Arduino library" in lines[0] and "make_libraries.py" in lines[0]
