"""``make pins``: constraints.txt, the exact versions of one term, from the installed environments.

Every path that installs the toolkit (``make setup``, the student bundle's setup, Gradescope's
setup.sh, all through tools/setup.sh) installs with ``-c constraints.txt``, so a student, the
grader and CI get the versions this term was tested with. The rows come from ``.venv`` (Python
3.11) and ``.venv38`` (Python 3.8, the lab PCs'); each row holds for the Python versions it was
installed on, and another Python resolves freely (docs/testing.md, "Pinned versions").

    python tools/pins.py [--out constraints.txt]
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

from packaging.utils import canonicalize_name

REPO = Path(__file__).resolve().parents[1]
#: (folder of the environment, the Python version it runs) -- the environments a term is tested on.
ENVIRONMENTS: Tuple[Tuple[str, str], ...] = ((".venv", "3.11"), (".venv38", "3.8"))
HEADER = """\
# The exact versions of this term's toolkit (make pins writes this file from .venv and .venv38).
# tools/setup.sh installs with `-c constraints.txt`: make setup, the student bundle, Gradescope.
# A row holds on the Python versions named in its marker; other Pythons resolve freely.
"""
_ROW = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;]+)$")


def parse_freeze(text: str) -> Dict[str, str]:
    """``name==version`` lines of ``pip freeze`` (canonical name -> version); direct references and
    editable installs are left out: they name a path of one machine."""
    pins: Dict[str, str] = {}
    for line in text.splitlines():
        found = _ROW.match(line.strip())
        if found:
            pins[canonicalize_name(found.group(1))] = found.group(2)
    return pins


def marker(versions: Sequence[str]) -> str:
    """The environment marker of a row that holds on ``versions`` (``python_version == "3.8" or ...``)."""
    return " or ".join(f'python_version == "{v}"' for v in sorted(versions, key=lambda v: tuple(map(int, v.split(".")))))


def merge(pins: Mapping[str, Mapping[str, str]]) -> List[str]:
    """Constraint rows from each Python version's pins (version -> name -> version), sorted by name:
    one row per package and version, with the Python versions it was installed on."""
    rows: List[str] = []
    names = sorted({name for found in pins.values() for name in found})
    for name in names:
        by_version: Dict[str, List[str]] = {}
        for python, found in pins.items():
            if name in found:
                by_version.setdefault(found[name], []).append(python)
        for version in sorted(by_version):
            rows.append(f"{name}=={version}; {marker(by_version[version])}")
    return rows


def freeze(python: Path) -> Dict[str, str]:
    """What ``python``'s environment holds of its own (not the system's site packages)."""
    done = subprocess.run([str(python), "-m", "pip", "freeze", "--local", "--exclude-editable",
                           "--disable-pip-version-check"], capture_output=True, text=True, check=True)
    return parse_freeze(done.stdout)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO / "constraints.txt")
    args = parser.parse_args(argv)
    pins: Dict[str, Dict[str, str]] = {}
    for folder, version in ENVIRONMENTS:
        python = REPO / folder / "bin" / "python"
        if not python.exists():
            print(f"pins: {folder} is missing: run `make setup` (it builds .venv, and .venv38 where a "
                  "Python 3.8 is found) first", file=sys.stderr)
            return 1
        pins[version] = freeze(python)
    rows = merge(pins)
    args.out.write_text(HEADER + "\n".join(rows) + "\n", encoding="utf-8")
    print(f"pins: {len(rows)} rows for Python {', '.join(v for _, v in ENVIRONMENTS)} in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
