"""Hostile Gradescope uploads, graded as run_autograder grades them (container.main in Gradescope's folders).

Each upload is one attack on the autograder's unpacking (issue 42, item 7): a zip holding a file and a
folder of the same name, links and special files in the zip or in the upload, a zip bomb by size and by
file count, names that are not UTF-8, an empty upload, a notebook that is not JSON, and a grader that
stops. Each must end in a valid results.json whose output says in one line what happened, never a
traceback, and leave nothing outside the scratch folder; the answer key, graded in the same batch,
keeps its full points. The checks graded are robot-params only (a probe in the sandbox, seconds).
"""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import tempfile
import zipfile
from pathlib import Path
from types import SimpleNamespace
from typing import Callable, Dict, Iterator, Optional

import pytest
from grading_helpers import REPO, SOLUTIONS, answer_text, open_folder

from hri_teleop.course.release import COURSE_DIR
from hri_teleop.grading.gradescope import container
from hri_teleop.grading.gradescope.container import CHECKS_ENV
from hri_teleop.grading.gradescope.notebooks import COURSE
from hri_teleop.grading.points import check_points

CHECK = "robot-params"
NOTEBOOK = "ex01_fsr_and_arduino.ipynb"
_PARAMS = "config/robot_params.yaml"


def _package_files() -> Dict[str, bytes]:
    """hri_lab/... -> bytes of the answer key (what a good student hands in)."""
    return {f"hri_lab/{p.relative_to(SOLUTIONS).as_posix()}": answer_text(str(p.relative_to(SOLUTIONS))).encode()
            for p in sorted(SOLUTIONS.rglob("*")) if p.is_file() and p.name != "README.md"}


def _member(zf: zipfile.ZipFile, name: str, data: bytes, mode: int = stat.S_IFREG | 0o644) -> None:
    info = zipfile.ZipInfo(name)
    info.create_system = 3  # unix: the mode's type bits count
    info.external_attr = mode << 16
    zf.writestr(info, data)


def _answer_key_zip(path: Path, first: Callable[[zipfile.ZipFile], None] = lambda zf: None,
                    skip: str = "") -> None:
    """The answer key zipped at ``path``, with ``first`` writing hostile members before it."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        first(zf)
        for name, data in _package_files().items():
            if name != skip:
                _member(zf, name, data)


def _honest(upload: Path) -> None:
    _answer_key_zip(upload / "hri_lab.zip")


def _file_and_folder(upload: Path) -> None:
    """hri_lab/config is a file first, then the folder of the answer key's params (crashed run_autograder)."""
    _answer_key_zip(upload / "hri_lab.zip", lambda zf: _member(zf, "hri_lab/config", b"not a folder"))


def _folder_then_file(upload: Path) -> None:
    """The answer key, then a member hri_lab/config that is a file where the folder already is."""
    _answer_key_zip(upload / "hri_lab.zip")
    with zipfile.ZipFile(upload / "hri_lab.zip", "a") as zf:
        _member(zf, "hri_lab/config", b"not a folder")


def _link_member(upload: Path) -> None:
    """robot_params.yaml as a link to /etc/shadow inside the zip."""
    _answer_key_zip(upload / "hri_lab.zip", lambda zf: _member(zf, f"hri_lab/{_PARAMS}", b"/etc/shadow",
                                                              stat.S_IFLNK | 0o777), skip=f"hri_lab/{_PARAMS}")


def _fifo_member(upload: Path) -> None:
    """robot_params.yaml as a FIFO inside the zip."""
    _answer_key_zip(upload / "hri_lab.zip", lambda zf: _member(zf, f"hri_lab/{_PARAMS}", b"",
                                                              stat.S_IFIFO | 0o644), skip=f"hri_lab/{_PARAMS}")


def _linked_folder(upload: Path) -> None:
    """hri_lab itself a link to another student's package (the answer key here), and a FIFO beside it."""
    other = upload.parent / "other-student"
    shutil.copytree(SOLUTIONS, other / "hri_lab")
    (other / "hri_lab" / _PARAMS).write_text(answer_text(_PARAMS))
    upload.mkdir(parents=True, exist_ok=True)
    (upload / "hri_lab").symlink_to(other / "hri_lab", target_is_directory=True)
    os.mkfifo(upload / "robot_params.yaml")


