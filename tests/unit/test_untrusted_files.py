"""grading.run.untrusted_files: a submission's files are read as regular files only, never through a link.

Each hostile shape a student can hand in: a link to a file outside (the answer key, /etc/shadow), a
link to a folder, a link in the middle of the path, a FIFO (a reader would block for ever), an endless
/proc file and a file past the cap. Each is refused with one line and nothing of its target is read.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.run.untrusted_files import (
    UntrustedFileError,
    copy_regular,
    copy_tree,
    is_regular,
    read_regular,
    refusal,
    walk_regular,
)

SECRET = "SECRET-untrusted-files-7f3a"


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """A package with one honest file, and a secret outside it."""
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.txt").write_text(SECRET)
    package = tmp_path / "hri_lab"
    (package / "config").mkdir(parents=True)
    (package / "config" / "robot_params.yaml").write_text("robot_name: FER\n")
    return package


def _no_secret(exc: BaseException) -> None:
    text = str(exc)
    assert SECRET not in text and "\n" not in text, text
    assert isinstance(exc, HriTeleopError)


def test_a_regular_file_is_read_and_copied(tree: Path, tmp_path: Path) -> None:
    path = tree / "config" / "robot_params.yaml"
    assert read_regular(path, root=tree) == b"robot_name: FER\n"
    assert is_regular(path) and refusal(path, tree) == ""
    assert copy_regular(path, tmp_path / "copy" / "x.yaml", root=tree) == 16
    assert (tmp_path / "copy" / "x.yaml").read_text() == "robot_name: FER\n"


def test_a_link_to_a_file_outside_is_refused_naming_the_link(tree: Path) -> None:
    link = tree / "config" / "graph.yaml"
    link.symlink_to(tree.parent / "outside" / "secret.txt")
    with pytest.raises(UntrustedFileError) as caught:
        read_regular(link, root=tree)
    _no_secret(caught.value)
    assert "is a link; hand in the file itself" in str(caught.value)
    assert not is_regular(link)
    with pytest.raises(UntrustedFileError):
        read_regular(link)  # without a root: the file's own name is not followed either


def test_a_link_in_the_middle_of_the_path_is_refused(tree: Path) -> None:
    (tree.parent / "outside" / "config").mkdir()
    (tree.parent / "outside" / "config" / "robot_params.yaml").write_text(SECRET)
    (tree / "launch").symlink_to(tree.parent / "outside" / "config", target_is_directory=True)
    with pytest.raises(UntrustedFileError) as caught:
        read_regular(tree / "launch" / "robot_params.yaml", root=tree)
    _no_secret(caught.value)
    assert "launch is a link; hand in the folder itself" in str(caught.value)


def test_a_link_to_a_folder_is_neither_entered_nor_copied(tree: Path, tmp_path: Path) -> None:
    (tree / "scripts").symlink_to(tree.parent / "outside", target_is_directory=True)
    walked = dict(walk_regular(tree))
    assert walked["scripts"].startswith("a link")
    assert not any(rel.startswith("scripts/") for rel in walked)
    report = copy_tree(tree, tmp_path / "copy")
    assert report.copied == ["config/robot_params.yaml"]
    assert ("scripts", "a link (the grader follows none)") in report.skipped
    assert not (tmp_path / "copy" / "scripts").exists()


def test_a_fifo_is_refused_at_once_without_blocking(tree: Path, tmp_path: Path) -> None:
    fifo = tree / "config" / "robot_params.yaml"
    fifo.unlink()
    os.mkfifo(fifo)
    outcome: list = []
    reader = threading.Thread(target=lambda: outcome.append(refusal(fifo, tree)), daemon=True)
    reader.start()
    reader.join(20.0)
    assert outcome and "is a FIFO, not a regular file" in outcome[0], outcome
    with pytest.raises(UntrustedFileError):
        read_regular(fifo, root=tree)
    report = copy_tree(tree, tmp_path / "copy")
    assert report.copied == [] and report.skipped == [("config/robot_params.yaml", "a FIFO, not a regular file")]


@pytest.mark.parametrize("target", ["/proc/self/pagemap", "/dev/zero", "/proc/self/mem"])
def test_a_link_to_an_endless_proc_or_device_file_is_refused(tree: Path, target: str) -> None:
    if not os.path.exists(target):
        pytest.skip(f"{target} does not exist here")
    link = tree / "config" / "robot_params.yaml"
    link.unlink()
    link.symlink_to(target)
    with pytest.raises(UntrustedFileError) as caught:
        read_regular(link, root=tree)
    assert "is a link" in str(caught.value)


def test_a_proc_file_given_directly_is_refused_as_not_regular_or_cut_at_the_cap() -> None:
    # /proc/self/pagemap is no regular file: never read to its (endless) end
    with pytest.raises(UntrustedFileError):
        read_regular("/proc/self/pagemap", limit_bytes=1024)


def test_a_file_past_the_cap_is_refused_after_reading_no_more_than_the_cap(tree: Path) -> None:
    big = tree / "config" / "big.yaml"
    big.write_bytes(b"x" * 5000)
    with pytest.raises(UntrustedFileError) as caught:
        read_regular(big, limit_bytes=4096, root=tree)
    assert "larger than 4 KB" in str(caught.value)
    report = copy_tree(tree, tree.parent / "copy", file_limit_bytes=4096)
    assert "config/big.yaml" not in report.copied


def test_paths_outside_the_root_are_refused(tree: Path) -> None:
    for path in (tree.parent / "outside" / "secret.txt", tree / ".." / "outside" / "secret.txt"):
        with pytest.raises(UntrustedFileError) as caught:
            read_regular(path, root=tree)
        _no_secret(caught.value)
