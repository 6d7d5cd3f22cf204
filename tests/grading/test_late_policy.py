"""The late policy: the rule at each threshold, late.yaml's one-line errors, and where submission times come from."""

from __future__ import annotations

import os
from datetime import datetime, timedelta, timezone
from pathlib import Path

import pytest

from hri_teleop.grading.batch.late import (
    ALL_ASSIGNMENTS,
    Extension,
    LateError,
    Lateness,
    LatePolicy,
    duration_text,
    judge_lateness,
    late_line,
    parse_timestamp,
    parse_when,
    read_late_policy,
    read_times,
    submission_time,
)

CET = timezone(timedelta(hours=1))
DEADLINE = datetime(2026, 12, 1, 23, 59, tzinfo=CET)
S = timedelta(seconds=1)
DAY = timedelta(days=1)


def _policy(**kw) -> LatePolicy:
    args = dict(source="late.yaml", deadlines={ALL_ASSIGNMENTS: DEADLINE}, per_day=0.1, cap=0.5, count="started")
    args.update(kw)
    return LatePolicy(**args)


@pytest.mark.parametrize("submitted, late_s, days, fraction", [
    (DEADLINE - S, 0, 0, 0.0),                # one second before: on time
    (DEADLINE, 0, 0, 0.0),                    # at the deadline: on time
    (DEADLINE + S, 1, 1, 0.1),                # one second after: a day started
    (DEADLINE + DAY, 86400, 1, 0.1),          # exactly one day after: still the first day
    (DEADLINE + DAY + S, 86401, 2, 0.2),      # a second into the second day
    (DEADLINE + 9 * DAY, 9 * 86400, 9, 0.5),  # the cap
])
def test_lateness_counts_every_day_started_at_each_threshold(submitted, late_s, days, fraction):
    got = judge_lateness(_policy(), "alice", "lab", submitted, "timestamp.txt")
    assert (got.late_s, got.days, got.late) == (late_s, days, late_s > 0)
    assert got.fraction == pytest.approx(fraction)


def test_lateness_pro_rata_counts_fractions_of_a_day():
    got = judge_lateness(_policy(count="fraction"), "alice", "lab", DEADLINE + DAY / 2)
    assert got.days == pytest.approx(0.5) and got.fraction == pytest.approx(0.05)


def test_an_extension_moves_the_deadline_by_days_or_to_a_date():
    policy = _policy(extensions={"bob": {ALL_ASSIGNMENTS: Extension(days=2)},
                                 "cleo": {"lab": Extension(until=DEADLINE + 3 * DAY)}})
    on_time = judge_lateness(policy, "bob", "lab", DEADLINE + 2 * DAY)  # at his own deadline
    assert not on_time.late and on_time.extended and on_time.deadline == DEADLINE + 2 * DAY
    late = judge_lateness(policy, "bob", "lab", DEADLINE + 2 * DAY + S)
    assert late.days == 1 and late.fraction == pytest.approx(0.1)
    assert not judge_lateness(policy, "cleo", "lab", DEADLINE + 3 * DAY).late
    assert judge_lateness(policy, "cleo", "preparation", DEADLINE + S).days == 1  # her extension is the lab's only
    assert judge_lateness(policy, "alice", "lab", DEADLINE + 2 * DAY).days == 2  # nobody else's


def test_an_unknown_submission_time_takes_nothing_itself_and_says_the_penalty_waits():
    got = judge_lateness(_policy(), "alice", "lab", None, problem="no files in x")
    assert got.fraction == 0 and not got.late and not got.known
    assert "submission time unknown (no files in x)" in late_line(got, 55)
    assert late_line(got, 55).endswith("the penalty waits for the instructor")


def test_the_feedback_line_says_when_how_late_and_the_penalty():
    got = judge_lateness(_policy(), "alice", "lab", DEADLINE + timedelta(hours=9, minutes=15), "timestamp.txt")
    line = late_line(got, 55.0, with_assignment=True)
    assert line == ("late policy, lab: submitted 2026-12-02 09:14:00+01:00 (timestamp.txt), 9 h 15 min after the "
                    "deadline 2026-12-01 23:59:00+01:00: 1 day(s) started, penalty 10% of 55 points = 5.5")
    assert "\n" not in line
    on_time = late_line(judge_lateness(_policy(), "alice", "lab", DEADLINE, "file times"), 10)
    assert on_time.endswith("on time (deadline 2026-12-01 23:59:00+01:00); no penalty") and "(file times)" in on_time


