"""The late policy of ``make grade``: late.yaml read and checked, the rule, and submission times.

A late penalty changes a student's grade, so the rule is a pure function tested at each threshold
(:func:`judge_lateness`), each problem of late.yaml is one line naming the file, the key and the fix,
and a submission's time comes only from a source the student cannot write (:func:`submission_time`:
which ones, and why nbgrader's timestamp.txt and file times are not). Without one the time is unknown,
said to the instructor, and the total left blank until it is given. On Gradescope the grader takes no
penalty (Gradescope has the times, due dates and extensions). The formats: grading/README.md.
"""

from __future__ import annotations

import csv
import difflib
import importlib
import importlib.util
import math
import os
import pwd
import re
import stat
from dataclasses import dataclass, field
from datetime import date, datetime, timedelta, timezone, tzinfo
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.yamlfile import read_yaml
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular

__all__ = ["LateError", "Extension", "LatePolicy", "Lateness", "LATE_FILE", "KEYS", "read_late_policy",
           "parse_when", "judge_lateness", "submission_time", "parse_timestamp", "late_line", "duration_text",
           "when_text", "ALL_ASSIGNMENTS", "FEEDBACK_PREFIX", "SubmissionTime", "read_times", "student_stamp",
           "TIMES_COLUMNS", "STAMP_CAP_BYTES", "exchange_time"]

#: The default late policy file: beside the course (an nbgrader course's folder, else the submissions folder).
LATE_FILE = "late.yaml"
KEYS = ("deadline", "per_day", "count", "cap", "extensions", "times", "exchange")
#: The columns of the LMS export late.yaml's ``times:`` names (any order; other columns are ignored).
TIMES_COLUMNS = ("student", "assignment", "submitted_at")
#: The most of a submitted timestamp.txt the grader reads (nbgrader writes about 26 bytes).
STAMP_CAP_BYTES = 1024
COUNTS = ("started", "fraction")
DAY_S = 86400.0
#: The key of an extension or deadline that holds for every assignment.
ALL_ASSIGNMENTS = "*"
#: Each line a late policy adds to a student's feedback.txt starts with this (a rerun replaces them).
FEEDBACK_PREFIX = "late policy"
_EXAMPLE = '"2026-12-01 23:59 Europe/Berlin"'
#: Time zone abbreviations nbgrader's timestamp.txt may carry (strftime's %Z), with their offset in hours.
_ABBREVIATIONS = {"UTC": 0, "GMT": 0, "Z": 0, "WET": 0, "WEST": 1, "BST": 1, "CET": 1, "CEST": 2, "EET": 2,
                  "EEST": 3, "EST": -5, "EDT": -4, "CST": -6, "CDT": -5, "MST": -7, "MDT": -6, "PST": -8, "PDT": -7}
_OFFSET = re.compile(r"^([+-])(\d{2}):?(\d{2})$")


class LateError(HriTeleopError, ValueError):
    """late.yaml cannot be used as written (a key, a value, a missing time zone): one line with the file and the fix."""


@dataclass(frozen=True)
class Extension:
    """A student's own deadline: ``days`` added to the course's, or ``until`` instead of it."""

    days: float = 0.0
    until: Optional[datetime] = None


