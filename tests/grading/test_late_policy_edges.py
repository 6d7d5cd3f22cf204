"""The late policy's inputs at their edges: an extension of 0 days, a timestamp.txt of 64 and 65 characters or
of two lines, of 1024 and 1025 bytes, an LMS export whose row is shorter than its header or broken over two lines,
whose exchange folders count (root's, another user's, one gone), what a refused timestamp.txt keeps beside a time.
Each edge written as a number or a literal; each gate of late.py pinned by what it does (issue 44)."""

from __future__ import annotations

import errno
import os
import time
from datetime import datetime, timedelta, timezone
from pathlib import Path

import pytest

from hri_teleop.grading.batch.late import (
    ALL_ASSIGNMENTS,
    Extension,
    LateError,
    Lateness,
    LatePolicy,
    SubmissionTime,
    duration_text,
    exchange_time,
    judge_lateness,
    late_line,
    parse_timestamp,
    parse_when,
    read_late_policy,
    read_times,
    student_stamp,
    submission_time,
)
from hri_teleop.grading.run.untrusted_files import read_regular

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


# --- Each gate of the policy pinned by what it does (issue 44: make mutants over late.py) ---

UTC = timezone.utc


def _late_yaml(tmp_path, text: str):
    path = tmp_path / "late.yaml"
    path.write_text(text)
    return path


def test_an_unknown_key_without_a_close_match_lists_the_valid_keys_and_guesses_nothing(tmp_path):
    path = _late_yaml(tmp_path, 'deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\ncolour: red\n')
    with pytest.raises(LateError) as err:
        read_late_policy(path)
    assert str(err.value) == (f"{path}: unknown key 'colour'; valid keys are deadline, per_day, count, cap, "
                              "extensions, times, exchange")


@pytest.mark.parametrize("text, start, fix", [
    ('deadline:\n  lab: "2026-12-01 23:59"\nper_day: 10%\n', "deadline.lab 2026-12-01 23:59: it has no time zone",
     "write e.g. deadline: "),
    ('deadline: "2026-12-01 23:59"\nper_day: 10%\n', "deadline 2026-12-01 23:59: it has no time zone",
     "write e.g. deadline: "),
    ('deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\nextensions: {bob: {lab: soon}}\n',
     "extensions.bob.lab must be days added", "write e.g. lab: 2"),
])
def test_a_bad_deadline_or_extension_of_one_assignment_names_the_file_that_assignments_key_and_the_fix(
        tmp_path, text, start, fix):
    path = _late_yaml(tmp_path, text)
    with pytest.raises(LateError) as err:
        read_late_policy(path)
    assert str(err.value).startswith(f"{path}: {start}") and fix in str(err.value), str(err.value)


def test_a_late_yaml_of_a_deadline_and_a_penalty_only_is_the_policy_with_every_default(tmp_path):
    path = _late_yaml(tmp_path, 'deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\n')
    assert read_late_policy(path) == LatePolicy(str(path), {ALL_ASSIGNMENTS: DEADLINE}, 0.1, 1.0, "started", {}, {},
                                                "", "")


@pytest.mark.parametrize("value, said", [
    (5, "it is 5, not a date and time"),
    ("  ", "it is '  ', not a date and time"),
    ("tomorrow", "it has no time zone"),
    ("soon UTC", "cannot read the date and time (write YYYY-MM-DD HH:MM[:SS])"),
    ("2026-12-01 23:59 Mars/Olympus", "cannot read the time zone 'Mars/Olympus'"),
    ("2026-12-01T22:59:00z", "it has no time zone"),  # ISO 8601 writes UTC's Z upper case: not guessed
])
def test_a_time_that_cannot_be_read_says_which_part_is_wrong(value, said):
    assert parse_when(value) == said


def test_a_number_as_deadline_is_refused_in_one_line(tmp_path):
    path = _late_yaml(tmp_path, "deadline: 5\nper_day: 10%\n")
    with pytest.raises(LateError, match="deadline 5: it is 5, not a date and time"):
        read_late_policy(path)


def test_a_time_written_with_z_is_utc_on_python_38_too(monkeypatch):
    from hri_teleop.grading.batch import late

    class Python38Datetime(datetime):
        """datetime as on the lab PCs' Python 3.8, whose fromisoformat does not read a trailing Z."""

        @classmethod
        def fromisoformat(cls, text: str) -> "Python38Datetime":
            if text.endswith("Z"):
                raise ValueError(f"Invalid isoformat string: {text!r}")
            return super().fromisoformat(text)

    monkeypatch.setattr(late, "datetime", Python38Datetime)
    with pytest.raises(ValueError):
        Python38Datetime.fromisoformat("2026-12-01T22:59:00Z")
    assert parse_when("2026-12-01T22:59:00Z") == datetime(2026, 12, 1, 22, 59, tzinfo=UTC)


