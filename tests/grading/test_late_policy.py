"""The late policy: the rule at each threshold, late.yaml's one-line errors, and where submission times come from."""

from __future__ import annotations

import os
from datetime import datetime, timedelta, timezone

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


def test_an_unknown_submission_time_costs_nothing_and_says_why():
    got = judge_lateness(_policy(), "alice", "lab", None, problem="no files in x")
    assert got.fraction == 0 and not got.late
    assert "submission time unknown (no files in x)" in late_line(got, 55)


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


@pytest.mark.parametrize("stamp", ["2026-12-01 22:59:00.000000", "2026-12-01 22:59:00", "2026-12-01T22:59:00"])
def test_a_timestamp_without_a_zone_is_read_as_utc_as_nbgrader_writes_it(tmp_path, stamp):
    (tmp_path / "timestamp.txt").write_text(stamp + "\n")
    assert parse_timestamp(tmp_path / "timestamp.txt") == datetime(2026, 12, 1, 22, 59, tzinfo=UTC) == DEADLINE
    assert submission_time(tmp_path) == (DEADLINE, "timestamp.txt", "")


def test_of_two_timestamps_the_later_one_is_the_submission_time(tmp_path):
    # "a" sorts first and holds the later time: neither the first nor the last file wins, the later time does.
    for folder, stamp in (("a", "2026-12-02 10:00:00 UTC"), ("b", "2026-12-01 09:00:00 UTC"),
                          ("c", "2026-12-01 22:00:00 -05:00")):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "timestamp.txt").write_text(stamp)
    assert submission_time(tmp_path) == (datetime(2026, 12, 2, 10, tzinfo=UTC), "timestamp.txt", "")
    (tmp_path / "c" / "timestamp.txt").write_text("2026-12-02 05:00:01 -05:00")  # 10:00:01 UTC: later still
    assert submission_time(tmp_path)[0] == datetime(2026, 12, 2, 10, 0, 1, tzinfo=UTC)
    (tmp_path / "b" / "timestamp.txt").write_text("not a time")  # an unreadable one does not hide the others
    assert submission_time(tmp_path)[0] == datetime(2026, 12, 2, 10, 0, 1, tzinfo=UTC)


def test_the_newest_file_time_wins_when_there_is_no_timestamp(tmp_path):
    for name, mtime in (("a.py", 1_700_000_500), ("b.py", 1_700_000_000), ("c.py", 1_600_000_000)):
        (tmp_path / name).write_text("x")
        os.utime(tmp_path / name, (mtime, mtime))
    assert submission_time(tmp_path) == (datetime.fromtimestamp(1_700_000_500, UTC), "file times", "")


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


def test_the_submission_time_is_nbgraders_timestamp_else_the_newest_file_time(tmp_path):
    sub = tmp_path / "alice"
    (sub / "hri_lab").mkdir(parents=True)
    (sub / "hri_lab" / "a.py").write_text("x")
    os.utime(sub / "hri_lab" / "a.py", (1_700_000_000, 1_700_000_000))
    assert submission_time(sub) == (datetime.fromtimestamp(1_700_000_000, timezone.utc), "file times", "")
    (sub / "timestamp.txt").write_text("2026-12-01 22:59:00.000000 UTC\n")
    assert submission_time(sub) == (DEADLINE, "timestamp.txt", "")
    (sub / "timestamp.txt").write_text("yesterday\n")
    when, source, problem = submission_time(sub)
    assert when is None and "timestamp.txt" in problem and "yesterday" in problem
    nested = tmp_path / "bob"  # plain folders: bob/<assignment>/timestamp.txt, as nbgrader collects them
    (nested / "task4").mkdir(parents=True)
    (nested / "task4" / "timestamp.txt").write_text("2026-12-01 23:59:00 +0100")
    assert submission_time(nested)[:2] == (DEADLINE, "timestamp.txt")
    assert submission_time(tmp_path / "empty")[2].startswith("no files in")


def test_a_zone_name_on_python_38_asks_for_an_offset(monkeypatch):
    import importlib.util

    from hri_teleop.grading.batch import late

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "zoneinfo" else real(name, *a))
    monkeypatch.setattr(late, "_zone", lambda name: None)  # as on 3.8: no zoneinfo module
    assert parse_when("2026-12-01 23:59 Europe/Berlin") == (
        "zone names like 'Europe/Berlin' need Python 3.9 or later; write the offset instead, e.g. +01:00")