@dataclass(frozen=True)
class LatePolicy:
    """late.yaml, checked. ``deadlines``: assignment (or :data:`ALL_ASSIGNMENTS`) -> deadline, time-zone aware.

    ``per_day`` and ``cap`` are fractions of the assignment's points; ``count`` "started" counts every
    day begun after the deadline as a whole day, "fraction" counts days pro rata to the second.
    """

    source: str
    deadlines: Dict[str, datetime]
    per_day: float
    cap: float = 1.0
    count: str = "started"
    extensions: Dict[str, Dict[str, Extension]] = field(default_factory=dict)
    #: The LMS export's submission times: (student, assignment or :data:`ALL_ASSIGNMENTS`) -> when (None:
    #: the export's cell is blank); ``times_source`` names the file ("" without ``times:``).
    times: Dict[Tuple[str, str], Optional[datetime]] = field(default_factory=dict)
    times_source: str = ""
    #: nbgrader's exchange folder of the course (``<Exchange.root>/<course_id>``, "" when not given): its
    #: ``inbound/`` entries' change times (:func:`exchange_time`).
    exchange: str = ""

    def deadline_for(self, student: str, assignment: str) -> Tuple[datetime, bool]:
        """(the deadline that holds for ``student``'s ``assignment``, whether an extension moved it)."""
        base = self.deadlines.get(assignment, self.deadlines.get(ALL_ASSIGNMENTS))
        if base is None:
            raise LateError(f"{self.source}: deadline has no entry for assignment {assignment!r}; "
                            f"add `{assignment}: {_EXAMPLE}` under deadline")
        own = self.extensions.get(student, {})
        ext = own.get(assignment, own.get(ALL_ASSIGNMENTS))
        if ext is None:
            return base, False
        return (ext.until if ext.until is not None else base + timedelta(days=ext.days)), True


@dataclass(frozen=True)
class Lateness:
    """The late policy applied to one (student, assignment): when it came, how late, the penalty.

    ``late_s`` is 0 when on time; ``fraction`` is the penalty as a fraction of the points (capped);
    ``submitted`` None means the time is unknown (``problem`` says why) and nothing is taken.
    """

    student: str
    assignment: str
    submitted: Optional[datetime]
    source: str
    deadline: datetime
    extended: bool
    late_s: float
    days: float
    fraction: float
    problem: str = ""
    stamp_refused: bool = False   # the submission's timestamp.txt could not be read (a link, garbage): shown

    @property
    def late(self) -> bool:
        return self.late_s > 0

    @property
    def known(self) -> bool:
        """Whether the submission time came from a trusted source (else the penalty awaits the instructor)."""
        return self.submitted is not None

    def points(self, max_score: Optional[float]) -> float:
        """The points taken from an assignment worth ``max_score`` (0 when its points are unknown)."""
        return round(self.fraction * max_score, 6) if max_score else 0.0

    def to_dict(self) -> Dict[str, Any]:
        return {"student": self.student, "assignment": self.assignment,
                "submitted": self.submitted.isoformat() if self.submitted else None, "source": self.source,
                "deadline": self.deadline.isoformat(), "extended": self.extended, "late_s": self.late_s,
                "days": self.days, "fraction": self.fraction, "problem": self.problem,
                "stamp_refused": self.stamp_refused}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Lateness":
        submitted = datetime.fromisoformat(d["submitted"]) if d.get("submitted") else None
        return cls(d["student"], d["assignment"], submitted, d.get("source", ""),
                   datetime.fromisoformat(d["deadline"]), bool(d.get("extended")), float(d["late_s"]),
                   float(d["days"]), float(d["fraction"]), d.get("problem", ""), bool(d.get("stamp_refused")))


def judge_lateness(policy: LatePolicy, student: str, assignment: str, submitted: Optional[datetime],
                   source: str = "", problem: str = "", stamp_refused: bool = False) -> Lateness:
    """The rule: late is after the deadline (at it is on time); each day started costs ``per_day``
    (or each second its share with count "fraction"), never more than ``cap``; an extension moves the deadline.
    ``submitted`` None: the time is unknown (``problem`` says why); nothing is taken here, and the
    assignment's total stays blank until the instructor gives the time (:attr:`Lateness.known`)."""
    deadline, extended = policy.deadline_for(student, assignment)
    if submitted is None:
        return Lateness(student, assignment, None, source, deadline, extended, 0.0, 0.0, 0.0,
                        problem or "no submission time", stamp_refused)
    late_s = max(0.0, (submitted - deadline).total_seconds())
    days = math.ceil(late_s / DAY_S) if policy.count == "started" else late_s / DAY_S
    fraction = min(policy.cap, policy.per_day * days)
    return Lateness(student, assignment, submitted, source, deadline, extended, late_s, float(days), fraction,
                    "", stamp_refused)