@pytest.mark.parametrize("seconds, text", [(59, "59 s"), (59.6, "1 min"), (60, "1 min"), (61, "1 min"), (119, "1 min"),
                                           (120, "2 min"), (3600, "1 h"), (3660, "1 h 1 min"), (86399, "23 h 59 min"),
                                           (86400, "1 d"), (86460, "1 d 1 min"), (90061, "1 d 1 h 1 min")])
def test_a_duration_reads_in_days_hours_and_minutes_and_under_a_minute_in_seconds(seconds, text):
    assert duration_text(seconds) == text


def test_the_feedback_line_names_the_assignment_and_the_extension_only_when_asked():
    got = judge_lateness(_policy(extensions={"alice": {ALL_ASSIGNMENTS: Extension(days=1)}}), "alice", "lab",
                         DEADLINE + DAY + S, "timestamp.txt")
    line = late_line(got, None)
    assert line.startswith("late policy: submitted ") and "(your extension)" in line
    assert line.endswith("1 s after the deadline 2026-12-02 23:59:00+01:00 (your extension): 1 day(s) started, "
                         "penalty 10% of the points")
    plain = late_line(judge_lateness(_policy(), "bob", "lab", DEADLINE + S, "timestamp.txt"), 10)
    assert "(your extension)" not in plain and plain.startswith("late policy: ")
    pro_rata = judge_lateness(_policy(count="fraction"), "bob", "lab", DEADLINE + DAY / 2, "file times")
    assert "0.50 day(s), penalty 5% of 10 points = 0.5" in late_line(pro_rata, 10)


def test_every_field_of_a_lateness_survives_its_json_form():
    got = judge_lateness(_policy(extensions={"alice": {ALL_ASSIGNMENTS: Extension(days=1)}}), "alice", "lab",
                         DEADLINE + DAY + S, "timestamp.txt")
    assert got.extended and Lateness.from_dict(got.to_dict()) == got
    unknown = judge_lateness(_policy(), "bob", "lab", None, problem="no files in x")
    assert unknown.to_dict()["submitted"] is None and Lateness.from_dict(unknown.to_dict()) == unknown
    assert Lateness.from_dict(unknown.to_dict()).problem == "no files in x"
    minimal = {k: v for k, v in got.to_dict().items() if k not in ("source", "extended", "problem")}
    assert (Lateness.from_dict(minimal).source, Lateness.from_dict(minimal).extended,
            Lateness.from_dict(minimal).problem) == ("", False, "")


def test_points_taken_are_rounded_to_a_millionth():
    third = judge_lateness(_policy(count="fraction", per_day=1.0, cap=1.0), "a", "lab", DEADLINE + DAY / 3)
    assert third.points(10) == 3.333333


def test_lateness_survives_its_json_form():
    got = judge_lateness(_policy(), "alice", "lab", DEADLINE + S, "timestamp.txt")
    assert Lateness.from_dict(got.to_dict()) == got
    assert got.points(55) == 5.5 and got.points(None) == 0.0


@pytest.mark.parametrize("text", ["2026-12-01T23:59:00+01:00", "2026-12-01 23:59 +01:00", "2026-12-01 23:59 CET",
                                  "2026-12-01 22:59:00.000000 UTC", "2026-12-01T22:59:00Z",
                                  "2026-12-01 23:59 Europe/Berlin"])
def test_deadlines_and_timestamps_name_their_time_zone(text):
    assert parse_when(text) == DEADLINE


UTC = timezone.utc


@pytest.mark.parametrize("text", ["2026-07-01 23:59 CEST", "2026-07-01 23:59 Europe/Berlin", "2026-07-01 23:59 +02:00",
                                  "2026-07-01T23:59:00+02:00", "2026-07-01 21:59 UTC"])