def _many_files(upload: Path) -> None:
    """A zip bomb by count: 6000 empty files."""
    with zipfile.ZipFile(upload / "many.zip", "w") as zf:
        for i in range(6000):
            zf.writestr(f"hri_lab/junk/{i}.txt", b"")


def _big(upload: Path) -> None:
    """A zip bomb by size: 300 MB of zeros in a zip of 300 KB."""
    with zipfile.ZipFile(upload / "big.zip", "w", zipfile.ZIP_DEFLATED) as zf, zf.open("hri_lab/bag.bag", "w") as f:
        block = bytes(2 ** 20)
        for _ in range(300):
            f.write(block)


def _outside(upload: Path) -> None:
    """A member that points outside the archive (zip-slip), next to the answer key."""
    _answer_key_zip(upload / "hri_lab.zip", lambda zf: _member(zf, "../../../../tmp/hri-zip-slip", b"x"))


def _bad_utf8_flagged(upload: Path) -> None:
    """A zip whose member's name is flagged UTF-8 but is not (crashed run_autograder)."""
    _answer_key_zip(upload / "hri_lab.zip", lambda zf: _member(zf, "hri_lab/n\u00e4me.txt", b"x"))
    data = (upload / "hri_lab.zip").read_bytes()
    (upload / "hri_lab.zip").write_bytes(data.replace("n\u00e4me".encode(), b"n\xff\xfeme"))


def _bad_utf8_names(upload: Path) -> None:
    """The answer key in a zip named with bytes that are not UTF-8, a loose file named so, and a link whose
    name holds a newline (named in the output: one line still)."""
    _answer_key_zip(upload / os.fsdecode(b"Abgabe-\xe4.zip"))
    (upload / os.fsdecode(b"notes-\xff.txt")).write_text("x")
    (upload / "two\nlines").symlink_to("/etc/passwd")


def _empty(upload: Path) -> None:
    upload.mkdir(parents=True, exist_ok=True)


def _empty_zip(upload: Path) -> None:
    (upload / "hri_lab.zip").write_bytes(b"")


def _not_json_notebook(upload: Path) -> None:
    """The answer key, and the course's notebook replaced by text that is not JSON."""
    _answer_key_zip(upload / "hri_lab.zip")
    (upload / NOTEBOOK).write_text("<script>alert(1)</script> this is not JSON")


UPLOADS: Dict[str, Callable[[Path], None]] = {
    "honest": _honest, "file_and_folder": _file_and_folder, "folder_then_file": _folder_then_file,
    "link_member": _link_member, "fifo_member": _fifo_member, "linked_folder": _linked_folder,
    "many_files": _many_files, "big": _big, "outside": _outside, "bad_utf8_flagged": _bad_utf8_flagged,
    "bad_utf8_names": _bad_utf8_names, "empty": _empty, "empty_zip": _empty_zip,
    "not_json_notebook": _not_json_notebook,
}


def _grade(folder: Path, name: str, build: Callable[[Path], None],
           monkeypatch: Optional[pytest.MonkeyPatch] = None) -> dict:
    """results.json of ``build``'s upload graded by container.main in Gradescope's folders under ``folder``."""
    root = folder / name
    upload = root / "submission"
    upload.mkdir(parents=True)
    build(upload)
    course = root / "source" / COURSE / "source" / "preparation"
    course.mkdir(parents=True)
    shutil.copy(COURSE_DIR / "source" / "preparation" / NOTEBOOK, course)
    (root / "submission_metadata.json").write_text(json.dumps({"users": [{"sid": name}]}))
    try:  # what a crash would leave: the payload says so, and this upload's tests fail, not the others'
        container.main(["--root", str(root)])
    except Exception as exc:  # noqa: BLE001 - any crash is the finding
        return {"crashed": f"{type(exc).__name__}: {exc}"}
    results = root / "results" / "results.json"
    if not results.is_file():
        return {"crashed": "no results.json"}
    return json.loads(results.read_bytes().decode("utf-8"))  # strict UTF-8: a parser that is not Python's reads it


