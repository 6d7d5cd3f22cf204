"""One row per benchmark figure, printed as a Markdown table (the README's performance table).

Why a row carries both numbers: a figure alone (say "rumble 1.4 ms after the force") says
little on a shared machine; beside the floor measured in the same run it does.
"""

from __future__ import annotations

import json
import math
import os
import platform
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence

from hri_teleop.core.errors import HriTeleopError

__all__ = ["BenchError", "BenchOptions", "BenchRow", "HEADER", "format_row", "machine_summary", "write_results"]


class BenchError(HriTeleopError, RuntimeError):
    """A benchmark could not run (what is missing and how to get it)."""


@dataclass(frozen=True)
class BenchOptions:
    """What every benchmark is given.

    ``smoke``: tiny sizes (make test proves each benchmark runs, not how fast);
    ``out_dir``: where a benchmark keeps its working files and plots;
    ``jobs``: the parallelism "all cores" means (None: the machine's cores).
    """

    out_dir: Path
    smoke: bool = False
    jobs: Optional[int] = None


@dataclass(frozen=True)
class BenchRow:
    """One figure and its reference, measured in the same run.

    ``ratio`` is figure / reference as ``ratio_means`` says (e.g. "p50 / floor p50");
    ``values`` holds the raw numbers with units in their keys (``p50_ms``, ``rtf``).
    """

    benchmark: str
    figure: str
    reference: str
    ratio: float
    ratio_means: str
    values: Dict[str, float] = field(default_factory=dict)


HEADER = ("| benchmark | figure | reference (same run) | ratio |\n"
          "|---|---|---|---|")


def _ratio_text(ratio: float) -> str:
    if not math.isfinite(ratio):
        return "n/a"
    return f"{ratio:.3g}×" if ratio < 100 else f"{ratio:.0f}×"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")  # a "|" inside a cell would split the Markdown row


def format_row(row: BenchRow) -> str:
    """The row as a Markdown table line: ``| name | figure | reference | 2.5× (p50 / floor) |``."""
    cells = (row.benchmark, row.figure, row.reference, f"{_ratio_text(row.ratio)} ({row.ratio_means})")
    return "| " + " | ".join(_cell(c) for c in cells) + " |"


def machine_summary() -> str:
    """One line naming the machine the figures come from (CPU model, cores, OS, Python)."""
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    cores = os.cpu_count() or 0
    os_name = platform.platform(terse=True)
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if line.startswith("PRETTY_NAME="):
                os_name = line.split("=", 1)[1].strip('"')
    except OSError:
        pass
    return f"{cpu or platform.processor() or 'unknown CPU'}, {cores} cores, {os_name}, Python {platform.python_version()}"


def write_results(rows: Sequence[BenchRow], out_dir: Path, machine: str, extra: Iterable[str] = ()) -> List[Path]:
    """results.json (every value) and results.md (the table) in ``out_dir``."""
    out_dir.mkdir(parents=True, exist_ok=True)
    json_path, md_path = out_dir / "results.json", out_dir / "results.md"
    json_path.write_text(json.dumps({"machine": machine, "rows": [asdict(r) for r in rows]}, indent=2) + "\n")
    lines = [f"Machine: {machine}", "", HEADER, *(format_row(r) for r in rows), *extra]
    md_path.write_text("\n".join(lines) + "\n")
    return [json_path, md_path]