def test_a_summer_deadline_in_berlin_is_central_european_summer_time_two_hours_ahead_of_utc(text):
    assert parse_when(text) == datetime(2026, 7, 1, 21, 59, tzinfo=UTC)


# Python 3.8's datetime.fromisoformat (the lab PCs) takes no space before an offset: there every
# "date time offset" goes through late.py's own zone reading; on 3.11 only a form ISO 8601 does not know
# does (two spaces), so both are here.
@pytest.mark.parametrize("text", ["2026-12-01 18:59 -05:00", "2026-12-01 18:59 -0500", "2026-12-01T18:59:00-05:00",
                                  "2026-12-01 18:59  -05:00", "2026-12-01 18:59:00  -0500",
                                  "2026-12-01 18:59 EST", "2026-12-01 15:59 PST", "2026-12-01 17:59 CST"])
def test_a_time_with_a_negative_utc_offset_is_that_many_hours_behind_utc(text):
    assert parse_when(text) == datetime(2026, 12, 1, 23, 59, tzinfo=UTC)


@pytest.mark.parametrize("text, hours, minutes", [("2026-12-01 23:59 +05:30", 5, 30), ("2026-12-01 23:59 -03:30", -3, -30),
                                                  ("2026-12-01 23:59 +0545", 5, 45), ("2026-12-01 23:59  +05:30", 5, 30),
                                                  ("2026-12-01 23:59  -03:30", -3, -30)])
def test_an_offset_counts_its_minutes_with_the_sign_of_its_hours(text, hours, minutes):
    assert parse_when(text).utcoffset() == timedelta(hours=hours, minutes=minutes)


def test_a_summer_deadline_is_judged_in_summer_time(tmp_path):
    path = tmp_path / "late.yaml"
    path.write_text('deadline: "2026-07-01 23:59 Europe/Berlin"\nper_day: 10%\n')
    policy = read_late_policy(path)
    assert judge_lateness(policy, "alice", "lab", datetime(2026, 7, 1, 21, 59, tzinfo=UTC)).late_s == 0.0
    late = judge_lateness(policy, "alice", "lab", datetime(2026, 7, 1, 21, 59, 1, tzinfo=UTC))
    assert (late.late_s, late.days, late.fraction) == (1.0, 1.0, 0.1)  # one second into summer time's next day


def test_late_yaml_is_read_with_zones_percentages_and_extensions(tmp_path):
    path = tmp_path / "late.yaml"
    path.write_text('deadline:\n  preparation: "2026-11-24 08:00 Europe/Berlin"\n  lab: 2026-12-01T23:59:00+01:00\n'
                    "per_day: 10%\ncap: 0.5\ncount: fraction\n"
                    'extensions:\n  bob: 2\n  cleo: {lab: "2026-12-04 12:00 +01:00"}\n  dan: 1.5 days\n')
    policy = read_late_policy(path)
    assert policy.deadlines["lab"] == DEADLINE and policy.deadlines["preparation"].utcoffset() == timedelta(hours=1)
    assert (policy.per_day, policy.cap, policy.count) == (0.1, 0.5, "fraction")
    assert policy.extensions["bob"] == {ALL_ASSIGNMENTS: Extension(days=2)}
    assert policy.extensions["dan"][ALL_ASSIGNMENTS].days == 1.5
    assert policy.extensions["cleo"]["lab"].until == datetime(2026, 12, 4, 12, tzinfo=CET)


