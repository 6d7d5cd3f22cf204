"""`make mutants`: mutmut over the core and the late policy, on a copy, then the survivors one per line.

mutmut 3 writes its mutants into a ``mutants/`` folder beside the code it is run in; this script runs it
in a copy of the checkout (``out/mutants/work``), so the working tree is the same before and after.
Each mutant is judged by the unit tests of its own module (tools/mutants_scope.py). At the end it
prints, per module, how many mutants mutmut made and how many survived, and each survivor as
``file:line: old -> new``; the same goes to out/mutants/survivors.txt and summary.json. Survivors that
only changed a message's text (an "XX" added, a changed case) are counted apart and listed in
out/mutants/survivors-text.txt.
docs/testing.md explains the scope, the numbers of the last full run and the equivalent mutants.

    python tools/mutants.py [--only hri_teleop/core/joints.py ...] [--jobs N] [--out out/mutants]
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import json
import os
import re
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - mutmut 3 needs Python 3.10; tomli is the test extra's on 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
SCOPE_TABLE = ("tool", "hri-teleop", "mutants")
#: mutmut's exit codes of a mutant's test run, as its own results command names them.
STATUS = {0: "survived", 1: "killed", 3: "killed", 5: "no tests", 33: "no tests", 34: "skipped",
          35: "suspicious", 36: "timeout", 37: "caught by type check", -24: "timeout", 24: "timeout",
          152: "timeout", 255: "timeout", -11: "segfault", -9: "killed (memory)", None: "not checked"}
HUNK = re.compile(r"^@@ -(\d+)(?:,\d+)? \+\d+(?:,\d+)? @@")


class MutantsError(Exception):
    """The configuration or the run cannot go on: one line naming the cause and the fix."""


def load_config(pyproject: Path = ROOT / "pyproject.toml") -> Tuple[Dict[str, object], Dict[str, List[str]]]:
    """([tool.mutmut], [tool.hri-teleop.mutants]) of ``pyproject``."""
    data = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    mutmut = data.get("tool", {}).get("mutmut")
    table: object = data
    for key in SCOPE_TABLE:
        table = table.get(key, {}) if isinstance(table, dict) else {}
    if not mutmut or not table:
        raise MutantsError(f"{pyproject} has no [tool.mutmut] or [tool.hri-teleop.mutants]; see docs/testing.md")
    return dict(mutmut), {str(k): [str(t) for t in v] for k, v in dict(table).items()}


def scope_problems(mutmut: Dict[str, object], table: Dict[str, List[str]], root: Path = ROOT) -> List[str]:
    """What makes the configuration disagree with itself or with the files (empty: it is consistent)."""
    problems = []
    only = [str(p) for p in mutmut.get("only_mutate", [])]  # type: ignore[attr-defined]
    selection = set(str(p) for p in mutmut.get("pytest_add_cli_args_test_selection", []))  # type: ignore[attr-defined]
    named = set(t for tests in table.values() for t in tests)
    for module in table:
        if not (root / module).is_file():
            problems.append(f"[tool.hri-teleop.mutants] names {module}, which does not exist")
    for test in sorted(named - selection):
        problems.append(f"{test} judges a module but is not in [tool.mutmut] pytest_add_cli_args_test_selection")
    for test in sorted(selection - named):
        problems.append(f"{test} is in pytest_add_cli_args_test_selection but judges no module")
    for test in sorted(named):
        if not (root / test).is_file():
            problems.append(f"[tool.hri-teleop.mutants] names {test}, which does not exist")
    for module in sorted(str(p.relative_to(root)) for p in (root / "hri_teleop" / "core").rglob("*.py")):
        if module not in table:
            problems.append(f"{module} has no entry in [tool.hri-teleop.mutants] (list its unit tests, or [])")
        if not any(fnmatch.fnmatch(module, pattern) for pattern in only):
            problems.append(f"{module} is not in [tool.mutmut] only_mutate")
    return problems


def toml_value(value: object) -> str:
    """A string or a list of strings as TOML (JSON's escapes are TOML's for these)."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    return json.dumps(str(value))


