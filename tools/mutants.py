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
import time
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


FUNCTIONS_TABLE = ("tool", "hri-teleop", "mutants-functions")
#: The checked-in list of mutants judged equivalent, each with its change and a one-line reason.
EQUIVALENTS = ROOT / "tools" / "mutants_equivalent.toml"
#: Files mutmut cannot mutate where they lie, moved in the copy: tests/leftovers.py is imported as
#: ``leftovers`` (from tests/ on sys.path), and mutmut names a mutant after the file's path.
RELOCATE = {"tests/leftovers.py": "leftovers.py"}


def load_functions(pyproject: Path = ROOT / "pyproject.toml") -> Dict[str, List[str]]:
    """[tool.hri-teleop.mutants-functions]: module -> the only functions mutated in it (``f`` or ``Class.method``),
    for a module whose rule is a few functions among process plumbing the unit tests do not run."""
    data: object = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    for key in FUNCTIONS_TABLE:
        data = data.get(key, {}) if isinstance(data, dict) else {}
    return {str(k): [str(f) for f in v] for k, v in dict(data).items()}  # type: ignore[call-overload]


def load_equivalents(path: Path = EQUIVALENTS) -> Dict[str, Tuple[str, str]]:
    """mutant name -> (its change as ``make mutants`` prints it, why it cannot change behaviour)."""
    if not path.is_file():
        return {}
    found: Dict[str, Tuple[str, str]] = {}
    for entry in tomllib.loads(path.read_text(encoding="utf-8")).get("equivalent", []):
        mutant, change, why = (str(entry.get(k, "")).strip() for k in ("mutant", "change", "why"))
        if not (mutant and change and why) or "__mutmut_" not in mutant:
            raise MutantsError(f"{path.name}: every [[equivalent]] needs mutant (mutmut's name), change and why; "
                               f"got {entry!r}")
        found[mutant] = (change, why)
    return found


def dotted(module: str) -> str:
    """mutmut's name of a module file: hri_teleop/core/__init__.py -> hri_teleop.core."""
    name = module[: -len(".py")].replace("/", ".")
    return name[: -len(".__init__")] if name.endswith(".__init__") else name


def mutant_patterns(modules: Sequence[str], functions: Dict[str, List[str]]) -> List[str]:
    """``mutmut run``'s name patterns for ``modules`` (their copy's paths): every mutant of a module, or only
    those of the functions [tool.hri-teleop.mutants-functions] names for it."""
    patterns = []
    for module in modules:
        original = next((old for old, new in RELOCATE.items() if new == module), module)
        names = functions.get(original)
        if not names:
            patterns.append(f"{dotted(module)}.*")
            continue
        for function in names:
            owner, _, method = function.rpartition(".")
            mangled = f"x\u01c1{owner}\u01c1{method}" if owner else f"x_{method}"
            patterns.append(f"{dotted(module)}.{mangled}__mutmut_*")
    return patterns


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
    for module in sorted(set(table) - set(only_mutate_modules(only, table))):
        problems.append(f"{module} is in [tool.hri-teleop.mutants] but not in [tool.mutmut] only_mutate")
    core = [f for f in tracked_files(root) if f.startswith("hri_teleop/core/") and f.endswith(".py")] or [
        str(p.relative_to(root)) for p in (root / "hri_teleop" / "core").rglob("*.py")]  # a new file counts once added
    for module in sorted(core):
        if module not in table:
            problems.append(f"{module} has no entry in [tool.hri-teleop.mutants] (list its unit tests, or [])")
        if not any(fnmatch.fnmatch(module, pattern) for pattern in only):
            problems.append(f"{module} is not in [tool.mutmut] only_mutate")
    return problems