def test_a_time_with_its_own_offset_keeps_it_whatever_abbreviation_follows():
    # Go's and date's "+0800 CST" is China's: the offset written beside the time decides, not the table's US CST
    assert parse_when("2026-12-02T07:59:00+08:00 CST") == datetime(2026, 12, 1, 23, 59, tzinfo=UTC)


def test_a_timestamp_split_over_two_lines_is_not_read_even_when_the_lines_together_make_a_time():
    assert parse_timestamp(b"2026-12-01\n22:59:00 UTC") == "timestamp.txt does not hold a date and time"


def test_a_blank_line_between_the_rows_of_the_lms_export_ends_nothing(tmp_path):
    path = tmp_path / "times.csv"
    path.write_text("student,assignment,submitted_at\nann,lab,2026-12-01T20:00:00Z\n,,\n\nbob,lab,2026-12-02T20:00:00Z\n")
    assert read_times(path) == {("ann", "lab"): datetime(2026, 12, 1, 20, tzinfo=UTC),
                                ("bob", "lab"): datetime(2026, 12, 2, 20, tzinfo=UTC)}


def test_a_time_the_export_broke_over_two_lines_is_refused_with_its_row_not_joined(tmp_path):
    path = tmp_path / "times.csv"
    path.write_bytes(b'student,assignment,submitted_at\r\nann,lab,2026-12-01T20:00:00Z\r\n'
                     b'bob,lab,"2026-12-01\r\n23:00:00+01:00"\r\n')
    with pytest.raises(LateError, match=r"times\.csv:3: submitted_at .*: it has no time zone"):
        read_times(path)
    path.write_bytes(b'student,assignment,submitted_at\r\nann,lab,2026-12-01T20:00:00Z\r\n')  # Windows' line ends
    assert read_times(path) == {("ann", "lab"): datetime(2026, 12, 1, 20, tzinfo=UTC)}


@pytest.mark.parametrize("size, said", [
    (1024, "timestamp.txt says 2026-12-01 22:59:00+00:00 (not used)"),
    (1025, "timestamp.txt is larger than 1024 bytes (not used, shown to the instructor)"),
])
def test_a_timestamp_of_1024_bytes_is_read_and_one_of_1025_is_refused(tmp_path, size, said):
    text = b"2026-12-01 22:59:00 UTC"
    (tmp_path / "timestamp.txt").write_bytes(text + b" " * (size - len(text)))
    assert student_stamp(tmp_path) == (f"the submission's {said}", size > 1024)


def test_a_timestamp_that_cannot_be_read_from_disk_is_said_so_and_the_next_still_read(tmp_path, monkeypatch):
    from hri_teleop.grading.batch import late

    _sub(tmp_path, "a", b"2026-11-01 10:00:00.000000")
    _sub(tmp_path, "b", b"2026-12-01 20:00:00.000000")
    real = read_regular

    def failing_disk(path, *args, **kwargs):
        if Path(path).parent.name == "a":
            raise OSError(errno.EIO, "Input/output error")
        return real(path, *args, **kwargs)

    monkeypatch.setattr(late, "read_regular", failing_disk)
    assert student_stamp(tmp_path) == ("the submission's a sub-folder's timestamp.txt cannot be read; a sub-folder's "
                                       "timestamp.txt says 2026-12-01 20:00:00+00:00 (not used, shown to the "
                                       "instructor)", True)


@pytest.mark.parametrize("swap, said", [
    ("the sub-folder for a link", "is a link (not followed)"),
    ("the sub-folder for a file", "is not inside a folder"),
    ("the submission for a link", "cannot be read"),
])
def test_a_folder_swapped_after_it_was_listed_is_not_followed_and_said_in_the_graders_words(tmp_path, monkeypatch,
                                                                                             swap, said):
    from hri_teleop.grading.batch import late

    folder = tmp_path / "submission"
    _sub(folder, "task4", b"2026-12-01 20:00:00.000000")
    elsewhere = tmp_path / "elsewhere"
    (elsewhere / "task4").mkdir(parents=True)
    (elsewhere / "task4" / "timestamp.txt").write_bytes(b"2026-11-01 10:00:00 UTC")
    swapped = folder if swap == "the submission for a link" else folder / "task4"
    real = read_regular

    def swap_then_read(path, *args, **kwargs):
        swapped.rename(tmp_path / "moved")
        if swap == "the sub-folder for a file":
            swapped.write_text("2026-11-01 10:00:00 UTC")
        else:
            swapped.symlink_to(elsewhere if swapped == folder else elsewhere / "task4", target_is_directory=True)
        return real(path, *args, **kwargs)

    monkeypatch.setattr(late, "read_regular", swap_then_read)
    assert student_stamp(folder) == (f"the submission's a sub-folder's timestamp.txt {said} (not used, shown to the "
                                     "instructor)", True)


@pytest.fixture
def grader_in_india(monkeypatch):
    """The grader machine's local zone is +05:30 for the test (TZ), then back."""
    monkeypatch.setenv("TZ", "Asia/Kolkata")
    time.tzset()
    yield
    monkeypatch.undo()
    time.tzset()


