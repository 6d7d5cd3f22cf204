"""A student node's crash as the student should see it: the traceback's frames in their own files.

A node's output holds Python's traceback with the grader's absolute paths, rospy's own frames and,
for an exception in a subscriber's callback, rospy's "bad callback" line (the node lives on, the
callback's work is lost). :func:`find_crash` keeps the last traceback's frames that lie in the
student's package, named relative to it; :func:`is_template` tells a deliverable handed in unfilled.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import List, Optional, Tuple

__all__ = ["Frame", "Crash", "find_crash", "crash_text", "is_template", "NOT_JUDGED_CRASH"]

#: The reason on every part that needs what a crashed node would have done.
NOT_JUDGED_CRASH = "the node crashed (see above)"

_TRACEBACK = "Traceback (most recent call last):"
_FRAME = re.compile(r'^\s*File "(?P<path>[^"]+)", line (?P<line>\d+), in (?P<function>\S+)\s*$')
_CARETS = re.compile(r"^\s*[\^~]+\s*$")
_BAD_CALLBACK = re.compile(r"bad callback: <bound method (?P<method>[\w.]+) of|bad callback: <function (?P<function>\w+)")
#: The grader's workspace lays the student's package out as .../ws/<package>/...
_PACKAGE_IN_WORKSPACE = re.compile(r"/ws/(?:hri_lab|ros_intro)/(?P<relative>.+)$")
#: How many of the student's frames are shown (the last ones: where it raised).
SHOWN_FRAMES = 3


@dataclass(frozen=True)
class Frame:
    """One frame of the student's own code: the file relative to their package, the line, the function
    and its source line."""

    file: str
    line: int
    function: str
    source: str


@dataclass(frozen=True)
class Crash:
    """``error``: the exception line (``NameError: name 'x' is not defined``); ``frames``: the student's
    own, outermost first; ``callback``: the method rospy called (the node kept running) or ''."""

    error: str
    frames: Tuple[Frame, ...]
    callback: str = ""

    @property
    def exception(self) -> str:
        """The exception's class name (``NameError``)."""
        return self.error.split(":", 1)[0].strip()

    @property
    def unfilled(self) -> bool:
        """A part left as the template has it (``# YOUR CODE HERE`` / ``raise NotImplementedError()``)."""
        return self.exception.endswith("NotImplementedError")


def _relative(path: str, package_dir: str) -> Optional[str]:
    """``path`` relative to the student's package, or None when it is not the student's file."""
    root = package_dir.rstrip("/")
    if root and path.startswith(root + "/"):
        return path[len(root) + 1:]
    match = _PACKAGE_IN_WORKSPACE.search(path)
    return match.group("relative") if match else None


#: Exceptions a node raises because it is being shut down (rospy's sleeps after a shutdown, Ctrl-C): not a crash.
_SHUTDOWN = ("ROSInterruptException", "KeyboardInterrupt")


def find_crash(output: str, package_dir: str = "") -> Optional[Crash]:
    """The last traceback in ``output`` (a process' last output) that is not one of a shutdown, or None."""
    text = str(output or "")
    end = len(text)
    while True:
        start = text.rfind(_TRACEBACK, 0, end)
        if start < 0:
            return None
        crash = _crash_at(text, start, package_dir)
        if crash is None or not crash.exception.endswith(_SHUTDOWN):
            return crash
        end = start  # rospy's shutdown: the crash, if any, came before it


def _crash_at(text: str, start: int, package_dir: str) -> Optional[Crash]:
    """The traceback that starts at ``start`` in ``text``; None when the text ends inside it."""
    before = text[max(0, start - 400):start].splitlines()[-2:]
    callback = ""
    for line in before:
        match = _BAD_CALLBACK.search(line)
        if match:
            callback = match.group("method") or match.group("function") or ""
    lines = text[start + len(_TRACEBACK):].splitlines()
    frames: List[Frame] = []
    error = ""
    i = 0
    while i < len(lines):
        line = lines[i]
        match = _FRAME.match(line)
        if match:
            source = ""
            if i + 1 < len(lines) and lines[i + 1].startswith("    ") and not _FRAME.match(lines[i + 1]):
                source = lines[i + 1].strip()
                i += 1
            relative = _relative(match.group("path"), package_dir)
            if relative is not None:
                frames.append(Frame(relative, int(match.group("line")), match.group("function"), source))
        elif line.strip() and not line.startswith(" ") and not _CARETS.match(line):
            error = line.strip()
            break
        i += 1
    if not error:
        return None  # the output ends inside the traceback: nothing to name
    return Crash(error[:300], tuple(frames), callback)


def crash_text(crash: Crash, what: str) -> str:
    """'<what> crashed: ...' with the student's frames and the error, one per line, for feedback."""
    if crash.callback:
        head = (f"{what} crashed in its callback {crash.callback}() (rospy prints the error and the node goes on "
                "without that message's work):")
    else:
        head = f"{what} crashed:"
    lines = [head]
    for frame in crash.frames[-SHOWN_FRAMES:]:
        lines.append(f"  {frame.file}, line {frame.line}, in {frame.function}")
        if frame.source:
            lines.append(f"    {frame.source[:200]}")
    if not crash.frames:
        lines.append("  (raised outside your files, by a call your code made)")
    lines.append(f"  {crash.error}")
    if crash.unfilled:
        lines.append("hint: a part marked YOUR CODE HERE still raises NotImplementedError: fill it in")
    return "\n".join(lines)


_UNFILLED = re.compile(r"#\s*YOUR CODE HERE\s*\n\s*raise NotImplementedError\(\)")


def is_template(student_text: str, template_text: str) -> bool:
    """The student's file still has every unfilled part of the template it was handed (and the template has one)."""
    want = len(_UNFILLED.findall(template_text))
    return want > 0 and len(_UNFILLED.findall(student_text)) >= want
