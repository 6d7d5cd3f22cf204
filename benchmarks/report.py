"""One row per benchmark figure, printed as a Markdown table (the README's performance table).

Why a row carries both numbers: a figure alone (say "rumble 1.4 ms after the force") says
little on a shared machine; beside the floor measured in the same run it does. Each row also
names its machine and whether that machine was idle (benchmarks/machine.py).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence

from benchmarks.machine import Machine
from hri_teleop.core.errors import HriTeleopError

__all__ = ["BenchError", "BenchOptions", "BenchRow", "HEADER", "format_row", "write_results"]


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
    ``values`` holds the raw numbers with units in their keys (``p50_ms``, ``rtf``);
    ``machine``: where and how loaded (``python -m benchmarks`` fills it in for every row).
    """

    benchmark: str
    figure: str
    reference: str
    ratio: float
    ratio_means: str
    values: Dict[str, float] = field(default_factory=dict)
    machine: Optional[Machine] = None


HEADER = ("| benchmark | figure | reference (same run) | ratio | machine |\n"
          "|---|---|---|---|---|")


def _ratio_text(ratio: float) -> str:
    if not math.isfinite(ratio):
        return "n/a"
    return f"{ratio:.3g}×" if ratio < 100 else f"{ratio:.0f}×"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")  # a "|" inside a cell would split the Markdown row


def format_row(row: BenchRow) -> str:
    """The row as a Markdown table line: ``| name | figure | reference | 2.5× (p50 / floor) | machine |``."""
    cells = (row.benchmark, row.figure, row.reference, f"{_ratio_text(row.ratio)} ({row.ratio_means})",
             row.machine.text() if row.machine is not None else "not recorded")
    return "| " + " | ".join(_cell(c) for c in cells) + " |"


def write_results(rows: Sequence[BenchRow], out_dir: Path, machine: Machine, extra: Iterable[str] = ()) -> List[Path]:
    """results.json (every value, each row's machine) and results.md (the table) in ``out_dir``;
    ``machine``: as sampled when the run started."""
    out_dir.mkdir(parents=True, exist_ok=True)
    json_path, md_path = out_dir / "results.json", out_dir / "results.md"
    json_path.write_text(json.dumps({"machine": asdict(machine), "machine_text": machine.summary(),
                                     "rows": [asdict(r) for r in rows]}, indent=2) + "\n")
    lines = [f"Machine: {machine.summary()}", "", HEADER, *(format_row(r) for r in rows), *extra]
    md_path.write_text("\n".join(lines) + "\n")
    return [json_path, md_path]