def test_a_timestamp_is_shown_in_utc_to_the_second_whatever_the_graders_own_zone(tmp_path, grader_in_india):
    (tmp_path / "timestamp.txt").write_bytes(b"2026-12-02 01:00:00.123456+01:00")
    assert student_stamp(tmp_path) == ("the submission's timestamp.txt says 2026-12-02 00:00:00+00:00 (not used)",
                                       False)


def test_the_feedback_line_shows_times_to_the_second():
    got = judge_lateness(_policy(), "ann", "lab", DEADLINE + timedelta(seconds=1, microseconds=500000), "exchange")
    assert late_line(got, 10).startswith("late policy: submitted 2026-12-01 23:59:01+00:00 (exchange), 2 s after the "
                                         "deadline 2026-12-01 23:59:00+00:00: ")


# nbgrader's exchange: whose folders count, and what a refused timestamp.txt beside it keeps

def _exchange_policy(tmp_path) -> LatePolicy:
    (tmp_path / "exchange" / "inbound").mkdir(parents=True, exist_ok=True)
    return read_late_policy(_late_yaml(tmp_path, 'deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\n'
                                                 "exchange: exchange\n"))


def _inbound(tmp_path: Path, name: str) -> Path:
    entry = tmp_path / "exchange" / "inbound" / name
    entry.mkdir()
    return entry


def _linked_stamp(tmp_path: Path) -> Path:
    folder = tmp_path / "submitted" / "carol"
    folder.mkdir(parents=True)
    (tmp_path / "valid.txt").write_text("2026-11-01 10:00:00 UTC")
    (folder / "timestamp.txt").symlink_to(tmp_path / "valid.txt")
    return folder


LINKED = "the submission's timestamp.txt is a link (not followed) (not used, shown to the instructor)"


def test_every_folder_under_a_students_name_made_by_another_user_is_counted_in_the_note(tmp_path):
    policy = _exchange_policy(tmp_path)
    for name in ("carol+lab+2026-11-01 10:00:00 UTC+AbCd", "carol+lab+2026-11-02 10:00:00 UTC+EfGh"):
        os.chown(_inbound(tmp_path, name), 54321, 54321)
    assert exchange_time(Path(policy.exchange), "carol", "lab") == (
        "nbgrader's exchange has no submission of carol, lab (2 under that name made by another user or not a "
        "folder, not counted)")


def test_an_exchange_folder_made_by_root_counts_when_the_grader_is_another_user(tmp_path, monkeypatch):
    if os.geteuid() != 0:
        pytest.skip("needs a folder owned by root: run as root (the test container is)")
    policy = _exchange_policy(tmp_path)
    entry = _inbound(tmp_path, "carol+lab+2026-11-01 10:00:00 UTC+AbCd")  # root's, as a sudo nbgrader makes it
    monkeypatch.setattr(os, "geteuid", lambda: 4242)  # the grader: neither root nor carol
    assert exchange_time(Path(policy.exchange), "carol", "lab") == datetime.fromtimestamp(os.lstat(entry).st_ctime, UTC)


def test_an_exchange_entry_gone_between_listing_and_looking_is_skipped_and_the_next_still_counted(tmp_path,
                                                                                                  monkeypatch):
    policy = _exchange_policy(tmp_path)
    entry = _inbound(tmp_path, "carol+lab+2026-11-02 10:00:00 UTC+EfGh")
    real = os.listdir
    monkeypatch.setattr(os, "listdir", lambda path: real(path) + ["carol+lab+2026-11-01 10:00:00 UTC+gone"])
    assert exchange_time(Path(policy.exchange), "carol", "lab") == datetime.fromtimestamp(os.lstat(entry).st_ctime, UTC)


def test_a_time_from_the_exchange_has_no_problem_and_keeps_a_refused_timestamp_beside_it(tmp_path):
    policy = _exchange_policy(tmp_path)
    entry = _inbound(tmp_path, "carol+lab+2026-11-01 10:00:00 UTC+AbCd")
    got = submission_time(policy, "carol", "lab", _linked_stamp(tmp_path))
    assert got == SubmissionTime(datetime.fromtimestamp(os.lstat(entry).st_ctime, UTC),
                                 "nbgrader's exchange (its inbound folder's change time)", "", LINKED, True)


def test_an_unknown_time_keeps_a_refused_timestamp_beside_it(tmp_path):
    policy = read_late_policy(_late_yaml(tmp_path, 'deadline: "2026-12-01 23:59 UTC"\nper_day: 10%\n'))
    got = submission_time(policy, "carol", "lab", _linked_stamp(tmp_path))
    assert got == SubmissionTime(None, "", "no source of submission times: late.yaml has neither times: (the LMS "
                                           "export) nor exchange: (nbgrader's exchange)", LINKED, True)
