"""pytest plugin for `make mutants`: a mutant is judged by the unit tests of its own module only.

mutmut runs, for each mutant, the tests that reached the mutated function in its first run. Many of
those reach it in passing (the teleoperation tests run the velocity limiter, the simulation runs the
joint judge); a mutant they kill says nothing about the module's own tests. Loaded with
``-p tools.mutants_scope`` (pyproject.toml's [tool.mutmut]), this plugin reads the mutant's name from
``MUTANT_UNDER_TEST`` and deselects every test outside the files that [tool.hri-teleop.mutants] names
for the mutant's module. With none left, pytest exits 5 and mutmut counts the mutant "no tests".
Outside a mutant's run (mutmut's first run, the clean and the forced-fail run) it does nothing.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - mutmut 3 needs Python 3.10; tomli is the test extra's on 3.10
    import tomli as tomllib

MUTANT_MARK = "__mutmut_"


def module_tests(pyproject: Path) -> Dict[str, List[str]]:
    """[tool.hri-teleop.mutants]: module path (hri_teleop/core/joints.py) -> its unit test files."""
    data = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    table = data.get("tool", {}).get("hri-teleop", {}).get("mutants", {})
    return {str(k): [str(t) for t in v] for k, v in table.items()}


def module_of_mutant(name: str) -> Optional[str]:
    """``hri_teleop.core.joints.xǁJointLimitWatchǁupdate__mutmut_3`` -> ``hri_teleop/core/joints.py``.

    mutmut names a mutant after its module, then ``x_`` and the function, or ``xǁClassǁmethod``.
    """
    if MUTANT_MARK not in name:
        return None
    parts = name.split(".")
    for i, part in enumerate(parts):
        if part.startswith("x_") or part.startswith("x\u01c1"):
            return "/".join(parts[:i]) + ".py"
    return None


def scope_for(name: str, table: Dict[str, List[str]]) -> Optional[Tuple[str, List[str]]]:
    """(module path, its test files) for a mutant's name; None when the name is no mutant's."""
    module = module_of_mutant(name)
    if module is None:
        return None
    if module not in table:
        package = module[: -len(".py")] + "/__init__.py"
        module = package if package in table else module
    return module, table.get(module, [])


def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: List[pytest.Item]) -> None:
    scope = scope_for(os.environ.get("MUTANT_UNDER_TEST", ""), module_tests(Path(str(config.rootpath)) / "pyproject.toml"))
    if scope is None:
        return
    own = {Path(t).as_posix() for t in scope[1]}
    keep, drop = [], []
    for item in items:
        (keep if item.nodeid.split("::", 1)[0] in own else drop).append(item)
    if drop:
        config.hook.pytest_deselected(items=drop)
        items[:] = keep