def duration_text(seconds: float) -> str:
    """``90061`` -> ``"1 d 1 h 1 min"``; under a minute in seconds."""
    seconds = int(round(seconds))
    if seconds < 60:
        return f"{seconds} s"
    days, rest = divmod(seconds, 86400)
    hours, rest = divmod(rest, 3600)
    parts = [f"{days} d"] if days else []
    parts += [f"{hours} h"] if hours else []
    parts += [f"{rest // 60} min"] if rest // 60 else []
    return " ".join(parts)


def when_text(when: datetime, zone: Optional[tzinfo]) -> str:
    """``when`` as feedback and report show it: in ``zone`` (the deadline's), to the second."""
    return when.astimezone(zone).isoformat(sep=" ", timespec="seconds")


def late_line(lateness: Lateness, max_score: Optional[float], with_assignment: bool = False) -> str:
    """The one line a student's feedback gets: submitted when (from where), how late, the penalty."""
    head = FEEDBACK_PREFIX + (f", {lateness.assignment}" if with_assignment else "") + ": "
    deadline = when_text(lateness.deadline, lateness.deadline.tzinfo)
    own = " (your extension)" if lateness.extended else ""
    if lateness.submitted is None:
        return (f"{head}submission time unknown ({lateness.problem}); deadline {deadline}{own}; "
                "the penalty waits for the instructor")
    submitted = f"submitted {when_text(lateness.submitted, lateness.deadline.tzinfo)} ({lateness.source})"
    if not lateness.late:
        return f"{head}{submitted}, on time (deadline {deadline}{own}); no penalty"
    counted = (f"{lateness.days:g} day(s) started" if lateness.days == int(lateness.days)
               else f"{lateness.days:.2f} day(s)")
    taken = f"penalty {lateness.fraction:.0%}" + (f" of {max_score:g} points = {lateness.points(max_score):g}"
                                                   if max_score else " of the points")
    return (f"{head}{submitted}, {duration_text(lateness.late_s)} after the deadline {deadline}{own}: "
            f"{counted}, {taken}")


def _zone(name: str) -> Optional[tzinfo]:
    """An IANA zone (Europe/Berlin) or a fixed offset/abbreviation; None when unknown."""
    match = _OFFSET.match(name)
    if match:
        sign = -1 if match.group(1) == "-" else 1
        return timezone(sign * timedelta(hours=int(match.group(2)), minutes=int(match.group(3))))
    if name.upper() in _ABBREVIATIONS:
        return timezone(timedelta(hours=_ABBREVIATIONS[name.upper()]))
    try:  # zoneinfo is Python >= 3.9; on 3.8 write an offset
        zoneinfo = importlib.import_module("zoneinfo")
        found: tzinfo = zoneinfo.ZoneInfo(name)
        return found
    except (ImportError, ValueError, KeyError, OSError):
        return None


