"""What run_autograder does in Gradescope's container: find the upload, grade it, write results.json.

Paths are Gradescope's (/autograder/submission, /autograder/results/results.json); the checks and
time limits come from gradescope.json in the autograder zip. The files are graded by one
``hri-grade submission`` process; when it times out or crashes, each check runs alone, so one
check the grader could not finish costs nothing else and is named in the results' output. The
upload's notebooks of the course are then autograded by nbgrader (:mod:`.notebooks`).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.cases.inputs import seed_for, student_seed
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.gradescope.layout import find_upload, printable
from hri_teleop.grading.gradescope.notebooks import COURSE, NOTEBOOKS_TIMEOUT_S, NotebookTests, grade_notebooks
from hri_teleop.grading.gradescope.report import Unjudged, results_payload
from hri_teleop.grading.results import CheckResult, GradingError
from hri_teleop.grading.run.jobs import run_job
from hri_teleop.grading.run.kernel_sandbox import KernelPolicy

__all__ = ["CONFIG_NAME", "CHECKS_ENV", "Config", "load_config", "load_config_checks", "student_from_metadata",
           "seed_from_metadata", "grade_upload", "not_graded", "write_results", "main"]

#: The autograder's settings, at the zip's root (written by ``make gradescope``).
CONFIG_NAME = "gradescope.json"
#: Defaults: Gradescope stops a run at its own limit (10 min unless raised); ours ends first.
SUBMISSION_TIMEOUT_S = 420.0
CHECK_TIMEOUT_S = 180.0
#: Environment variable: comma-separated checks that replace the config's (e.g. a TA regrading one check).
CHECKS_ENV = "HRI_GRADESCOPE_CHECKS"


@dataclass(frozen=True)
class Config:
    """Which checks this Gradescope assignment grades, and how long the grader may take."""

    checks: Tuple[str, ...] = tuple(CHECKS)
    submission_timeout_s: float = SUBMISSION_TIMEOUT_S
    check_timeout_s: float = CHECK_TIMEOUT_S
    notebooks_timeout_s: float = NOTEBOOKS_TIMEOUT_S
    unsandboxed: bool = False   # the notebooks' kernels run with the grader's rights (make gradescope UNSANDBOXED=1)

    def to_json(self) -> Dict[str, Any]:
        return {"checks": list(self.checks), "submission_timeout_s": self.submission_timeout_s,
                "check_timeout_s": self.check_timeout_s, "notebooks_timeout_s": self.notebooks_timeout_s,
                "unsandboxed": self.unsandboxed}


def load_config(path: Path) -> Config:
    """The config at ``path`` (defaults when absent); GradingError naming a bad key or check."""
    if not path.is_file():
        return Config()
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        checks = tuple(data.get("checks", CHECKS))
        config = Config(checks, float(data.get("submission_timeout_s", SUBMISSION_TIMEOUT_S)),
                        float(data.get("check_timeout_s", CHECK_TIMEOUT_S)),
                        float(data.get("notebooks_timeout_s", NOTEBOOKS_TIMEOUT_S)), data.get("unsandboxed") is True)
    except (ValueError, TypeError, AttributeError) as exc:
        raise GradingError(f"{path}: not a valid autograder config ({exc}); rebuild it with make gradescope") from exc
    load_config_checks(config, str(path))
    return config


def load_config_checks(config: Config, where: str = CHECKS_ENV) -> None:
    """GradingError unless every check of ``config`` is known and there is one at least."""
    unknown = [c for c in config.checks if c not in CHECKS]
    if unknown or not config.checks:
        raise GradingError(f"{where}: unknown or no checks {unknown}; use some of {', '.join(CHECKS)}")


def _user_id(user: Dict[str, Any]) -> str:
    for key in ("sid", "email", "id"):
        if str(user.get(key) or "").strip():
            return str(user[key]).strip()
    return ""


def student_from_metadata(path: Path) -> Optional[str]:
    """The submitters' student id from Gradescope's metadata: each one's roster *Student ID* (``sid``; put
    the students' make grade ids there), else their email, else Gradescope's user id; a group's joined by
    ``+``. None when the metadata is missing or names no user."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        users = sorted(filter(None, (_user_id(u) for u in data.get("users", []))))
    except (OSError, ValueError, AttributeError):
        return None
    return "+".join(users) or None