def work_pyproject(mutmut: Dict[str, object], table: Dict[str, List[str]], pytest_ini: Dict[str, object],
                   only: Sequence[str]) -> str:
    """The copy's pyproject.toml: pytest's settings, [tool.mutmut] (narrowed to ``only``), the scope table."""
    mutmut = dict(mutmut)
    if only:
        mutmut["only_mutate"] = list(only)
        mutmut["pytest_add_cli_args_test_selection"] = sorted({t for m in only for t in table[m]})
    lines = ["[tool.pytest.ini_options]"] + [f"{k} = {toml_value(v)}" for k, v in pytest_ini.items()]
    lines += ["", "[tool.mutmut]"] + [f"{k} = {toml_value(v)}" for k, v in mutmut.items()]
    lines += ["", "[tool.hri-teleop.mutants]"] + [f"{json.dumps(k)} = {toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def prepare(work: Path, text: str) -> None:
    """A fresh copy of what the unit tests need: the package, its lab config, the tests, the scope plugin."""
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".hypothesis", ".pytest_cache")
    shutil.copytree(ROOT / "hri_teleop", work / "hri_teleop", ignore=ignore)
    shutil.copytree(ROOT / "tests", work / "tests", ignore=ignore)
    shutil.copytree(ROOT / "hri_lab", work / "hri_lab", ignore=ignore)  # the lab's config the package reads
    (work / "tools").mkdir()
    shutil.copy2(ROOT / "tools" / "mutants_scope.py", work / "tools" / "mutants_scope.py")
    (work / "pyproject.toml").write_text(text, encoding="utf-8")


def results(work: Path) -> Iterator[Tuple[str, str, str]]:
    """(module path, mutant name, status) of every mutant mutmut made in ``work``."""
    base = work / "mutants"
    for meta in sorted(base.rglob("*.py.meta")):
        module = meta.relative_to(base).as_posix()[: -len(".meta")]
        data = json.loads(meta.read_text(encoding="utf-8"))
        for name, code in sorted(data.get("exit_code_by_key", {}).items(), key=lambda kv: _natural(kv[0])):
            yield module, name, STATUS.get(code, f"exit code {code}")


def _natural(name: str) -> Tuple[str, int]:
    head, _, number = name.rpartition("__mutmut_")
    return head, int(number) if number.isdigit() else 0


def mutant_diff(work: Path, name: str, module: str) -> str:
    """mutmut's diff of one mutant against its function (its own ``mutmut show``)."""
    here = os.getcwd()
    try:
        os.chdir(work)
        from mutmut.mutation.diff_apply import get_diff_for_mutant  # noqa: PLC0415 - mutmut only here

        return str(get_diff_for_mutant(name, path=Path(module)))
    except Exception:  # noqa: BLE001 - an internal API of mutmut; its command line says the same
        shown = subprocess.run([str(mutmut_command()), "show", name], cwd=work, capture_output=True, text=True)
        return shown.stdout
    finally:
        os.chdir(here)


def function_span(source: str, name: str) -> Optional[Tuple[int, int]]:
    """(first, last line) of the function a mutant's name points at (``x_f`` or ``xǁClassǁmethod``)."""
    tail = name.rsplit(".", 1)[-1].rsplit("__mutmut_", 1)[0]
    path = tail.split("\u01c1")[1:] if tail.startswith("x\u01c1") else [tail[len("x_"):]]
    nodes: Sequence[ast.AST] = ast.parse(source).body
    found: Optional[ast.AST] = None
    for part in path:
        found = next((n for n in nodes if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
                      and n.name == part), None)
        if found is None:
            return None
        nodes = getattr(found, "body", [])
    if found is None:
        return None
    first = min([found.lineno] + [d.lineno for d in getattr(found, "decorator_list", [])])
    return first, int(getattr(found, "end_lineno", first) or first)


def describe(diff: str, source: str, name: str) -> Tuple[int, str]:
    """(line in the module, ``old -> new``) of a mutant from its diff."""
    old, new, offset, line_in_function = [], [], 0, 0
    for text in diff.splitlines():
        hunk = HUNK.match(text)
        if hunk:
            line_in_function = int(hunk.group(1))
            continue
        if text.startswith(("---", "+++")) or not line_in_function:
            continue
        if text.startswith("-"):
            old.append(text[1:].strip())
            offset = offset or line_in_function
            line_in_function += 1
        elif text.startswith("+"):
            new.append(text[1:].strip())
        elif not old:
            line_in_function += 1
    span = function_span(source, name)
    line = 0
    if span is not None:
        line = span[0] + max(offset, 1) - 1
        lines = source.splitlines()
        if old:
            for number in range(span[0], span[1] + 1):
                if lines[number - 1].strip() == old[0]:
                    line = number
                    break
    return line, f"{' '.join(old)}  ->  {' '.join(new)}" if old or new else "(no diff)"


STRING = re.compile(r"""[rbuf]*("[^"\\]*(?:\\.[^"\\]*)*"|'[^'\\]*(?:\\.[^'\\]*)*')""", re.IGNORECASE)