@pytest.mark.parametrize("text, words", [
    ("deadline: 2026-12-01 23:59:00\nper_day: 10%\n", ["deadline", "no time zone", "Europe/Berlin"]),
    ("deadline: 2026-12-01\nper_day: 10%\n", ["deadline", "without a time", "write e.g."]),
    ('deadline: "2026-12-01 23:59 Mars/Olympus"\nper_day: 10%\n', ["Mars/Olympus", "time zone"]),
    ('deadline: "2026-12-01 23:59 UTC"\nper_day: ten\n', ["per_day", "'ten'", "per_day: 10%"]),
    ('deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\ncap: 150%\n', ["cap", "150%", "cap: 50%"]),
    ('deadline: "2026-12-01 23:59 UTC"\nper_dya: 10%\n', ["unknown key 'per_dya'", "did you mean 'per_day'"]),
    ('per_day: 10%\n', ["no deadline", "add deadline:"]),
    ('deadline: "2026-12-01 23:59 UTC"\n', ["no per_day", "per_day: 10%"]),
    ('deadline: "2026-12-01 23:59 UTC"\nper_day: 1%\ncount: hours\n', ["count", "'hours'", "count: started"]),
    ('deadline: "2026-12-01 23:59 UTC"\nper_day: 1%\nextensions: {bob: soon}\n', ["extensions.bob", "'soon'"]),
    ("deadline: [1\n", ["late.yaml:2", "YAML syntax"]),
])
def test_a_bad_late_yaml_is_one_line_naming_the_file_the_key_and_the_fix(tmp_path, text, words):
    path = tmp_path / "late.yaml"
    path.write_text(text)
    with pytest.raises(LateError) as err:
        read_late_policy(path)
    message = str(err.value)
    assert "\n" not in message and str(path) in message
    for word in words:
        assert word in message, message


def test_a_missing_late_yaml_says_where_to_put_it(tmp_path):
    with pytest.raises(LateError, match="late policy not found: .*LATE=path/to/late.yaml"):
        read_late_policy(tmp_path / "late.yaml")


def test_a_per_assignment_deadline_names_the_assignment_it_lacks():
    with pytest.raises(LateError, match="no entry for assignment 'lab'; add `lab: "):
        judge_lateness(_policy(deadlines={"preparation": DEADLINE}), "alice", "lab", DEADLINE)


def test_a_zone_name_on_python_38_asks_for_an_offset(monkeypatch):
    import importlib.util

    from hri_teleop.grading.batch import late

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "zoneinfo" else real(name, *a))
    monkeypatch.setattr(late, "_zone", lambda name: None)  # as on 3.8: no zoneinfo module
    assert parse_when("2026-12-01 23:59 Europe/Berlin") == (
        "zone names like 'Europe/Berlin' need Python 3.9 or later; write the offset instead, e.g. +01:00")


# --- Where submission times come from: only the LMS export decides; the student's timestamp.txt is shown ---

TIMES_HEADER = "student,assignment,submitted_at\n"


def _course(tmp_path, rows: str, extra: str = "") -> LatePolicy:
    """late.yaml (deadline 2026-12-01 23:59 +01:00, 10 % a day, cap 50 %) naming the LMS export ``rows``."""
    (tmp_path / "submitted-at.csv").write_text(TIMES_HEADER + rows)
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\ncap: 50%\n'
                                        "times: submitted-at.csv\n" + extra)
    return read_late_policy(tmp_path / "late.yaml")


def _handed_in(tmp_path, student: str = "alice", stamp=None):
    folder = tmp_path / "submitted" / student / "lab"
    (folder / "hri_lab").mkdir(parents=True, exist_ok=True)
    if stamp is not None:
        (folder / "timestamp.txt").write_text(stamp)
    return folder


@pytest.mark.parametrize("at, days, fraction", [
    ("2026-12-01T23:58:59+01:00", 0, 0.0),   # a second before: on time
    ("2026-12-01T23:59:00+01:00", 0, 0.0),   # at the deadline: on time
    ("2026-12-01T23:59:01+01:00", 1, 0.1),   # a second after: a day started
    ("2026-12-02 22:59 UTC", 1, 0.1),        # exactly a day after, in another zone: still the first day
    ("2026-12-02T23:59:01+01:00", 2, 0.2),   # a second into the second day
    ("2026-12-05T23:59:01+01:00", 5, 0.5),   # five days started: 50 %, the cap exactly
    ("2026-12-09T23:59:01+01:00", 9, 0.5),   # nine days started: held at the cap
])
def test_the_lms_export_decides_the_penalty_at_each_threshold(tmp_path, at, days, fraction):
    policy = _course(tmp_path, f"alice,lab,{at}\n")
    got = submission_time(policy, "alice", "lab", _handed_in(tmp_path))
    assert got.when == parse_when(at) and got.source == "submitted-at.csv, the LMS export" and not got.problem
    lateness = judge_lateness(policy, "alice", "lab", got.when, got.shown_source)
    assert (lateness.days, lateness.known) == (days, True) and lateness.fraction == pytest.approx(fraction)
    assert "(submitted-at.csv, the LMS export)" in late_line(lateness, 55)


