"""hri_teleop.core.files.replace_text: a file the lab keeps (a calibrated launch file, a trial's sidecar) is
replaced all at once, keeps its permissions, and a failed write leaves the old file whole and nothing beside it."""

from __future__ import annotations

import os
import stat

import pytest

from hri_teleop.core import files
from hri_teleop.core.files import replace_text

TEXT = "<launch>\n  <!-- Kraft ≤ 20 N, calibrated 2026-11-29 -->\n</launch>\n"


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def test_a_new_file_gets_the_text_as_utf8_and_mode_0644_by_default(tmp_path):
    target = tmp_path / "sensor.launch"
    replace_text(target, TEXT)
    assert target.read_bytes() == TEXT.encode("utf-8")
    assert _mode(target) == 0o644
    assert sorted(os.listdir(tmp_path)) == ["sensor.launch"]


def test_a_new_file_gets_the_mode_asked_for(tmp_path):
    replace_text(tmp_path / "P01_t01.yaml", "force: 1\n", new_mode=0o600)
    assert _mode(tmp_path / "P01_t01.yaml") == 0o600


@pytest.mark.parametrize("mode", [0o755, 0o600, 0o2750])
def test_a_replaced_file_keeps_its_own_permissions_whatever_the_new_mode(tmp_path, mode):
    target = tmp_path / "sensor.launch"
    target.write_text("old\n")
    os.chmod(target, mode)
    replace_text(target, TEXT, new_mode=0o644)
    assert target.read_text(encoding="utf-8") == TEXT
    assert _mode(target) == mode


def test_while_it_is_written_the_new_text_sits_hidden_beside_the_old_file_named_for_it(tmp_path, monkeypatch):
    """In the same folder (a rename there is atomic), hidden and ending in .tmp: a listing of *.launch, or the
    lab's launch, sees the old file or the new one, never a half-written one."""
    target = tmp_path / "sensor.launch"
    target.write_text("old\n")
    seen = []
    real_fsync = os.fsync

    def looking_fsync(fd):
        seen.append(sorted(os.listdir(tmp_path)))
        seen.append(target.read_text())
        return real_fsync(fd)

    monkeypatch.setattr(files.os, "fsync", looking_fsync)
    replace_text(target, TEXT)
    listing, old_text = seen
    assert old_text == "old\n"
    assert len(listing) == 2 and "sensor.launch" in listing
    temp = next(name for name in listing if name != "sensor.launch")
    assert temp.startswith(".sensor.launch.") and temp.endswith(".tmp")
    assert sorted(os.listdir(tmp_path)) == ["sensor.launch"]


@pytest.mark.parametrize("failure", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_a_write_that_fails_leaves_the_old_file_whole_and_no_temporary_file(tmp_path, monkeypatch, failure):
    target = tmp_path / "sensor.launch"
    target.write_text("old\n")
    os.chmod(target, 0o640)

    def failing_fsync(fd):
        raise failure

    monkeypatch.setattr(files.os, "fsync", failing_fsync)
    with pytest.raises(type(failure)):
        replace_text(target, TEXT)
    assert target.read_text() == "old\n" and _mode(target) == 0o640
    assert sorted(os.listdir(tmp_path)) == ["sensor.launch"]


def test_a_rename_that_fails_leaves_the_old_file_and_no_temporary_file(tmp_path, monkeypatch):
    target = tmp_path / "P01_t01.yaml"
    target.write_text("old\n")

    def failing_replace(src, dst):
        raise OSError(18, "Invalid cross-device link")

    monkeypatch.setattr(files.os, "replace", failing_replace)
    with pytest.raises(OSError, match="cross-device"):
        replace_text(target, "new\n")
    assert target.read_text() == "old\n"
    assert sorted(os.listdir(tmp_path)) == ["P01_t01.yaml"]


def test_a_path_given_as_text_works_as_a_path(tmp_path):
    replace_text(str(tmp_path / "a.yaml"), "a: 1\n")
    assert (tmp_path / "a.yaml").read_text() == "a: 1\n"


def test_a_process_in_the_c_locale_still_writes_utf8(tmp_path):
    """A lab service or cron job runs in the C locale, where Python's default text encoding is ASCII: the text
    must go out as UTF-8 all the same (a sensor's name with a degree sign, a participant's comment)."""
    import locale

    before = locale.setlocale(locale.LC_CTYPE)
    locale.setlocale(locale.LC_CTYPE, "C")
    try:
        replace_text(tmp_path / "P01_t01.yaml", "comment: Kraft ≤ 20 N, 21 °C\n")
    finally:
        locale.setlocale(locale.LC_CTYPE, before)
    assert (tmp_path / "P01_t01.yaml").read_bytes() == "comment: Kraft ≤ 20 N, 21 °C\n".encode("utf-8")