def only_mutate_modules(only: Sequence[str], table: Dict[str, List[str]]) -> List[str]:
    """The modules of ``table`` that ``only_mutate``'s patterns take."""
    return [m for m in table if any(fnmatch.fnmatch(m, p) for p in only)]


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
                   only: Sequence[str], also_copy: Sequence[str] = (), relocate: Optional[Dict[str, str]] = None) -> str:
    """The copy's pyproject.toml: pytest's settings, [tool.mutmut] (narrowed to ``only``; ``also_copy`` the copy's
    other top-level entries, so that mutmut's folder holds all a test reads), the scope table; each path of
    ``relocate`` (default :data:`RELOCATE`) under its new name."""
    moved = RELOCATE if relocate is None else relocate

    def here(path: str) -> str:
        return moved.get(path, path)

    mutmut = dict(mutmut)
    if only:
        mutmut["only_mutate"] = list(only)
        mutmut["pytest_add_cli_args_test_selection"] = sorted({t for m in only for t in table[m]})
    for key in ("source_paths", "only_mutate"):
        mutmut[key] = [here(str(p)) for p in mutmut.get(key, [])]  # type: ignore[attr-defined]
    if also_copy:
        sources = {str(p).rstrip("/") for p in mutmut["source_paths"]}  # type: ignore[attr-defined]
        mutmut["also_copy"] = [e for e in also_copy if e not in sources and e != "pyproject.toml"]
    lines = ["[tool.pytest.ini_options]"] + [f"{k} = {toml_value(v)}" for k, v in pytest_ini.items()]
    lines += ["", "[tool.mutmut]"] + [f"{k} = {toml_value(v)}" for k, v in mutmut.items()]
    lines += ["", "[tool.hri-teleop.mutants]"] + [f"{json.dumps(here(k))} = {toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def tracked_files(root: Path = ROOT) -> List[str]:
    """The checkout's tracked files that exist (``git ls-files``), relative to ``root``; [] outside git.

    What a test may read is what a clone has: never what a run left in the tree (a catkin_ws/build, plots,
    dumps), and everything a test imports (solutions/, benchmarks/, notebooks/ ...)."""
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", "-z", "--cached"], capture_output=True,
                                check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return []
    names = [n for n in listed.decode("utf-8", "surrogateescape").split("\0") if n]
    return [n for n in names if os.path.lexists(root / n)]


#: Built, untracked files the package loads when they are there (the simulated arm's compiled cycle).
BUILT = ("hri_teleop/**/*.so",)


def prepare(work: Path, text: str, relocate: Optional[Dict[str, str]] = None, root: Path = ROOT) -> List[str]:
    """A fresh copy of the checkout's tracked files (and the package's built libraries) in ``work``, with
    ``text`` as its pyproject.toml and each file of ``relocate`` moved (old path -> new path). Returns the
    top-level entries copied (mutmut copies them again beside its mutants: ``also_copy``)."""
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    files = tracked_files(root)
    if not files:  # not a git checkout: the package, its lab config, the tests, the scope plugin
        files = [str(p.relative_to(root)) for top in ("hri_teleop", "hri_lab", "tests") for p in (root / top).rglob("*")
                 if p.is_file() and "__pycache__" not in p.parts] + ["tools/mutants_scope.py"]
    files += [str(p.relative_to(root)) for pattern in BUILT for p in root.glob(pattern)]
    for name in files:
        source, target = root / name, work / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.is_symlink():
            os.symlink(os.readlink(source), target)
        elif source.is_file():
            shutil.copy2(source, target)
    for old, new in (relocate or {}).items():
        if (work / old).is_file():
            (work / old).rename(work / new)
    (work / "pyproject.toml").write_text(text, encoding="utf-8")
    return sorted({Path(name).parts[0] for name in files} | set((relocate or {}).values()))


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
        same = [n for n in range(span[0], span[1] + 1) if old and lines[n - 1].strip() == old[0]]
        if same:  # the line as written, nearest to where the diff says it is (a line may occur twice)
            line = min(same, key=lambda n: abs(n - line))
    return line, f"{' '.join(old)}  ->  {' '.join(new)}" if old or new else "(no diff)"


STRING = re.compile(r"""[rbuf]*("[^"\\]*(?:\\.[^"\\]*)*"|'[^'\\]*(?:\\.[^'\\]*)*')""", re.IGNORECASE)


BRACES = re.compile(r"\{[^{}]*\}")


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
    pairs = zip(STRING.finditer(old), STRING.finditer(new))
    if any(a.group(0) != b.group(0) and "f" in a.group(0).split(a.group(1))[0].lower()
           and BRACES.sub("{}", a.group(1)) == BRACES.sub("{}", b.group(1)) for a, b in pairs):
        return False  # inside an f-string's braces: code, not words
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
    started = time.monotonic()
    try:
        mutmut, table = load_config()
        functions = load_functions()
        equivalents = load_equivalents()
        problems = scope_problems(mutmut, table)
        problems += [f"[tool.hri-teleop.mutants-functions] names {m}, which is not in [tool.hri-teleop.mutants]"
                     for m in functions if m not in table]
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
    scope = args.only or only_mutate_modules([str(p) for p in mutmut["only_mutate"]], table)  # type: ignore[attr-defined]
    print(f"mutants: copying the checkout's tracked files to {work}; mutmut over {len(scope)} module(s), "
          f"{args.jobs} at once")
    top = prepare(work, "", RELOCATE)
    (work / "pyproject.toml").write_text(work_pyproject(mutmut, table, pytest_ini, args.only, top), encoding="utf-8")
    patterns = mutant_patterns([RELOCATE.get(m, m) for m in scope], functions)
    # processes the tests start (a box's Python, a node) import the mutated package too, as the tests do; the
    # folder exists before mutmut starts, or its Python would cache the entry as missing
    (work / "mutants").mkdir(exist_ok=True)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (str(work / "mutants"), os.environ.get("PYTHONPATH", ""))
                                                      if p))
    run = subprocess.run([str(command), "run", "--max-children", str(args.jobs), *patterns], cwd=work, env=env)
    if run.returncode != 0:
        print(f"mutants: mutmut stopped with exit code {run.returncode} (its output above says why)", file=sys.stderr)
        return run.returncode
    return report(work, args.out.resolve(), scope, equivalents, (time.monotonic() - started) / 60.0, functions)


