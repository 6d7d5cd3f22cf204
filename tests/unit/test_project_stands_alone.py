"""The project stands alone: no file points at material outside the repository.

The lab's facts live in docs/lab-facts.md; the handout is cited by its title and exercise
number. A path into a neighbouring folder works on one machine and nowhere else.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SKIP_DIRS = {".git", ".venv", ".venv38", "out", "build", "__pycache__", ".pytest_cache", "hri_teleop.egg-info"}
TEXT = {".py", ".md", ".yaml", ".yml", ".launch", ".ipynb", ".txt", ".cfg", ".toml", ".sh", ".xml", ".cpp", ".h",
        ".ino", ".json", ".in", ""}
#: The neighbouring folder and page the course was written beside, spelled in parts so that this
#: file does not itself name them.
_NEIGHBOUR, _PAGE = "sha" + "red", "des" + "ign"
OUTSIDE = re.compile(rf"\.\./{_NEIGHBOUR}\b|\b{_NEIGHBOUR}/handout\b|\b{_PAGE}\.md\b")


def _project_files():
    for path in ROOT.rglob("*"):
        rel = path.relative_to(ROOT)
        if any(part in SKIP_DIRS for part in rel.parts) or not path.is_file() or path.suffix not in TEXT:
            continue
        if path.name == Path(__file__).name:
            continue
        yield rel, path


def test_no_project_file_refers_to_material_outside_the_repository():
    hits = []
    for rel, path in _project_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue
        for number, line in enumerate(text.splitlines(), 1):
            if OUTSIDE.search(line):
                hits.append(f"{rel}:{number}: {line.strip()[:100]}")
    assert hits == [], "files refer outside the project (cite docs/lab-facts.md or the handout by title):\n" + "\n".join(hits)


def test_the_pattern_catches_each_outside_reference():
    for line in (f"see ../{_NEIGHBOUR}/{_PAGE}.md", f"limits ({_PAGE}.md)", f"the handout ({_NEIGHBOUR}/handout/task4.md)"):
        assert OUTSIDE.search(line), line
    assert not OUTSIDE.search("see docs/lab-facts.md and the handout, Ex. 8")


def test_the_lab_facts_page_quotes_the_limits_the_code_enforces():
    from hri_teleop.core.limits import ROBOT_LIMITS
    from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M

    facts = (ROOT / "docs" / "lab-facts.md").read_text(encoding="utf-8")
    t, r = ROBOT_LIMITS.translation, ROBOT_LIMITS.rotation
    row_t = f"| translation | {t.velocity:g} m/s | {t.acceleration:g} m/s² | {t.jerk:g} m/s³ |"
    row_r = f"| rotation | {r.velocity:g} rad/s | {r.acceleration:g} rad/s² | {r.jerk:g} rad/s³ |"
    assert row_t in facts and row_r in facts
    assert f"0..{GRIPPER_MAX_WIDTH_M:g} m" in facts
    from hri_teleop.core.joints import ROBOT_JOINT_LIMITS as J

    for label, values in (("position min (rad)", J.position_min_rad), ("position max (rad)", J.position_max_rad),
                          ("velocity (rad/s)", J.velocity_rad_per_s), ("acceleration (rad/s²)", J.acceleration_rad_per_s2),
                          ("jerk (rad/s³)", J.jerk_rad_per_s3)):
        assert f"| {label} | " + " | ".join(f"{v:g}" for v in values) + " |" in facts, label
