"""The late policy's inputs at their edges: an extension of 0 days, a timestamp.txt of 64 and 65 characters or
of two lines, an LMS export whose row is shorter than its header. Each edge written as a number or a literal."""

from __future__ import annotations

from datetime import datetime, timedelta, timezone

import pytest

from hri_teleop.grading.batch.late import (
    ALL_ASSIGNMENTS,
    Extension,
    Lateness,
    LatePolicy,
    duration_text,
    judge_lateness,
    parse_timestamp,
    read_late_policy,
    read_times,
    student_stamp,
)

STAMP = "2026-12-01 23:59:00.000000"  # nbgrader's form: no zone, read as UTC


@pytest.mark.parametrize("value, days", [("0", 0.0), ("0.5", 0.5), ("2", 2.0)])
def test_an_extension_of_zero_days_or_more_is_days(tmp_path, value, days):
    path = tmp_path / "late.yaml"
    path.write_text(f'deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\nextensions:\n  bob: {value}\n')
    assert read_late_policy(path).extensions["bob"] == {ALL_ASSIGNMENTS: Extension(days=days)}


@pytest.mark.parametrize("padding, read", [(64 - len(STAMP), True), (65 - len(STAMP), False)])
def test_a_timestamp_of_64_characters_is_read_and_one_of_65_is_not(padding, read):
    text = STAMP + " " * 0 + "0" * padding  # more digits of the fraction: still a time up to 64 characters
    assert len(text) == len(STAMP) + padding
    got = parse_timestamp(text.encode())
    assert isinstance(got, datetime) is read, got


def test_a_timestamp_of_two_lines_is_not_read():
    assert parse_timestamp(f"{STAMP}\n{STAMP}".encode()) == "timestamp.txt does not hold a date and time"
    assert parse_timestamp(f"{STAMP}\n".encode()) == datetime(2026, 12, 1, 23, 59, tzinfo=timezone.utc)


def test_a_row_shorter_than_the_header_has_blank_cells(tmp_path):
    path = tmp_path / "times.csv"
    path.write_text("student,assignment,submitted_at\nann,lab,2026-12-01T20:00:00Z\nbob,lab\ncleo\n")
    assert read_times(path) == {("ann", "lab"): datetime(2026, 12, 1, 20, tzinfo=timezone.utc), ("bob", "lab"): None,
                                ("cleo", ALL_ASSIGNMENTS): None}


def _policy() -> LatePolicy:
    return LatePolicy(source="late.yaml", deadlines={ALL_ASSIGNMENTS: DEADLINE}, per_day=0.1, cap=0.5,
                      count="started")


DEADLINE = datetime(2026, 12, 1, 23, 59, tzinfo=timezone.utc)


def test_a_submission_without_a_time_is_judged_with_everything_it_was_given_and_nothing_taken():
    got = judge_lateness(_policy(), "ann", "lab", None, source="times.csv", problem="no row for ann", stamp_refused=True)
    assert got == Lateness("ann", "lab", None, "times.csv", DEADLINE, False, 0.0, 0.0, 0.0, "no row for ann", True)
    plain = judge_lateness(_policy(), "bob", "preparation", None)
    assert plain == Lateness("bob", "preparation", None, "", DEADLINE, False, 0.0, 0.0, 0.0, "no submission time",
                             False)


def test_a_late_submission_is_judged_with_its_source_and_no_problem():
    when = DEADLINE + timedelta(hours=25)
    got = judge_lateness(_policy(), "ann", "lab", when, source="times.csv")
    assert got == Lateness("ann", "lab", when, "times.csv", DEADLINE, False, 90000.0, 2.0, 0.2, "", False)


@pytest.mark.parametrize("seconds, text", [(59, "59 s"), (60, "1 min"), (90, "1 min"), (3600, "1 h"),
                                           (3630, "1 h"), (86400, "1 d"), (90061, "1 d 1 h 1 min")])
def test_a_duration_is_written_in_whole_units_leaving_out_the_empty_ones(seconds, text):
    assert duration_text(seconds) == text


@pytest.mark.parametrize("value, fraction", [("0%", 0.0), ("100%", 1.0), ("0", 0.0), ("1", 1.0)])
def test_a_penalty_of_0_or_100_percent_is_a_fraction(tmp_path, value, fraction):
    path = tmp_path / "late.yaml"
    path.write_text(f'deadline: "2026-12-01 23:59 UTC"\nper_day: "{value}"\n')
    assert read_late_policy(path).per_day == fraction


def _sub(folder, name: str, content):
    (folder / name).mkdir(parents=True)
    if isinstance(content, bytes):
        (folder / name / "timestamp.txt").write_bytes(content)
    else:
        (folder / name / "timestamp.txt").symlink_to(content)


def test_a_submissions_timestamps_are_shown_each_in_the_graders_words_refused_ones_first_named(tmp_path):
    """A link is not followed and the next sub-folder's stamp is still read; at most three are shown."""
    _sub(tmp_path, "a", "/etc/hostname")                          # a link: refused, not followed
    _sub(tmp_path, "b", b"2026-12-01 20:00:00.000000")            # read, as UTC
    _sub(tmp_path, "c", b"not a time")
    _sub(tmp_path, "d", b"2026-12-02 01:00:00+01:00")
    stamp, refused = student_stamp(tmp_path)
    assert refused is True
    assert stamp == ("the submission's a sub-folder's timestamp.txt is a link (not followed); a sub-folder's "
                     "timestamp.txt says 2026-12-01 20:00:00+00:00; a sub-folder's timestamp.txt does not hold a date "
                     "and time (not used, shown to the instructor)")


def test_a_submissions_own_readable_timestamp_is_shown_and_not_used(tmp_path):
    (tmp_path / "timestamp.txt").write_bytes(b"2026-12-02 01:00:00+01:00\n")
    assert student_stamp(tmp_path) == ("the submission's timestamp.txt says 2026-12-02 00:00:00+00:00 (not used)",
                                       False)
    assert student_stamp(tmp_path / "nothing-here") == ("", False)


def test_a_timestamp_that_is_only_a_link_is_refused(tmp_path):
    (tmp_path / "timestamp.txt").symlink_to("/etc/hostname")
    assert student_stamp(tmp_path) == ("the submission's timestamp.txt is a link (not followed) (not used, shown to "
                                       "the instructor)", True)
