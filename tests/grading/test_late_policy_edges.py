"""The late policy's inputs at their edges: an extension of 0 days, a timestamp.txt of 64 and 65 characters or
of two lines, an LMS export whose row is shorter than its header. Each edge written as a number or a literal."""

from __future__ import annotations

from datetime import datetime, timezone

import pytest

from hri_teleop.grading.batch.late import ALL_ASSIGNMENTS, Extension, parse_timestamp, read_late_policy, read_times

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