def parse_when(value: object) -> Union[datetime, str]:
    """A time-zone-aware datetime from late.yaml or timestamp.txt, or the reason it is not one.

    Accepted: ISO 8601 with an offset (``2026-12-01T23:59:00+01:00``, ``...Z``), or a date and time
    followed by a zone name, an abbreviation or an offset (``2026-12-01 23:59 Europe/Berlin``, nbgrader's
    ``2026-12-01 22:59:00.123456 UTC``).
    """
    if isinstance(value, datetime):
        return value if value.tzinfo is not None else "it has no time zone"
    if isinstance(value, date):
        return "it is a date without a time and time zone"
    if not isinstance(value, str) or not value.strip():
        return f"it is {value!r}, not a date and time"
    text = value.strip()
    try:
        parsed = datetime.fromisoformat(text[:-1] + "+00:00" if text.endswith("Z") else text)
    except ValueError:
        parsed = None
    if parsed is not None:
        return parsed if parsed.tzinfo is not None else "it has no time zone"
    head, _sep, name = text.rpartition(" ")
    if not head:  # one word, and not ISO 8601: no zone after a date and time
        return "it has no time zone"
    zone = _zone(name)
    if zone is None and "/" in name and importlib.util.find_spec("zoneinfo") is None:
        return f"zone names like {name!r} need Python 3.9 or later; write the offset instead, e.g. +01:00"
    if zone is None:
        return f"cannot read the time zone {name!r}"
    try:
        local = datetime.fromisoformat(head.strip())
    except ValueError:
        return "cannot read the date and time (write YYYY-MM-DD HH:MM[:SS])"
    return local.replace(tzinfo=zone) if local.tzinfo is None else local


def _when(value: object, source: str, key: str) -> datetime:
    parsed = parse_when(value)
    if isinstance(parsed, str):
        raise LateError(f"{source}: {key} {value!s:.60}: {parsed}; write e.g. {key.split('.')[0]}: {_EXAMPLE} "
                        "(quoted) or 2026-12-01T23:59:00+01:00")
    return parsed


def _fraction(value: object, source: str, key: str, example: str) -> float:
    text = str(value).strip()
    number: Optional[float] = None
    try:
        number = float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        pass
    if isinstance(value, bool) or number is None or not 0.0 <= number <= 1.0 or math.isnan(number):
        raise LateError(f"{source}: {key} must be a fraction of the points, 0..1 or 0%..100%, got {value!r}; "
                        f"write e.g. {key}: {example}")
    return number


def _extension(value: object, source: str, key: str) -> Extension:
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value >= 0:
        return Extension(days=float(value))
    if isinstance(value, str) and re.fullmatch(r"\s*\d+(\.\d+)?\s*(d|days?)?\s*", value):
        return Extension(days=float(re.sub(r"[^\d.]", "", value)))
    parsed = parse_when(value)
    if isinstance(parsed, str):
        raise LateError(f"{source}: {key} must be days added (e.g. 2) or the student's own deadline with its "
                        f"time zone, got {value!r} ({parsed}); write e.g. {key.split('.')[-1]}: 2")
    return Extension(until=parsed)


