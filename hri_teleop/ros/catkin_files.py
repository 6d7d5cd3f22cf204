"""What the handout's catkin steps leave in a package, read without building it.

Ex. 9 and Ex. 12 c) have students make a script executable and list it in the package's
``CMakeLists.txt`` (``catkin_install_python(PROGRAMS ...)``) before building the workspace.
These functions read those two facts, and turn a failed ``catkin_make`` log into the one line
a student can act on. Plain text in, plain values out: the grader, the notebooks and the
workspace builder share them.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path
from typing import List, Union

__all__ = ["installed_programs", "is_executable", "explain_build_failure"]

_COMMENT = re.compile(r"#[^\n]*")
_INSTALL = re.compile(r"catkin_install_python\s*\((?P<args>[^)]*)\)", re.IGNORECASE)
_KEYWORDS = {"PROGRAMS", "DESTINATION", "OPTIONAL"}


def installed_programs(cmake_text: str) -> List[str]:
    """The scripts every ``catkin_install_python(PROGRAMS ...)`` of a CMakeLists.txt lists, as written.

    Comments are ignored (a commented-out entry installs nothing); quotes are removed;
    the DESTINATION's value is not a program.
    """
    programs: List[str] = []
    for match in _INSTALL.finditer(_COMMENT.sub("", cmake_text)):
        words = [w.strip('"') for w in match.group("args").split()]
        if not words or words[0].upper() != "PROGRAMS":
            continue
        skip_next = False
        for word in words[1:]:
            if skip_next:
                skip_next = False
                continue
            if word.upper() == "DESTINATION":
                skip_next = True
                continue
            if word.upper() in _KEYWORDS:
                continue
            programs.append(word)
    return programs


def is_executable(path: Union[str, Path]) -> bool:
    """True if the file exists and its owner may execute it (``chmod +x``), as rosrun requires."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISREG(mode) and bool(mode & stat.S_IXUSR)


def explain_build_failure(log_text: str, package_dir: Union[str, Path] = "hri_lab") -> str:
    """The cause of a failed ``catkin_make``, as one line naming the file and the fix."""
    missing = re.search(r"catkin_install_python\(\) called with\s+non-existing file\s+'([^']+)'", log_text)
    if missing:
        name = Path(missing.group(1)).name
        return (f"CMakeLists.txt lists scripts/{name}, which does not exist: correct the name in "
                f"catkin_install_python(PROGRAMS ...) or put the file into {package_dir}/scripts/")
    parse = re.search(r"CMake Error at [^\n]*CMakeLists\.txt:(\d+)[^\n]*\n\s*Parse error\.\s*([^\n]+)", log_text)
    if parse:
        return (f"CMakeLists.txt line {parse.group(1)} is not valid CMake ({parse.group(2).strip()}): "
                "compare it with the lines around it (every '(' needs its ')')")
    manifest = re.search(r"Error\(s\) in package '[^']*package\.xml':", log_text)
    if manifest:
        detail = re.search(r"^- ([^\n]+)", log_text[manifest.end():], re.M)
        reason = f" ({detail.group(1).strip()})" if detail else ""
        return f"package.xml is not a valid catkin manifest{reason}; restore it from the released version"
    errors = [line.strip() for line in log_text.splitlines() if line.strip()
              and ("Error" in line or "error:" in line) and not line.lstrip().startswith("####")]
    if errors:
        return f"catkin_make failed: {errors[0]}"
    return "catkin_make failed (see catkin_ws/build.log)"