def seed_from_metadata(path: Path) -> Optional[int]:
    """The hidden inputs' seed of the submitters: :func:`~hri_teleop.grading.cases.inputs.student_seed` of
    their student id (:func:`student_from_metadata`), as make grade derives it from the same id; the same
    on every resubmission and in every assignment. Gradescope grades every upload in the same folder, so
    the folder-derived seed would give the whole class the same hidden inputs. None without users."""
    student = student_from_metadata(path)
    return None if student is None else student_seed(student)


def _hri_grade(package: Path, out: Path, checks: Sequence[str], seed: Optional[int], timeout_s: float,
               log: Path) -> Tuple[List[CheckResult], Optional[str]]:
    """(results, None) or ([], why it could not finish) for ``hri-grade submission`` on ``checks``."""
    argv = [sys.executable, "-m", "hri_teleop.apps.grade", "submission", str(package), "--out", str(out),
            "--checks", ",".join(checks)]
    if seed is not None:
        argv += ["--seed", str(seed)]
    run = run_job(argv, log, timeout_s)
    if run.timed_out:
        return [], f"timed out after {timeout_s:.0f} s"
    listing = out / "checks.json"
    if run.returncode not in (0, 1) or not listing.is_file():
        lines = log.read_text(encoding="utf-8", errors="replace").strip().splitlines()
        return [], f"stopped with an error ({(lines[-1] if lines else 'no output')[:200]})"
    return [CheckResult.from_dict(d) for d in json.loads(listing.read_text(encoding="utf-8"))], None


def grade_upload_notebooks(notebooks: Sequence[Path], package: Path, course: Optional[Path], work: Path,
               timeout_s: float, seed: Optional[int], sandbox: Optional[KernelPolicy]) -> NotebookTests:
    """The course's notebooks of the upload graded; a failure of the grader is a "not judged" line, never a crash."""
    if not notebooks or course is None or not course.is_dir():
        return NotebookTests()
    try:
        # the check cells' hidden inputs are the files' tests' (seed): one student, one seed
        return grade_notebooks(notebooks, package, course, work / "notebooks", timeout_s, "student", sandbox, seed)
    except Exception as exc:  # noqa: BLE001 - whatever stops nbgrader, the files' grades must still be written
        print(f"run_autograder: grading the notebooks failed: {type(exc).__name__}: {exc}", flush=True)
        names = ", ".join(p.name for p in notebooks[:6]) + (" ..." if len(notebooks) > 6 else "")
        return NotebookTests(unjudged=[(names, f"the grader stopped with {type(exc).__name__}")])


def grade_upload(submission: Path, work: Path, config: Config, seed: Optional[int] = None,
                 course: Optional[Path] = None, hidden: Sequence[Path] = ()) -> Dict[str, Any]:
    """results.json's content for the upload in ``submission`` (scratch files under ``work``).

    ``course``: the zip's course folder; the upload's notebooks of that course are graded too, in the
    kernel sandbox unless ``config.unsandboxed``, which hides ``hidden`` (/autograder) besides the course.
    """
    started = time.monotonic()
    seed = seed_for(submission) if seed is None else seed  # one seed for the files' tests and the notebooks
    upload = find_upload(submission, work)
    notes = list(upload.notes)
    results, why = _hri_grade(upload.hri_lab, work / "out", config.checks, seed, config.submission_timeout_s,
                              work / "grader.log")
    unjudged: List[Unjudged] = []
    if why is not None:  # each check alone: what can be judged is
        print(f"run_autograder: hri-grade submission {why}; grading each check alone", flush=True)
        for check in config.checks:
            one, reason = _hri_grade(upload.hri_lab, work / f"out-{check}", [check], seed, config.check_timeout_s,
                                     work / f"grader-{check}.log")
            results += one
            if reason is not None:
                unjudged.append(Unjudged(check, reason))
    sandbox = None if config.unsandboxed else KernelPolicy(tuple(str(p) for p in (*hidden, work, submission)
                                                                  if p is not None) + ((str(course),) if course else ()))
    graded = grade_upload_notebooks(upload.notebooks, upload.hri_lab, course, work, config.notebooks_timeout_s, seed, sandbox)
    return results_payload(results, unjudged, notes + graded.notes, time.monotonic() - started, order=config.checks,
                           notebook_tests=graded.tests, notebooks_unjudged=graded.unjudged)