def _scratch_in(folder: Path) -> SimpleNamespace:
    """A stand-in for container's ``tempfile`` that makes its scratch folders in ``folder`` (removed with it)."""
    return SimpleNamespace(mkdtemp=lambda prefix="": tempfile.mkdtemp(prefix=prefix, dir=folder))


@pytest.fixture(scope="module")
def graded() -> Iterator[Dict[str, dict]]:
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(CHECKS_ENV, CHECK)
        for folder in open_folder("hri-hostile-uploads-"):
            (folder / "tmp").mkdir()
            mp.setattr(container, "tempfile", _scratch_in(folder / "tmp"))  # run_autograder's scratch goes with it
            yield {name: _grade(folder, name, build) for name, build in UPLOADS.items()}


def _no_surrogates(value: object) -> bool:
    if isinstance(value, str):
        return not any(0xD800 <= ord(c) <= 0xDFFF for c in value)
    if isinstance(value, dict):
        return all(_no_surrogates(k) and _no_surrogates(v) for k, v in value.items())
    if isinstance(value, list):
        return all(_no_surrogates(v) for v in value)
    return True


@pytest.mark.parametrize("name", sorted(UPLOADS))
def test_every_upload_gets_a_valid_results_json_without_a_traceback(graded, name):
    payload = graded[name]
    assert "crashed" not in payload, payload
    assert isinstance(payload["score"], (int, float)) and isinstance(payload["tests"], list)
    text = json.dumps(payload)
    assert "Traceback" not in text and 'File "/' not in text, text
    assert _no_surrogates(payload), payload
    assert payload.get("output_format") == "text"
    assert payload["score"] <= check_points(CHECK) + 1e-9


def test_the_honest_upload_in_the_same_batch_keeps_its_full_points(graded):
    payload = graded["honest"]
    assert payload["score"] == pytest.approx(check_points(CHECK)), payload


def _output(payload: dict) -> str:
    assert "crashed" not in payload, payload
    return str(payload.get("output", ""))


def _line(payload: dict, needle: str) -> str:
    """The one line of the output naming ``needle`` (the test fails when there is none)."""
    lines = [line for line in _output(payload).splitlines() if needle in line]
    assert lines, f"no line names {needle!r} in:\n{_output(payload)}"
    return lines[0]


@pytest.mark.parametrize("name", ["file_and_folder", "folder_then_file"])
def test_a_file_and_a_folder_of_the_same_name_are_named_and_the_rest_is_graded(graded, name):
    line = _line(graded[name], "a file and a folder of the same name")
    assert "hri_lab/config" in line and "left out" in line
    assert graded[name]["tests"], "the rest of the upload is graded"
    if name == "folder_then_file":  # the folder came first: the params are there, and right
        assert graded[name]["score"] == pytest.approx(check_points(CHECK))


@pytest.mark.parametrize("name, why", [("link_member", "a link"), ("fifo_member", "not a regular file")])
def test_links_and_special_files_in_a_zip_are_left_out_and_named(graded, name, why):
    line = _line(graded[name], _PARAMS)
    assert why in line and "left out" in line
    assert graded[name]["score"] < check_points(CHECK)  # robot_params.yaml missing: not the honest score
    assert "root:" not in json.dumps(graded[name])


def test_a_linked_package_folder_is_not_followed_and_the_student_is_told(graded):
    payload = graded["linked_folder"]
    assert "a link" in _line(payload, "hri_lab")
    assert "not a regular file" in _line(payload, "robot_params.yaml")
    assert payload["score"] == 0.0  # another student's package earns nothing


@pytest.mark.parametrize("name, words", [("many_files", "more than 5000 files"), ("big", "more than 200 MB"),
                                         ("outside", "points outside the archive"),
                                         ("bad_utf8_flagged", "not a readable zip"),
                                         ("empty_zip", "not a readable zip")])
def test_an_upload_that_cannot_be_opened_is_refused_in_one_line(graded, name, words):
    payload = graded[name]
    assert payload["score"] == 0.0 and payload["tests"] == []
    assert len(_output(payload).splitlines()) == 1 and words in _output(payload), _output(payload)
    assert not Path("/tmp/hri-zip-slip").exists()