def _unknown_key(key: str, source: str, where: str, valid: Sequence[str]) -> LateError:
    close = difflib.get_close_matches(key, valid, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return LateError(f"{source}: unknown key {where}{key!r}; {hint}valid keys are {', '.join(valid)}")


def read_late_policy(path: Union[str, Path]) -> LatePolicy:
    """late.yaml checked into a :class:`LatePolicy`; :class:`LateError` (one line: file, key, fix) otherwise."""
    source = str(path)
    data = read_yaml(path, LateError, what="late policy",
                     missing_fix="give LATE=path/to/late.yaml or put late.yaml beside the course (grading/README.md)")
    if not isinstance(data, dict):
        raise LateError(f"{source}: expected `key: value` lines ({', '.join(KEYS)}), got {type(data).__name__}; "
                        f"write e.g. deadline: {_EXAMPLE}")
    for key in data:
        if key not in KEYS:
            raise _unknown_key(str(key), source, "", KEYS)
    if "deadline" not in data:
        raise LateError(f"{source}: no deadline; add deadline: {_EXAMPLE}")
    if "per_day" not in data:
        raise LateError(f"{source}: no per_day (the penalty per day late); add e.g. per_day: 10%")
    raw = data["deadline"]
    if isinstance(raw, dict):
        deadlines = {str(a): _when(v, source, f"deadline.{a}") for a, v in raw.items()}
    else:
        deadlines = {ALL_ASSIGNMENTS: _when(raw, source, "deadline")}
    count = data.get("count", "started")
    if count not in COUNTS:
        raise LateError(f"{source}: count must be started (every day begun counts whole) or fraction "
                        f"(pro rata), got {count!r}; write count: started")
    extensions: Dict[str, Dict[str, Extension]] = {}
    raw_ext = data.get("extensions") or {}
    if not isinstance(raw_ext, dict):
        raise LateError(f"{source}: extensions must map students to days or deadlines, got {raw_ext!r}; "
                        "write e.g. extensions: {alice: 2}")
    for student, value in raw_ext.items():
        if isinstance(value, dict):
            extensions[str(student)] = {str(a): _extension(v, source, f"extensions.{student}.{a}")
                                        for a, v in value.items()}
        else:
            extensions[str(student)] = {ALL_ASSIGNMENTS: _extension(value, source, f"extensions.{student}")}
    times: Dict[Tuple[str, str], Optional[datetime]] = {}
    times_source = ""
    if data.get("times") is not None:
        if not isinstance(data["times"], str) or not data["times"].strip():
            raise LateError(f"{source}: times must be the path of the LMS export of submission times, got "
                            f"{data['times']!r}; write e.g. times: submitted-at.csv")
        times_path = Path(path).parent / data["times"].strip()
        times, times_source = read_times(times_path), str(times_path)
    exchange = ""
    if data.get("exchange") is not None:
        folder = Path(path).parent / str(data["exchange"]).strip()
        if not isinstance(data["exchange"], str) or not (folder / "inbound").is_dir():
            raise LateError(f"{source}: exchange {data['exchange']!r:.80} is not nbgrader's exchange folder of the "
                            "course (no inbound/ in it); write e.g. exchange: /srv/nbgrader/exchange/task4")
        exchange = str(folder)
    return LatePolicy(source, deadlines, _fraction(data["per_day"], source, "per_day", "10%"),
                      _fraction(data.get("cap", 1.0), source, "cap", "50%"), count, extensions, times, times_source,
                      exchange)


def _times_error(source: str, where: str, problem: str) -> LateError:
    return LateError(f"{source}{where}: {problem}; write a CSV with the header {','.join(TIMES_COLUMNS)} and rows "
                     "like alice,lab,2026-12-01T23:40:00+01:00 (grading/README.md, Late policy)")


def read_times(path: Union[str, Path]) -> Dict[Tuple[str, str], Optional[datetime]]:
    """The LMS export: (student, assignment) -> submitted_at, from a CSV with the columns :data:`TIMES_COLUMNS`.

    An assignment of ``*`` or blank holds for every assignment of that student (plain folders: their one
    submission); a blank submitted_at is a row without a time (that student's time stays unknown).
    :class:`LateError` in one line naming the file, the row and the fix otherwise."""
    source = str(path)
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = list(csv.reader(fh))
    except FileNotFoundError:
        raise LateError(f"submission times not found: {source}; give late.yaml's times: the path of the LMS "
                        "export (relative to late.yaml)") from None
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise _times_error(source, "", f"cannot read it ({type(exc).__name__})") from None
    header = [c.strip().lower() for c in (rows[0] if rows else [])]
    missing = [c for c in TIMES_COLUMNS if c not in header]
    if missing:
        raise _times_error(source, ":1", f"no column {', '.join(missing)} in the header")
    index = {c: header.index(c) for c in TIMES_COLUMNS}
    times: Dict[Tuple[str, str], Optional[datetime]] = {}
    for number, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        cells = {c: (row[i].strip() if i < len(row) else "") for c, i in index.items()}
        student, assignment = cells["student"], cells["assignment"] or ALL_ASSIGNMENTS
        if not student:
            raise _times_error(source, f":{number}", "no student id")
        key = (student, assignment)
        if key in times:
            raise _times_error(source, f":{number}", f"a second row for {student}, {assignment}; keep one row per "
                               "student and assignment: the time of the submission you grade")
        when: Optional[datetime] = None
        if cells["submitted_at"]:
            parsed = parse_when(cells["submitted_at"])
            if isinstance(parsed, str):
                raise _times_error(source, f":{number}", f"submitted_at {cells['submitted_at']!r:.60}: {parsed}")
            when = parsed
        times[key] = when
    return times


def parse_timestamp(data: bytes, name: str = "timestamp.txt") -> Union[datetime, str]:
    """The time in the bytes of an nbgrader ``timestamp.txt`` (no zone: UTC, as nbgrader reads it), or why not.

    The reason never quotes the file: a student wrote it."""
    text = data.decode("utf-8", errors="replace").strip()
    if not text:
        return f"{name} is empty"
    parsed = parse_when(text) if len(text) <= 64 and "\n" not in text else "too long"
    if parsed == "it has no time zone":
        parsed = parse_when(text + " UTC")
    return parsed if isinstance(parsed, datetime) else f"{name} does not hold a date and time"


def _stamp_paths(folder: Path) -> List[Path]:
    """``folder``/timestamp.txt, else each ``folder``/<sub>/timestamp.txt of a real sub-folder (no link)."""
    if os.path.lexists(folder / "timestamp.txt"):
        return [folder / "timestamp.txt"]
    try:
        entries = sorted(os.scandir(folder), key=lambda e: e.name)
    except OSError:
        return []
    return [Path(e.path) / "timestamp.txt" for e in entries
            if e.is_dir(follow_symlinks=False) and os.path.lexists(Path(e.path) / "timestamp.txt")]


def _refusal_words(exc: UntrustedFileError) -> str:
    """What was wrong with a submitted timestamp.txt, in the grader's words (no path a student named)."""
    text = str(exc)
    for words, said in (("is a link", "is a link (not followed)"), ("not a regular file", "is not a regular file"),
                        ("larger than", f"is larger than {STAMP_CAP_BYTES} bytes"),
                        ("is not a folder", "is not inside a folder")):
        if words in text:
            return said
    return "cannot be read"


def student_stamp(folder: Path) -> Tuple[str, bool]:
    """(what the submission's own timestamp.txt says, in the grader's words; whether it could not be read).

    ("", False) when there is none. Read only through :func:`read_regular` below ``folder`` (no link
    followed, regular files only, :data:`STAMP_CAP_BYTES`); its text is never repeated, only a time the
    grader parsed and writes itself. It decides nothing: the student's own ``nbgrader submit`` wrote it."""
    said: List[str] = []
    refused = False
    for path in _stamp_paths(folder):
        name = "timestamp.txt" if path.parent == folder else "a sub-folder's timestamp.txt"
        try:
            data = read_regular(path, STAMP_CAP_BYTES, root=folder)
        except UntrustedFileError as exc:
            said.append(f"{name} {_refusal_words(exc)}")
            refused = True
            continue
        except OSError:
            said.append(f"{name} cannot be read")
            refused = True
            continue
        parsed = parse_timestamp(data, name)
        if isinstance(parsed, datetime):
            said.append(f"{name} says {parsed.astimezone(timezone.utc).isoformat(sep=' ', timespec='seconds')}")
        else:
            said.append(parsed)
            refused = True
    if not said:
        return "", False
    return "the submission's " + "; ".join(said[:3]) + (" (not used)" if not refused else " (not used, shown to "
                                                                                              "the instructor)"), refused


@dataclass(frozen=True)
class SubmissionTime:
    """When a submission counts as handed in (None: unknown), from where, why unknown, and what the
    student's own timestamp.txt says beside it (``stamp``, never used to decide; ``refused``: it could not be read)."""

    when: Optional[datetime]
    source: str
    problem: str = ""
    stamp: str = ""
    refused: bool = False

    @property
    def shown_source(self) -> str:
        return self.source + (f"; {self.stamp}" if self.stamp and self.when is not None else "")

    @property
    def shown_problem(self) -> str:
        return self.problem + (f"; {self.stamp}" if self.stamp and self.when is None else "")


def _owners(student: str) -> Tuple[int, ...]:
    """The uids whose exchange entries count for ``student``: theirs (a user of this machine), root, the grader."""
    try:
        own: Tuple[int, ...] = (pwd.getpwnam(student).pw_uid,)
    except (KeyError, UnicodeEncodeError):
        own = ()
    return own + (0, os.geteuid())


def exchange_time(exchange: Path, student: str, assignment: str) -> Union[datetime, str]:
    """When ``student`` last handed ``assignment`` in through nbgrader's exchange, or why it is not known.

    ``nbgrader submit`` (run by the student) makes ``<exchange>/inbound/<student>+<assignment>+<time>[+<random>]``;
    the time in that name and the timestamp.txt inside are the student's own clock, but the folder's change
    time (ctime) is the file system's: its owner can only move it later (adding a file, a chmod), never back.
    So: the latest ctime of those folders (real folders, no link) owned by the student (or root, or the
    grader), the submission nbgrader collect takes by default being the newest. A folder under the student's
    name made by someone else is not counted. It holds only on the machine the students submitted to: a copy
    of the exchange has the copy's times."""
    inbound = exchange / "inbound"
    prefix = f"{student}+{assignment}+"
    owners = _owners(student)
    times: List[float] = []
    others = 0
    try:
        names = sorted(n for n in os.listdir(inbound) if n.startswith(prefix))
    except OSError as exc:
        return f"nbgrader's exchange {inbound} cannot be listed ({exc.strerror})"
    for name in names:
        try:
            st = os.lstat(inbound / name)
        except OSError:
            continue
        if not stat.S_ISDIR(st.st_mode):
            others += 1
        elif st.st_uid not in owners:
            others += 1
        else:
            times.append(st.st_ctime)
    if not times:
        extra = f" ({others} under that name made by another user or not a folder, not counted)" if others else ""
        return f"nbgrader's exchange has no submission of {student}, {assignment}{extra}"
    return datetime.fromtimestamp(max(times), timezone.utc)


def submission_time(policy: LatePolicy, student: str, assignment: str, folder: Path) -> SubmissionTime:
    """When ``student``'s ``assignment`` was handed in, from a source the student cannot write, in this order:

    1. the LMS export late.yaml names (``times:``, :func:`read_times`): the row of (student, assignment), else
       of (student, ``*``);
    2. nbgrader's exchange late.yaml names (``exchange:``): :func:`exchange_time`;
    else unknown. Nothing the student wrote decides: nbgrader's timestamp.txt, the time in its exchange
    folder's name and the gradebook's timestamp all come from the student's own ``nbgrader submit``, and
    file times from their machine (or from unpacking): file times are not looked at. The submission's
    timestamp.txt in ``folder`` is read (safely, :func:`student_stamp`) to be shown beside the trusted
    time, never used to decide."""
    stamp, refused = student_stamp(folder)
    name = Path(policy.times_source).name
    problems: List[str] = []
    if policy.times_source:
        for key in ((student, assignment), (student, ALL_ASSIGNMENTS)):
            if key in policy.times:
                when = policy.times[key]
                if when is not None:
                    return SubmissionTime(when, f"{name}, the LMS export", "", stamp, refused)
                problems.append(f"{name} has no time for {student}, {assignment}")
                break
        else:
            problems.append(f"{name} has no row for {student}, {assignment}")
    if policy.exchange:
        got = exchange_time(Path(policy.exchange), student, assignment)
        if isinstance(got, datetime):
            return SubmissionTime(got, "nbgrader's exchange (its inbound folder's change time)", "", stamp, refused)
        problems.append(got)
    if not policy.times_source and not policy.exchange:
        problems.append(f"no source of submission times: {Path(policy.source).name} has neither times: (the LMS "
                        "export) nor exchange: (nbgrader's exchange)")
    return SubmissionTime(None, "", "; ".join(problems), stamp, refused)