def is_text_change(change: str) -> bool:
    """True when a mutation changed only what is inside string literals (a message's words or case).

    The toolkit's messages are one line naming the cause and the fix; their tests check the words
    that matter, not every letter, so an "XX" added or a changed case is no rule changed.
    A literal without a space ("max", "ok", "started", a key or a status compared somewhere) is a name,
    not a message: changing it can change a rule, so it stays a survivor.
    """
    old, _, new = change.partition("  ->  ")
    if old == new or STRING.sub('""', old) != STRING.sub('""', new):
        return False
    changed = set(STRING.findall(old)) - set(STRING.findall(new))
    return bool(changed) and all(re.search(r"\s", literal[1:-1]) for literal in changed)


def mutmut_command() -> Path:
    found = shutil.which("mutmut", path=str(Path(sys.executable).parent)) or shutil.which("mutmut")
    if not found:
        raise MutantsError("mutmut is not installed in this Python: run make setup (the test extra brings it on "
                           "Python 3.10 or later)")
    return Path(found)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", default=[], metavar="MODULE",
                        help="mutate only these modules (paths as in [tool.hri-teleop.mutants])")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="mutants tested at once")
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "mutants")
    args = parser.parse_args(argv)
    try:
        mutmut, table = load_config()
        problems = scope_problems(mutmut, table)
        if problems:
            raise MutantsError(f"{problems[0]}; fix pyproject.toml (docs/testing.md)")
        unknown = [m for m in args.only if m not in table]
        if unknown:
            raise MutantsError(f"--only {unknown[0]}: not a module of the scope; use one of "
                               f"{', '.join(sorted(table))}")
        command = mutmut_command()
    except MutantsError as exc:
        print(f"mutants: {exc}", file=sys.stderr)
        return 2
    pytest_ini = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["pytest"]["ini_options"]
    work = args.out.resolve() / "work"
    scope = args.only or sorted(table)
    print(f"mutants: copying the checkout to {work}; mutmut over {len(scope)} module(s), {args.jobs} at once")
    prepare(work, work_pyproject(mutmut, table, pytest_ini, args.only))
    run = subprocess.run([str(command), "run", "--max-children", str(args.jobs)], cwd=work)
    if run.returncode != 0:
        print(f"mutants: mutmut stopped with exit code {run.returncode} (its output above says why)", file=sys.stderr)
        return run.returncode
    return report(work, args.out.resolve(), scope)


def report(work: Path, out: Path, scope: Sequence[str]) -> int:
    counts: Dict[str, Counter] = {m: Counter() for m in scope}
    survivors: List[str] = []
    texts: List[str] = []
    no_tests: List[str] = []
    for module, name, status in results(work):
        if status not in ("survived", "no tests"):
            counts.setdefault(module, Counter())[status] += 1
            continue
        source = (work / module).read_text(encoding="utf-8")
        line, change = describe(mutant_diff(work, name, module), source, name)
        entry = f"{module}:{line}: {change}    [{name}]"
        if status == "no tests":
            no_tests.append(entry)
        elif is_text_change(change):
            texts.append(entry)
            status = "survived (text)"
        else:
            survivors.append(entry)
        counts.setdefault(module, Counter())[status] += 1
    columns = ("killed", "survived", "survived (text)", "no tests")
    print()
    print(f"{'module':<40} {'mutants':>7} {'killed':>6} {'survived':>8} {'text':>5} {'no tests':>8} {'other':>5}")
    total: Counter = Counter()
    for module in sorted(counts) + ["all"]:
        c = total if module == "all" else counts[module]
        if module != "all":
            total.update(c)
        made = sum(c.values())
        other = made - sum(c[k] for k in columns)
        print(f"{module:<40} {made:>7} {c['killed']:>6} {c['survived']:>8} {c['survived (text)']:>5} "
              f"{c['no tests']:>8} {other:>5}")
    print()
    print(f"survivors ({len(survivors)}): file:line: the mutation    [mutmut's name; `mutmut show NAME` in {work}]")
    for line in survivors:
        print(f"  {line}")
    out.mkdir(parents=True, exist_ok=True)
    for name, lines in (("survivors.txt", survivors), ("survivors-text.txt", texts), ("no-tests.txt", no_tests)):
        (out / name).write_text("".join(s + "\n" for s in lines), encoding="utf-8")
    (out / "summary.json").write_text(json.dumps({m: dict(c) for m, c in sorted(counts.items())}, indent=1) + "\n",
                                      encoding="utf-8")
    print(f"mutants: {len(texts)} survivor(s) changed only a message's text ({out / 'survivors-text.txt'}); "
          f"{len(no_tests)} mutant(s) no test of their module reaches ({out / 'no-tests.txt'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