def in_functions(name: str, names: Sequence[str]) -> bool:
    """Whether mutant ``name`` changes one of the functions ``names`` (``f`` or ``Class.method``); all when empty."""
    if not names:
        return True
    tail = name.rsplit(".", 1)[-1].rsplit("__mutmut_", 1)[0]
    function = ".".join(tail.split("\u01c1")[1:]) if tail.startswith("x\u01c1") else tail[len("x_"):]
    return function in names


def report(work: Path, out: Path, scope: Sequence[str], equivalents: Optional[Dict[str, Tuple[str, str]]] = None,
           minutes: float = 0.0, functions: Optional[Dict[str, List[str]]] = None) -> int:
    """Print and write the figures of a run in ``work``; 1 while a real survivor remains (one that is not
    in ``equivalents`` with the same change, and changed more than a message's words), else 0."""
    equivalents = equivalents or {}
    back = {new: old for old, new in RELOCATE.items()}
    counts: Dict[str, Counter] = {m: Counter() for m in scope}
    survivors: List[str] = []
    texts: List[str] = []
    no_tests: List[str] = []
    equivalent: List[str] = []
    stale: List[str] = []
    for work_module, name, status in results(work):
        module = back.get(work_module, work_module)
        if module not in counts or not in_functions(name, (functions or {}).get(module, [])):
            continue  # not asked for in this run
        if status not in ("survived", "no tests"):
            counts[module][status] += 1
            continue
        source = (work / work_module).read_text(encoding="utf-8")
        line, change = describe(mutant_diff(work, name, work_module), source, name)
        entry = f"{module}:{line}: {change}    [{name}]"
        if status == "no tests":
            no_tests.append(entry)
        elif name in equivalents and equivalents[name][0] == change:
            equivalent.append(f"{entry}\n      equivalent: {equivalents[name][1]}")
            status = "equivalent"
        elif is_text_change(change):
            texts.append(entry)
            status = "survived (text)"
        else:
            if name in equivalents:
                stale.append(f"{name}: listed as equivalent for {equivalents[name][0]!r}, but the mutant is now {change!r}")
            survivors.append(entry)
        counts[module][status] += 1
    columns = ("killed", "survived", "equivalent", "survived (text)", "no tests")
    print()
    print(f"{'module':<40} {'mutants':>7} {'killed':>6} {'survived':>8} {'equiv':>5} {'text':>5} {'no tests':>8} "
          f"{'other':>5}")
    total: Counter = Counter()
    for module in sorted(counts) + ["all"]:
        c = total if module == "all" else counts[module]
        if module != "all":
            total.update(c)
        made = sum(c.values())
        other = made - sum(c[k] for k in columns)
        print(f"{module:<40} {made:>7} {c['killed']:>6} {c['survived']:>8} {c['equivalent']:>5} "
              f"{c['survived (text)']:>5} {c['no tests']:>8} {other:>5}")
    print()
    print(f"equivalent ({len(equivalent)}), from {EQUIVALENTS.relative_to(ROOT)}:")
    for line in equivalent:
        print(f"  {line}")
    for line in stale:
        print(f"  stale entry: {line}")
    print(f"survivors ({len(survivors)}): file:line: the mutation    [mutmut's name; `mutmut show NAME` in {work}]")
    for line in survivors:
        print(f"  {line}")
    out.mkdir(parents=True, exist_ok=True)
    for name, lines in (("survivors.txt", survivors), ("survivors-text.txt", texts), ("no-tests.txt", no_tests),
                        ("equivalent.txt", equivalent)):
        (out / name).write_text("".join(s + "\n" for s in lines), encoding="utf-8")
    summary = {m: dict(c) for m, c in sorted(counts.items())}
    (out / "summary.json").write_text(json.dumps({"modules": summary, "minutes": round(minutes, 1)}, indent=1) + "\n",
                                      encoding="utf-8")
    print(f"mutants: {len(texts)} survivor(s) changed only a message's text ({out / 'survivors-text.txt'}); "
          f"{len(no_tests)} mutant(s) no test of their module reaches ({out / 'no-tests.txt'})")
    print(f"mutants: {sum(total.values())} made, {total['killed']} killed, {len(survivors)} survived, "
          f"{len(equivalent)} equivalent, {len(texts)} text only, {len(no_tests)} no tests, in {minutes:.1f} min")
    if survivors:
        print(f"mutants: {len(survivors)} real survivor(s): kill each with a test that fails on it, or list it in "
              f"{EQUIVALENTS.relative_to(ROOT)} with the reason it cannot change behaviour", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
