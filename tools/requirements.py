"""Print the requirements pyproject.toml names, one per line: ``dependencies`` and the extras given.

tools/setup.sh builds .venv38 (Python 3.8) from them without installing the project itself, beside
.venv's install. It runs on a bare Python 3.8 (no tomllib, no tomli), so it reads the two arrays
itself: pyproject.toml writes each requirement as one double-quoted string per line.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path
from typing import List

PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"


def array(text: str, name: str) -> List[str]:
    """The strings of the TOML array ``name = [...]`` (one per line, comments allowed)."""
    found = re.search(rf"^{re.escape(name)} = \[\n(.*?)^\]", text, re.S | re.M)
    if found is None:
        raise SystemExit(f"tools/requirements.py: no array {name!r} in {PYPROJECT}; name 'dependencies' or an extra")
    strings = []
    for line in found.group(1).splitlines():
        match = re.match(r'\s*("(?:[^"\\]|\\.)*")\s*,?\s*(#.*)?$', line)
        if match:
            strings.append(json.loads(match.group(1)))
        elif line.strip() and not line.strip().startswith("#"):
            raise SystemExit(f"tools/requirements.py: cannot read {line.strip()!r} in {name} of {PYPROJECT}")
    return strings


def main(names: List[str]) -> int:
    text = PYPROJECT.read_text(encoding="utf-8")
    for name in names or ["dependencies"]:
        print("\n".join(array(text, name)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
