"""Ex. 3 and 4: the grader works out the notebook's ``rosparam`` commands itself, in a box.

The values of those cells are what the student's commands leave on a server. A kernel can report any value
(a hook rewrites what it reads back), so the grader does not take it: it reads the notebook handed in, takes
the shell lines of its code cells (:func:`hri_teleop.core.rosparam_model.shell_commands`) and has a probe
work them out on a fresh model server (``probe rosparam-commands``), with copies of the files they load.
Files and YAML are a student's, so they are read as any submitted file and parsed only in the box.
"""

from __future__ import annotations

import json
import os
import posixpath
import shutil
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.rosparam_model import shell_commands
from hri_teleop.grading.judge.harness import grader_shell_env, isolated_module_argv
from hri_teleop.grading.judge.notebook_answers import COMMAND_CELLS, command_values
from hri_teleop.grading.run.records import RosparamCommandsResult
from hri_teleop.grading.run.sandbox import DEFAULT_LIMITS, StudentProcess, student_uid
from hri_teleop.grading.run.untrusted_files import read_regular

__all__ = ["student_sources", "named_files", "work_out", "command_cells_values"]

#: A file a command loads (the probe refuses larger ones as well).
_FILE_CAP_BYTES = 256 * 1024
_RESULT_CAP_BYTES = 4 * 1024 ** 2
_PROBE_TIMEOUT_S = 30.0


def student_sources(notebook: Mapping[str, Any]) -> List[str]:
    """The sources of the notebook's code cells in order, without its autograded test cells (nbgrader put the
    course's source back in those; the student's commands are in the others)."""
    sources = []
    cells = notebook.get("cells")
    for cell in cells if isinstance(cells, list) else []:
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        meta = cell.get("metadata")
        nbgrader = meta.get("nbgrader") if isinstance(meta, dict) else None
        if isinstance(nbgrader, dict) and nbgrader.get("grade") is True and nbgrader.get("solution") is not True:
            continue
        source = cell.get("source")
        sources.append("".join(source) if isinstance(source, list) else str(source or ""))
    return sources


def named_files(commands: Sequence[Sequence[str]]) -> List[str]:
    """The files the commands read (``load FILE``, ``set -t FILE``), as written, inside the folder only."""
    found = []
    for argv in commands:
        args = list(argv[2:])
        if len(argv) > 1 and argv[1] == "load":
            found += [a for a in args if not a.startswith("-")][:1]
        elif len(argv) > 1 and argv[1] == "set":
            found += [args[i + 1] for i, a in enumerate(args[:-1]) if a in ("-t", "--textfile", "-b", "--binfile")]
    inside = []
    for name in found:
        normal = posixpath.normpath(name)
        if not posixpath.isabs(normal) and normal != ".." and not normal.startswith("../") and normal not in inside:
            inside.append(normal)
    return inside


def _copy_in(folder: Path, scratch: Path, names: Sequence[str], uid: Optional[int]) -> Dict[str, str]:
    """Copies of ``names`` from the submission's ``folder`` (regular files only, no link on the way); the
    names refused, with why (named from the folder), for the probe to say."""
    refused = {}
    for name in names:
        if not os.path.lexists(folder / name):
            continue  # the probe says, as rosparam would, that it does not exist
        try:
            data = read_regular(folder / name, _FILE_CAP_BYTES, root=folder)
        except OSError as exc:  # UntrustedFileError: a link, a FIFO, a folder, too large
            refused[name] = " ".join(str(exc).replace(f"{folder}/", "").split())[:200]
            continue
        target = scratch / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
    if uid is not None:
        for root, dirs, files in os.walk(scratch):
            for entry in [root, *(os.path.join(root, d) for d in dirs), *(os.path.join(root, f) for f in files)]:
                os.chown(entry, uid, uid)
    return refused


def work_out(folder: Path, commands: Sequence[Sequence[str]]) -> Tuple[Optional[RosparamCommandsResult], str]:
    """(the probe's result, "") for ``commands`` run against copies of their files from ``folder``, or (None, why
    the grader could not work them out)."""
    uid = student_uid()
    scratch = Path(tempfile.mkdtemp(prefix="hri-grade-commands-"))
    try:
        os.chmod(scratch, 0o755)
        box = scratch / "folder"
        box.mkdir()
        refused = _copy_in(folder, box, named_files(commands), uid)
        plan = box / ".commands.json"
        plan.write_text(json.dumps({"commands": [list(a) for a in commands], "refused": refused}), encoding="utf-8")
        out = box / ".result.json"
        if uid is not None:
            os.chown(box, uid, uid)
            os.chown(plan, uid, uid)
        env = dict(grader_shell_env(), HOME=str(box), PYTHONDONTWRITEBYTECODE="1")
        argv = isolated_module_argv("hri_teleop.grading.run.probe", ["rosparam-commands", str(plan), str(out)])
        proc = StudentProcess(argv, box, env, scratch / "probe.log", DEFAULT_LIMITS, uid=uid, nested=True,
                              network=False)
        code = proc.wait(_PROBE_TIMEOUT_S)
        proc.stop()
        if code != 0:
            tail = proc.output_tail(600).strip().splitlines()
            return None, f"the probe ended with status {proc.returncode}" + (f": {tail[-1]}" if tail else "")
        try:
            result = RosparamCommandsResult.from_json(json.loads(read_regular(out, _RESULT_CAP_BYTES, root=box)))
        except (OSError, ValueError) as exc:
            return None, f"the probe's result cannot be read ({type(exc).__name__})"
        return (result, "") if result.ok else (None, result.error)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def command_cells_values(folder: Path, notebook: Mapping[str, Any], grade_ids: Sequence[str]
                         ) -> Dict[str, Dict[str, Any]]:
    """grade id -> the values its rule judges, for the :data:`COMMAND_CELLS` among ``grade_ids``, worked out
    from ``notebook``'s commands (files named from ``folder``, the notebook's); {} when there are none.
    When the commands cannot be worked out, each gets ``{"not_judged": why}``."""
    wanted = [g for g in grade_ids if g in COMMAND_CELLS]
    if not wanted:
        return {}
    commands = shell_commands(student_sources(notebook))
    result, why = work_out(folder, commands)
    if result is None:
        return {g: {"not_judged": f"the grader could not work out your notebook's rosparam commands ({why})"}
                for g in wanted}
    return {g: command_values(g, result.tree, result.dumps, result.notes) for g in wanted}
