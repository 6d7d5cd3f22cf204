"""``make doctor`` in a notebook: the same checks, a table of ok / FAIL / note with the fix, and buttons for the walk.

The checks run as ``python -m hri_teleop.apps.doctor`` in a child process: its rospy node, pygame
and a simulated lab it may start at home never touch the kernel's own. The walk-through's
answers (skip, piston pressed, rumble felt) go to the child's standard input, as Enter would.
"""

from __future__ import annotations

import html
import os
import subprocess
import sys
import threading
from typing import Callable, List, Optional

import ipywidgets as widgets

from hri_teleop.core.doctor import FAIL, NOTE, OK, Finding

__all__ = ["Doctor", "findings_html", "DOCTOR_MODULE"]

DOCTOR_MODULE = "hri_teleop.apps.doctor"
_COLORS = {OK: "#1b7a1b", FAIL: "#b00020", NOTE: "#7a5b00"}


def findings_html(findings: List[Finding]) -> str:
    """The findings as an HTML table: status in colour, the item, what was found, and the fix."""
    rows = "".join(
        f'<tr><td style="color:{_COLORS[f.status]};font-weight:bold">{html.escape(f.status)}</td>'
        f"<td>{html.escape(f.item)}</td><td>{html.escape(f.detail)}</td>"
        f"<td><i>{html.escape(f.fix)}</i></td></tr>" for f in findings)
    return f"<table><tr><th></th><th>item</th><th>found</th><th>fix</th></tr>{rows}</table>"


class Doctor(widgets.VBox):
    """Run the station's checks from a notebook; with ``walk`` the pad and piston walk-through too."""

    def __init__(self, walk: bool = False, ports: Optional[List[str]] = None, autostart: bool = True,
                 python: str = sys.executable) -> None:
        self.findings: List[Finding] = []
        self.lines: List[str] = []
        self._python = python
        self._ports = list(ports or [])
        self._proc: Optional["subprocess.Popen[str]"] = None
        self._reader: Optional[threading.Thread] = None
        self.walk = widgets.Checkbox(value=walk, description="walk through pad and piston", indent=False)
        self.run_button = widgets.Button(description="Check again", icon="stethoscope")
        self.run_button.on_click(lambda _b: self.run())
        self.prompt = widgets.HTML()
        answers = (("Skip", ""), ("Piston pressed", "p"), ("Felt it", "y"), ("Not felt", "n"))
        self.answer_buttons = [self._answer_button(label, text) for label, text in answers]
        self.table = widgets.HTML()
        self.summary = widgets.HTML()
        super().__init__([widgets.HBox([self.run_button, self.walk]), self.table, self.prompt,
                          widgets.HBox(self.answer_buttons), self.summary])
        self._show_answers(False)
        if autostart:
            self.run()

    def _answer_button(self, label: str, text: str) -> widgets.Button:
        button = widgets.Button(description=label)
        button.on_click(lambda _b: self.answer(text))
        return button

    def _show_answers(self, shown: bool) -> None:
        for button in self.answer_buttons:
            button.layout.display = "" if shown else "none"

    def run(self) -> None:
        """Start the checks (the previous run, if any, is stopped first)."""
        self.close_run()
        self.findings, self.lines = [], []
        self.table.value, self.prompt.value = "", ""
        self.summary.value = "checking ..."
        argv = [self._python, "-m", DOCTOR_MODULE] + (["--walk"] if self.walk.value else [])
        for port in self._ports:
            argv += ["--port", port]
        self._proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                      text=True, bufsize=1, env=dict(os.environ), start_new_session=True)
        if not self.walk.value:
            assert self._proc.stdin is not None
            self._proc.stdin.close()  # nothing to answer: a stray read ends at once
        self._show_answers(self.walk.value)
        self._reader = threading.Thread(target=self._read, args=(self._proc, self._on_line), daemon=True)
        self._reader.start()

    def _read(self, proc: "subprocess.Popen[str]", on_line: Callable[[str], None]) -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            on_line(line.rstrip("\n"))
        proc.wait()
        self._show_answers(False)
        self.prompt.value = ""
        if proc.returncode not in (0, 1):
            self.summary.value = html.escape(f"the checks stopped (exit {proc.returncode}): {self.lines[-1:]}")

    def _on_line(self, line: str) -> None:
        self.lines.append(line)
        finding = Finding.from_line(line)
        if finding is not None:
            self.findings.append(finding)
            self.table.value = findings_html(self.findings)
        elif line.startswith("doctor:"):
            self.summary.value = html.escape(line)
        elif line.strip():
            self.prompt.value = f"<b>{html.escape(line.strip())}</b>"

    def answer(self, text: str) -> None:
        """What Enter (``""``: skip), p, y or n would say to the walk-through in a terminal."""
        proc = self._proc
        if proc is not None and proc.poll() is None and proc.stdin is not None:
            try:
                proc.stdin.write(text + "\n")
                proc.stdin.flush()
            except (BrokenPipeError, ValueError):
                pass

    def wait(self, timeout_s: float = 60.0) -> int:
        """Wait for the checks to end; their exit code (0: nothing to fix)."""
        assert self._proc is not None, "run() first"
        code = self._proc.wait(timeout=timeout_s)
        if self._reader is not None:
            self._reader.join(timeout=5)
        return code

    def close_run(self) -> None:
        proc, self._proc = self._proc, None
        if proc is not None and proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()

    def close(self) -> None:
        self.close_run()
        super().close()