def not_graded(reason: str) -> Dict[str, Any]:
    """results.json of an upload that could not be graded: score 0 and ``reason`` in one line."""
    line = printable(" ".join(reason.split()))[:500]
    return {"score": 0.0, "tests": [], "visibility": "visible", "stdout_visibility": "hidden",
            "output_format": "text", "output": f"Not graded: {line}"}


def write_results(results_file: Path, payload: Dict[str, Any]) -> None:
    """``payload`` as results.json: valid UTF-8 JSON whatever bytes the upload's names held."""
    text = json.dumps(payload, indent=2, ensure_ascii=False)
    results_file.write_bytes(text.encode("utf-8", "replace"))


def main(argv: Optional[Sequence[str]] = None) -> int:
    """run_autograder: grade /autograder/submission into /autograder/results/results.json (``--root`` elsewhere).

    Whatever the upload holds, results.json is written: an upload that cannot be opened (GradingError) gets
    its one-line reason; a grader crash a one-line "not graded" (its traceback goes to the scratch folder's
    crash.log, for course staff)."""
    if hasattr(sys.stdout, "reconfigure"):  # a file name's stray bytes printed must not stop the run
        sys.stdout.reconfigure(errors="backslashreplace")
    args = list(sys.argv[1:] if argv is None else argv)
    root = Path(args[args.index("--root") + 1]) if "--root" in args else Path("/autograder")
    results_file = root / "results" / "results.json"
    results_file.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="hri-gradescope-"))
    work.chmod(0o755)  # the sandbox's student uid must reach its copy of the package
    try:
        config = load_config(root / "source" / CONFIG_NAME)
        if os.environ.get(CHECKS_ENV):  # a TA's rerun of some checks (and the zip's test)
            config = replace(config, checks=tuple(c.strip() for c in os.environ[CHECKS_ENV].split(",") if c.strip()))
            load_config_checks(config)
        seed = seed_from_metadata(root / "submission_metadata.json")
        if seed is None:  # not on Gradescope (a local try): one fixed seed, not one per scratch folder
            seed = seed_for(root / "submission")
        payload = grade_upload(root / "submission", work, config, seed, root / "source" / COURSE, hidden=(root,))
    except GradingError as exc:  # an upload that cannot be opened: one line for the student
        payload = not_graded(str(exc))
    except Exception as exc:  # noqa: BLE001 - whatever the upload does to the grader, results.json is written
        crash = work / "crash.log"
        crash.write_text(traceback.format_exc(), encoding="utf-8", errors="backslashreplace")
        print(f"run_autograder: the grader stopped with {type(exc).__name__}; its traceback is in {crash}", flush=True)
        payload = not_graded(f"the autograder stopped with {type(exc).__name__} on this upload; course staff will "
                             "look at it (upload your hri_lab folder, zipped or as it is, to try again)")
    write_results(results_file, payload)
    print(f"run_autograder: score {payload['score']:g}, {len(payload['tests'])} tests, scratch files in {work}")
    return 0


if __name__ == "__main__":
    os.umask(0o022)
    sys.exit(main())