def test_names_that_are_not_utf8_are_shown_with_a_replacement_character(graded):
    payload = graded["bad_utf8_names"]
    assert "Abgabe-\ufffd.zip" in _output(payload), _output(payload)
    assert "two?lines (a link" in _line(payload, "left out of the upload")
    assert payload["score"] == pytest.approx(check_points(CHECK))  # the package in it is graded


def test_an_empty_upload_says_what_to_upload(graded):
    assert "upload your hri_lab folder" in _line(graded["empty"], "found none of the package's files")
    assert graded["empty"]["score"] == 0.0


def test_a_notebook_that_is_not_json_fails_its_cells_with_the_reason_and_the_files_keep_their_points(graded):
    payload = graded["not_json_notebook"]
    cells = [t for t in payload["tests"] if t["name"].startswith(f"preparation/{NOTEBOOK}")]
    assert cells and all(t["score"] == 0 for t in cells)
    assert all("is not a Jupyter notebook (not JSON)" in t["output"] and "save it" in t["output"] for t in cells)
    assert not any("course staff will regrade" in t["output"] for t in cells)  # the upload's fault, not the grader's
    files = [t for t in payload["tests"] if not t["name"].startswith("preparation/")]
    assert sum(t["score"] for t in files) == pytest.approx(check_points(CHECK))


def test_a_grader_that_stops_on_an_upload_still_writes_one_line(tmp_path, monkeypatch):
    monkeypatch.setattr(container, "tempfile", _scratch_in(tmp_path))
    def crash(*args: object, **kwargs: object) -> None:
        raise IsADirectoryError(21, "Is a directory", "/tmp/x/hri_lab/config")

    monkeypatch.setattr(container, "find_upload", crash)
    (tmp_path / "submission").mkdir()
    assert container.main(["--root", str(tmp_path)]) == 0
    payload = json.loads((tmp_path / "results" / "results.json").read_text(encoding="utf-8"))
    assert payload["score"] == 0.0 and payload["tests"] == []
    assert len(_output(payload).splitlines()) == 1 and "IsADirectoryError" in _output(payload)
    assert "Traceback" not in _output(payload)


def test_run_autograder_writes_results_when_python_cannot_even_start(tmp_path):
    """The shell script alone, in Gradescope's folders, with no .venv: results.json still holds one line."""
    if shutil.which("bwrap") is None or subprocess.run(["bwrap", "--dev-bind", "/", "/", "true"]).returncode:
        pytest.skip("bubblewrap cannot run here: the Gradescope layout needs it to mount /autograder")
    from test_gradescope import _box

    source = tmp_path / "source"
    source.mkdir()
    shutil.copy(REPO / "hri_teleop" / "grading" / "gradescope" / "files" / "run_autograder", source)
    (tmp_path / "box" / "ag" / "submission").mkdir(parents=True)
    proc = _box(tmp_path / "box", source, ["/autograder/source/run_autograder"], {}, timeout_s=60)
    results = tmp_path / "box" / "ag" / "results" / "results.json"
    assert proc.returncode == 0 and results.is_file(), proc.stdout + proc.stderr
    payload = json.loads(results.read_text(encoding="utf-8"))
    assert payload["score"] == 0 and payload["tests"] == [], payload
    assert payload["output"].startswith("Not graded: the autograder stopped (status ") and "\n" not in payload["output"]


def test_loose_files_past_the_size_or_count_limit_refuse_the_upload(tmp_path, monkeypatch):
    from hri_teleop.grading.gradescope import layout
    from hri_teleop.grading.results import GradingError

    monkeypatch.setattr(layout, "MAX_UNPACKED_BYTES", 1000)
    (tmp_path / "big").mkdir()
    (tmp_path / "big" / "bag.bag").write_bytes(bytes(2000))
    with pytest.raises(GradingError, match="the upload is larger than"):
        layout.find_upload(tmp_path / "big", tmp_path / "work-big")
    monkeypatch.setattr(layout, "MAX_UPLOAD_FILES", 3)
    (tmp_path / "many").mkdir()
    for i in range(5):
        (tmp_path / "many" / f"{i}.txt").write_text("x")
    with pytest.raises(GradingError, match="holds more than 3 files"):
        layout.find_upload(tmp_path / "many", tmp_path / "work-many")
