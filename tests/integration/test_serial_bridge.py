"""serial_bridge.py on a private roscore, fed by a scripted board on a pseudo-terminal: corrupt
and lost lines are counted and skipped, only checked counts reach /pub_force; a missing port
is one line naming the cause and the fix. (The real firmware on a simulated Uno, unplugged
and replugged, is tests/integration/test_firmware_hil.py.)"""

from __future__ import annotations

import os
import threading
import time
import tty
from pathlib import Path

import pytest

from hri_teleop.core.serial_protocol import format_line
from hri_teleop.ros.bags import read_topics

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
BRIDGE = REPO / "hri_lab" / "scripts" / "serial_bridge.py"

GOOD_COUNTS = set(range(100, 120))
CORRUPT_COUNT = 999


def _script_cycle(start_seq: int):
    """20 sample slots: 16 good lines, 2 corrupt (bad checksum, garbage), 2 never sent (lost)."""
    lines = []
    for i in range(20):
        seq = (start_seq + i) % 65536
        count = 100 + i
        if i == 5:
            good = format_line(seq, CORRUPT_COUNT)
            wrong = int(good[-3:-1], 16) ^ 0x5A
            lines.append(good[:-3] + b"%02X\n" % wrong)                    # wrong checksum
        elif i == 11:
            lines.append(b"\xff\xfe\x02\x00\xfd\x07\x00\x10\x00" + b"\n")    # a rosserial frame
        elif i in (15, 16):
            continue                                                      # lost
        else:
            lines.append(format_line(seq, count))
    return lines


class ScriptedBoard:
    """A pseudo-terminal whose far end sends the script at about 200 lines per second."""

    def __init__(self) -> None:
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        os.set_blocking(self.master, False)
        self.port = os.ttyname(self.slave)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        seq = 0
        while not self._stop.is_set():
            for line in _script_cycle(seq):
                try:
                    os.write(self.master, line)
                except BlockingIOError:
                    pass  # nobody reads yet: a real board's USB chip drops it too
                time.sleep(0.005)
            seq += 20

    def __enter__(self) -> "ScriptedBoard":
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(5)
        os.close(self.master)
        os.close(self.slave)


def test_only_checked_counts_reach_pub_force_and_bad_lines_are_counted(ros_master, tmp_path):
    with ScriptedBoard() as board:
        bridge = ros_master.run([str(BRIDGE), f"_port:={board.port}", "_log_every_s:=0.5"], "serial_bridge")
        ros_master.wait_for(lambda: bool(ros_master.publishers("/pub_force")) or not bridge.running, 20,
                            "serial_bridge to advertise /pub_force")
        assert bridge.running, bridge.output()
        recorder = ros_master.record(tmp_path / "bridge.bag", ["/pub_force"])
        # Two more corrupt-line reports while recording: two cycles of the script (20 lines, 16 good) at least.
        reports = bridge.output().count("corrupt line(s) skipped")
        ros_master.wait_for(lambda: bridge.output().count("corrupt line(s) skipped") >= reports + 2
                            or not bridge.running, 30, "two corrupt-line reports while recording")
        recorder.stop()
        bridge.stop()
    counts = [int(m.data) for _, m in read_topics(tmp_path / "bridge.bag", ["/pub_force"])["/pub_force"]]
    assert len(counts) >= 16, f"{len(counts)} counts recorded over two cycles of the script"
    assert set(counts) <= GOOD_COUNTS, sorted(set(counts) - GOOD_COUNTS)
    out = bridge.output()
    report = next(ln for ln in out.splitlines() if "corrupt line(s) skipped" in ln)
    assert "line(s) lost" in report and "check the USB cable" in report, report
    assert "Traceback" not in out, out
    # The shutdown summary: 2 corrupt and 2 lost lines in every 20.
    summary = next(ln for ln in out.splitlines() if "board restarts" in ln)
    samples, lost, corrupt = (int(summary.split(word)[0].split()[-1]) for word in (" samples", " lost", " corrupt"))
    assert corrupt * 8 == pytest.approx(samples, rel=0.1) and lost == pytest.approx(corrupt * 2, abs=4), summary


def test_a_missing_port_is_one_line_naming_the_cause_and_the_fix(ros_master, tmp_path):
    port = tmp_path / "ttyACM0"
    bridge = ros_master.run([str(BRIDGE), f"_port:={port}"], "serial_bridge")
    code = bridge.wait(20)
    out = bridge.output()
    assert code == 1, out
    assert "Traceback" not in out, out
    lines = [ln for ln in out.splitlines() if str(port) in ln]
    assert len(lines) == 1, out
    assert f"no serial port {port}: plug the board in or pass port:=..." in lines[0]


def test_a_bad_parameter_is_one_line_naming_it(ros_master):
    bridge = ros_master.run([str(BRIDGE), "_reconnect_s:=-1"], "serial_bridge")
    code = bridge.wait(20)
    out = bridge.output()
    assert code == 1, out
    assert "Traceback" not in out, out
    assert "/serial_bridge/reconnect_s is -1.0" in out, out