@pytest.mark.parametrize("stamp, shown", [
    ("2026-11-20 10:00:00.000000 UTC", "2026-11-20 10:00:00+00:00"),   # nbgrader's own format, a forged date
    ("2026-11-20 10:00:00", "2026-11-20 10:00:00+00:00"),              # no zone: read as UTC, as nbgrader does
    ("2026-12-01T23:59:00+01:00", "2026-12-01 22:59:00+00:00"),        # exactly the deadline
])
def test_a_forged_timestamp_never_lowers_the_penalty_and_is_shown_beside_the_trusted_time(tmp_path, stamp, shown):
    policy = _course(tmp_path, "alice,lab,2026-12-02T23:59:01+01:00\n")  # two days started: 20 %
    got = submission_time(policy, "alice", "lab", _handed_in(tmp_path, stamp=stamp))
    lateness = judge_lateness(policy, "alice", "lab", got.when, got.shown_source, got.shown_problem, got.refused)
    assert lateness.days == 2 and lateness.fraction == pytest.approx(0.2) and not lateness.stamp_refused
    assert f"(submitted-at.csv, the LMS export; the submission's timestamp.txt says {shown} (not used))" \
        in late_line(lateness, 55)


def test_a_timestamp_alone_decides_nothing_the_time_stays_unknown(tmp_path):
    policy = _course(tmp_path, "bob,lab,2026-12-01T20:00:00+01:00\n")  # alice has no row
    got = submission_time(policy, "alice", "lab", _handed_in(tmp_path, stamp="2026-11-20 10:00:00 UTC"))
    assert got.when is None and got.problem == "submitted-at.csv has no row for alice, lab"
    lateness = judge_lateness(policy, "alice", "lab", got.when, got.shown_source, got.shown_problem, got.refused)
    assert not lateness.known and "timestamp.txt says 2026-11-20 10:00:00+00:00 (not used)" in lateness.problem
    without = tmp_path / "no-times"
    without.mkdir()
    (without / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\n')
    bare = submission_time(read_late_policy(without / "late.yaml"), "carol", "lab", _handed_in(tmp_path, "carol"))
    assert bare.when is None and bare.problem == ("no source of submission times: late.yaml has neither times: (the LMS export) nor "
                                                  "exchange: (nbgrader's exchange)") and bare.stamp == ""


def _secret(tmp_path):
    secret = tmp_path / "shadow"
    secret.write_text("root:$6$SECRETHASH:19000:0:99999:7:::\n")
    secret.chmod(0o600)
    return secret


@pytest.mark.parametrize("kind, said", [
    ("link to a secret", "timestamp.txt is a link (not followed)"),
    ("link to a valid time", "timestamp.txt is a link (not followed)"),
    ("fifo", "timestamp.txt is not a regular file"),
    ("folder", "timestamp.txt is not a regular file"),
    ("10 MB", "timestamp.txt is larger than 1024 bytes"),
    ("markup", "timestamp.txt does not hold a date and time"),
    ("binary", "timestamp.txt does not hold a date and time"),
    ("empty", "timestamp.txt is empty"),
])
def test_a_timestamp_that_cannot_be_read_is_shown_never_followed_never_quoted_and_waives_nothing(tmp_path, kind, said):
    policy = _course(tmp_path, "alice,lab,2026-12-01T23:59:01+01:00\n")  # a second late: 10 %
    folder = _handed_in(tmp_path)
    stamp = folder / "timestamp.txt"
    if kind == "link to a secret":
        stamp.symlink_to(_secret(tmp_path))
    elif kind == "link to a valid time":
        (tmp_path / "elsewhere.txt").write_text("2026-11-01 10:00:00 UTC")
        stamp.symlink_to(tmp_path / "elsewhere.txt")
    elif kind == "fifo":
        os.mkfifo(stamp)  # a reader without O_NONBLOCK would wait for ever
    elif kind == "folder":
        stamp.mkdir()
    elif kind == "10 MB":
        stamp.write_bytes(b"2026-11-01 10:00:00 UTC" + b"A" * 10 * 1024 ** 2)
    elif kind == "markup":
        stamp.write_text("<script>alert('SECRETHASH')</script>")
    elif kind == "binary":
        stamp.write_bytes(b"\x00\xff\xfeSECRETHASH\x1b[2J")
    else:
        stamp.write_text("")
    got = submission_time(policy, "alice", "lab", folder)
    assert got.refused and got.stamp == f"the submission's {said} (not used, shown to the instructor)"
    lateness = judge_lateness(policy, "alice", "lab", got.when, got.shown_source, got.shown_problem, got.refused)
    assert lateness.days == 1 and lateness.fraction == pytest.approx(0.1) and lateness.stamp_refused
    line = late_line(lateness, 55)
    assert "\n" not in line and "SECRETHASH" not in line and "<script" not in line and "AAAA" not in line, line
    assert said in line
    assert Lateness.from_dict(lateness.to_dict()) == lateness


def test_a_link_in_a_sub_folder_is_not_followed_and_a_nested_stamp_is_read_below_the_root(tmp_path):
    policy = _course(tmp_path, "bob,*,2026-12-01T20:00:00+01:00\n")
    folder = tmp_path / "submitted" / "bob"
    (folder / "task4").mkdir(parents=True)
    (folder / "task4" / "timestamp.txt").write_text("2026-12-01 18:00:00 UTC")  # plain folders: one level below
    other = tmp_path / "other"
    other.mkdir()
    (other / "timestamp.txt").symlink_to(_secret(tmp_path))
    (folder / "zz").symlink_to(other, target_is_directory=True)  # a linked folder is not entered
    got = submission_time(policy, "bob", "files", folder)
    assert got.when == datetime(2026, 12, 1, 19, tzinfo=UTC) and not got.refused
    assert got.stamp == "the submission's a sub-folder's timestamp.txt says 2026-12-01 18:00:00+00:00 (not used)"


def test_file_times_decide_nothing_not_even_a_pycache_written_after_the_deadline(tmp_path):
    policy = _course(tmp_path, "alice,lab,2026-12-01T23:00:00+01:00\n")  # on time by the LMS
    folder = _handed_in(tmp_path)
    future = DEADLINE.timestamp() + 30 * 86400
    for relative in ("hri_lab/scripts/__pycache__/teleoperation.cpython-311.pyc", "hri_lab/scripts/teleoperation.py"):
        (folder / relative).parent.mkdir(parents=True, exist_ok=True)
        (folder / relative).write_text("x")
        os.utime(folder / relative, (future, future))
    got = submission_time(policy, "alice", "lab", folder)
    assert not judge_lateness(policy, "alice", "lab", got.when).late
    unknown = submission_time(policy, "bob", "lab", folder)  # no row: file times do not stand in
    assert unknown.when is None and unknown.source == ""


def test_an_assignments_own_row_extension_and_deadline_win_over_the_star(tmp_path):
    # the "*" row last and first: the assignment's own row wins either way
    for rows in ("bob,lab,2026-12-01T23:00:00+01:00\nbob,*,2026-12-05T23:00:00+01:00\n",
                 "bob,*,2026-12-05T23:00:00+01:00\nbob,lab,2026-12-01T23:00:00+01:00\n"):
        policy = _course(tmp_path, rows)
        assert submission_time(policy, "bob", "lab", _handed_in(tmp_path, "bob")).when == \
            datetime(2026, 12, 1, 23, tzinfo=CET)
        assert submission_time(policy, "bob", "preparation", _handed_in(tmp_path, "bob")).when == \
            datetime(2026, 12, 5, 23, tzinfo=CET)
    own = _policy(extensions={"bob": {ALL_ASSIGNMENTS: Extension(days=3), "lab": Extension(days=1)}})
    assert own.deadline_for("bob", "lab") == (DEADLINE + DAY, True)
    assert own.deadline_for("bob", "preparation") == (DEADLINE + 3 * DAY, True)
    per = _policy(deadlines={ALL_ASSIGNMENTS: DEADLINE, "lab": DEADLINE + 2 * DAY})
    assert per.deadline_for("bob", "lab") == (DEADLINE + 2 * DAY, False)
    assert per.deadline_for("bob", "preparation") == (DEADLINE, False)


def test_the_lms_export_takes_a_byte_order_mark_other_columns_and_a_blank_time(tmp_path):
    (tmp_path / "times.csv").write_bytes(
        "\ufeffSubmitted_At,Name,Student,Assignment\n2026-12-01T23:00:00+01:00,Alice A.,alice,\n,Bob B.,bob,lab\n"
        .encode("utf-8"))
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\ntimes: times.csv\n')
    policy = read_late_policy(tmp_path / "late.yaml")
    assert policy.times == {("alice", ALL_ASSIGNMENTS): datetime(2026, 12, 1, 23, tzinfo=CET), ("bob", "lab"): None}
    blank = submission_time(policy, "bob", "lab", _handed_in(tmp_path, "bob"))
    assert blank.when is None and blank.problem == "times.csv has no time for bob, lab"
    assert read_times(tmp_path / "times.csv") == policy.times


@pytest.mark.parametrize("csv_text, words", [
    ("student,submitted_at\nalice,2026-12-01T23:00:00+01:00\n", [":1: no column assignment in the header"]),
    (TIMES_HEADER + "alice,lab,2026-12-01 23:00\n", [":2: submitted_at '2026-12-01 23:00'", "no time zone"]),
    (TIMES_HEADER + "alice,lab,2026-12-01T23:00:00Z\nbob,lab,\nalice,lab,2026-12-02T23:00:00Z\n",
     [":4: a second row for alice, lab", "keep one row per student and assignment"]),
    (TIMES_HEADER + ",lab,2026-12-01T23:00:00Z\n", [":2: no student id"]),
    ("", [":1: no column student, assignment, submitted_at"]),
])
def test_an_lms_export_that_cannot_be_used_is_one_line_naming_the_file_the_row_and_the_fix(tmp_path, csv_text, words):
    (tmp_path / "times.csv").write_text(csv_text)
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\ntimes: times.csv\n')
    with pytest.raises(LateError) as err:
        read_late_policy(tmp_path / "late.yaml")
    message = str(err.value)
    assert "\n" not in message and str(tmp_path / "times.csv") in message
    assert "student,assignment,submitted_at" in message, message
    for word in words:
        assert word in message, message


@pytest.mark.parametrize("line, words", [
    ("times: gone.csv\n", ["submission times not found", "gone.csv", "relative to late.yaml"]),
    ("times: [a, b]\n", ["times must be the path", "times: submitted-at.csv"]),
])
def test_a_times_key_that_names_no_file_says_what_to_write(tmp_path, line, words):
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\n' + line)
    with pytest.raises(LateError) as err:
        read_late_policy(tmp_path / "late.yaml")
    assert "\n" not in str(err.value) and all(w in str(err.value) for w in words), str(err.value)


def test_parse_timestamp_reads_nbgraders_format_and_never_repeats_what_it_cannot_read():
    assert parse_timestamp(b"2026-12-01 22:59:00.000000\n") == DEADLINE
    assert parse_timestamp(b"2026-12-01 23:59:00 +0100") == DEADLINE
    assert parse_timestamp(b"yesterday <b>") == "timestamp.txt does not hold a date and time"
    assert parse_timestamp(b"2026-12-01 22:59:00 UTC\n2026-12-01 22:59:00 UTC") == \
        "timestamp.txt does not hold a date and time"


# --- nbgrader's exchange: the inbound folder's change time, which its owner can only move later ---

def _exchange(tmp_path, deadline: datetime, extra: str = "") -> LatePolicy:
    (tmp_path / "exchange" / "inbound").mkdir(parents=True, exist_ok=True)
    (tmp_path / "late.yaml").write_text(f'deadline: "{deadline.isoformat()}"\nper_day: 10%\nexchange: exchange\n'
                                        + extra)
    return read_late_policy(tmp_path / "late.yaml")


def _submit(tmp_path, name: str) -> Path:
    """What `nbgrader submit` leaves in the exchange: a folder whose name carries the student's own clock."""
    entry = tmp_path / "exchange" / "inbound" / name
    (entry / "ex01.ipynb").parent.mkdir(parents=True)
    (entry / "ex01.ipynb").write_text("{}")
    (entry / "timestamp.txt").write_text(name.split("+")[2])
    return entry


def test_the_exchange_gives_the_inbound_folders_change_time_not_the_time_in_its_name(tmp_path):
    now = datetime.now(timezone.utc)
    policy = _exchange(tmp_path, now - DAY)  # the deadline was yesterday
    first = _submit(tmp_path, "alice+lab+2026-11-01 10:00:00.000000 UTC+AbCd")  # a forged early name
    second = _submit(tmp_path, "alice+lab+2026-11-02 10:00:00.000000 UTC+EfGh")
    first.chmod(0o777)  # as nbgrader does last: the change time moves later, never back
    got = submission_time(policy, "alice", "lab", _handed_in(tmp_path, stamp="2026-11-01 10:00:00 UTC"))
    newest = max(os.lstat(first).st_ctime, os.lstat(second).st_ctime)
    assert got.when == datetime.fromtimestamp(newest, UTC) and got.source.startswith("nbgrader's exchange")
    lateness = judge_lateness(policy, "alice", "lab", got.when, got.shown_source)
    assert lateness.late and lateness.days >= 1
    assert "timestamp.txt says 2026-11-01 10:00:00+00:00 (not used)" in late_line(lateness, 55)
    assert not judge_lateness(_exchange(tmp_path / "later", now + DAY), "alice", "lab", got.when).late


def test_an_exchange_folder_under_a_students_name_made_by_someone_else_or_a_link_is_not_counted(tmp_path):
    policy = _exchange(tmp_path, DEADLINE)
    forged = _submit(tmp_path, "carol+lab+2026-11-01 10:00:00.000000 UTC+AbCd")
    os.chown(forged, 54321, 54321)  # another user's folder, named for carol
    (tmp_path / "exchange" / "inbound" / "carol+lab+2026-11-02 10:00:00 UTC").symlink_to(tmp_path)
    got = submission_time(policy, "carol", "lab", _handed_in(tmp_path, "carol"))
    assert got.when is None and got.problem == (
        "nbgrader's exchange has no submission of carol, lab (2 under that name made by another user or not a "
        "folder, not counted)")
    assert submission_time(policy, "dave", "lab", _handed_in(tmp_path, "dave")).problem == \
        "nbgrader's exchange has no submission of dave, lab"


def test_the_lms_export_comes_before_the_exchange(tmp_path):
    (tmp_path / "times.csv").write_text(TIMES_HEADER + "alice,lab,2026-12-01T20:00:00+01:00\n")
    policy = _exchange(tmp_path, DEADLINE, "times: times.csv\n")
    _submit(tmp_path, "alice+lab+2026-11-01 10:00:00.000000 UTC+AbCd")
    _submit(tmp_path, "bob+lab+2026-11-01 10:00:00.000000 UTC+AbCd")
    alice = submission_time(policy, "alice", "lab", _handed_in(tmp_path))
    assert (alice.when, alice.source) == (datetime(2026, 12, 1, 20, tzinfo=CET), "times.csv, the LMS export")
    bob = submission_time(policy, "bob", "lab", _handed_in(tmp_path, "bob"))
    assert bob.source.startswith("nbgrader's exchange") and bob.when is not None
    nobody = submission_time(policy, "eve", "lab", _handed_in(tmp_path, "eve"))
    assert nobody.problem == "times.csv has no row for eve, lab; nbgrader's exchange has no submission of eve, lab"


def test_an_exchange_key_that_is_no_exchange_says_what_to_write(tmp_path):
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\nexchange: nowhere\n')
    with pytest.raises(LateError) as err:
        read_late_policy(tmp_path / "late.yaml")
    assert str(err.value) == (f"{tmp_path / 'late.yaml'}: exchange 'nowhere' is not nbgrader's exchange folder of "
                              "the course (no inbound/ in it); write e.g. exchange: /srv/nbgrader/exchange/task4")
