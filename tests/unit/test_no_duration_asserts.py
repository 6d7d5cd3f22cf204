"""No test passes or fails on how long something took: a busy machine must not fail `make test`.

Every test file under tests/ is read with ``ast``. A value read from a clock (``time.perf_counter()``,
``time.monotonic()``, ``time.process_time()``, ``time.time()``, their ``_ns`` forms, ``timeit``) is an
*instant*; anything minus an instant is a *duration* (a bag's stamp too), and so is anything computed from a duration
(a ratio, ``min`` of several, a list they were appended to, what a helper function returns). An
``assert`` whose expression compares a duration fails the suite. Comparing instants with each other
(``assert started <= clock.now() <= time.monotonic()``: an order, not a speed) and deadline loops
(``while time.monotonic() < deadline``: a hang guard that ends a wait) are not flagged. Speed figures
live in ``make bench`` (benchmarks/, docs/benchmarks.md), each beside a reference from the same run.
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Dict, FrozenSet, Iterable, Iterator, List, NamedTuple, Optional, Set, Tuple

import pytest

TESTS = Path(__file__).resolve().parents[1]
ROOT = TESTS.parent

#: Clock functions whose call reads an instant (module ``time``, or imported from it by name).
CLOCKS = {"perf_counter", "perf_counter_ns", "monotonic", "monotonic_ns", "process_time", "process_time_ns",
          "time", "time_ns", "thread_time", "thread_time_ns", "default_timer"}
#: Calls that return a duration outright (``timeit.timeit(stmt, number=n)``).
DURATION_CALLS = {"timeit", "repeat"}

#: How a clock taints a value: not at all, an instant, a duration.
NONE, INSTANT, DURATION = 0, 1, 2
Location = Tuple[str, int, str]


class Kind(NamedTuple):
    """What an expression holds: ``level`` (NONE, INSTANT, DURATION) and, for a record (a dict, an object,
    a tuple), the fields that hold a duration (keys, attributes, ``#i`` for a tuple's i-th item)."""

    level: int = NONE
    fields: FrozenSet[str] = frozenset()  # paths: "seconds", "#1", "#1/seconds" (a tuple's dict)

    def __or__(self, other: "Kind") -> "Kind":  # type: ignore[override]
        return Kind(max(self.level, other.level), self.fields | other.fields)


PLAIN, STAMP, SPAN = Kind(NONE), Kind(INSTANT), Kind(DURATION)


def _nest(key: str, kind: Kind) -> Kind:
    """A record whose field ``key`` holds ``kind``."""
    nested = [f"{key}/{f}" for f in kind.fields if f.count("/") < 3]  # deep enough; a loop x = (x, d) ends
    return Kind(NONE, frozenset(([key] if kind.level == DURATION else []) + nested))


def _field(kind: Kind, key: Optional[str]) -> Kind:
    """What field ``key`` of ``kind`` holds (a field of a duration is one too: ``times[-1]``)."""
    if kind.level:
        return Kind(kind.level)
    inner = frozenset(f[len(key) + 1:] for f in kind.fields if key is not None and f.startswith(key + "/"))
    return Kind(DURATION if key in kind.fields else NONE, inner)


def _record(fields: Iterable[Tuple[str, Kind]]) -> Kind:
    result = PLAIN
    for key, kind in fields:
        result = result | _nest(key, kind)
    return result


def _key(node: ast.AST) -> Optional[str]:
    """The field a subscript or attribute reads: ``x["k"]``, ``x.k``, ``x[2]`` (as ``#2``)."""
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Subscript):
        index = node.slice
        if type(index).__name__ == "Index":  # Python 3.8 wraps a subscript's value
            index = index.value  # type: ignore[attr-defined]
        if isinstance(index, ast.Constant) and isinstance(index.value, str):
            return index.value
        if isinstance(index, ast.Constant) and isinstance(index.value, int):
            return f"#{index.value}"
    return None


class _Module:
    """The clock taint of one module, to a fixed point: which names hold instants, durations or records
    with durations in them (per top-level function; flow-insensitive), and what each function returns."""

    def __init__(self, tree: ast.Module) -> None:
        self.tree = tree
        self.time_modules, self.timeit_modules = {"time"}, {"timeit"}  # names these modules are bound to
        self.clock_names: Set[str] = set()  # ``from time import perf_counter [as pc]``
        self.classes: Dict[str, List[str]] = {}  # a dataclass or NamedTuple here: its fields in order
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name == "time":
                        self.time_modules.add(alias.asname or "time")
                    elif alias.name == "timeit":
                        self.timeit_modules.add(alias.asname or "timeit")
            elif isinstance(node, ast.ImportFrom) and node.module == "time":
                self.clock_names |= {a.asname or a.name for a in node.names if a.name in CLOCKS}
            elif isinstance(node, ast.ClassDef):
                self.classes[node.name] = [s.target.id for s in node.body
                                           if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)]
        self.scopes: Dict[int, Dict[str, Kind]] = {}  # per top-level statement (a test, a helper); -1: the module
        self.scope = -1
        self.returns: Dict[str, Kind] = {}  # function (or fixture) name -> what it returns or yields
        while self._step():
            pass

    # -- what an expression is -----------------------------------------------------------------

    def _clock_call(self, node: ast.Call) -> Kind:
        func = node.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            if func.value.id in self.time_modules and func.attr in CLOCKS:
                return STAMP
            if func.value.id in self.timeit_modules:
                return SPAN if func.attr in DURATION_CALLS else STAMP if func.attr == "default_timer" else PLAIN
        if isinstance(func, ast.Name) and func.id in self.clock_names:
            return STAMP
        return PLAIN

    def _call(self, node: ast.Call) -> Kind:
        clock = self._clock_call(node)
        if clock.level:
            return clock
        func = node.func
        name = func.id if isinstance(func, ast.Name) else None
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id in ("self", "cls"):
            name = func.attr
        if name in self.returns:
            return self.returns[name]
        if name in self.classes or name == "dict":  # a record: which of its fields got a duration
            order = self.classes.get(name, [])
            return _record([(k.arg, self.kind(k.value)) for k in node.keywords if k.arg] +
                           [(order[i], self.kind(a)) for i, a in enumerate(node.args[:len(order)])])
        parts = [*node.args, *(k.value for k in node.keywords)]
        return SPAN if any(self.kind(p).level == DURATION for p in parts) else PLAIN  # min(), round(), float() ...

    def kind(self, node: ast.AST) -> Kind:
        if isinstance(node, ast.Name):
            return self.scopes.get(self.scope, {}).get(node.id, PLAIN) | self.scopes.get(-1, {}).get(node.id, PLAIN)
        if isinstance(node, ast.Call):
            return self._call(node)
        if isinstance(node, ast.BinOp):
            left, right = self.kind(node.left).level, self.kind(node.right).level
            if DURATION in (left, right) or (isinstance(node.op, ast.Sub) and right == INSTANT):
                return SPAN  # an instant minus an instant, or a time from elsewhere (a bag's stamp) minus one
            if isinstance(node.op, (ast.Add, ast.Sub)) and INSTANT in (left, right):
                return STAMP  # a deadline, a stamp in the past
            return PLAIN
        if isinstance(node, ast.UnaryOp):
            return self.kind(node.operand)
        if isinstance(node, (ast.Attribute, ast.Subscript)):
            return _field(self.kind(node.value), _key(node))
        if isinstance(node, ast.Starred):
            return self.kind(node.value)
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            kinds = [self.kind(e) for e in node.elts]
            if isinstance(node, ast.Tuple):
                return _record((f"#{i}", k) for i, k in enumerate(kinds))
            return Kind(max((k.level for k in kinds), default=NONE))
        if isinstance(node, ast.Dict):
            return _record((k.value, self.kind(v)) for k, v in zip(node.keys, node.values)
                           if isinstance(k, ast.Constant) and isinstance(k.value, str))
        if isinstance(node, (ast.ListComp, ast.SetComp, ast.GeneratorExp)):
            return Kind(self.kind(node.elt).level)
        if isinstance(node, ast.DictComp):
            return Kind(self.kind(node.value).level)
        if isinstance(node, ast.IfExp):
            return self.kind(node.body) | self.kind(node.orelse)
        if isinstance(node, ast.NamedExpr):
            return self.kind(node.value)
        return PLAIN

    # -- the names, to a fixed point -----------------------------------------------------------

    def _bind(self, target: ast.AST, kind: Kind, value: Optional[ast.AST] = None) -> bool:
        if isinstance(target, (ast.Tuple, ast.List)):
            if isinstance(value, (ast.Tuple, ast.List)) and len(value.elts) == len(target.elts):
                return any([self._bind(t, self.kind(v), v) for t, v in zip(target.elts, value.elts)])
            return any([self._bind(t, _field(kind, f"#{i}")) for i, t in enumerate(target.elts)])
        if isinstance(target, ast.Starred):
            return self._bind(target.value, kind)
        if isinstance(target, (ast.Attribute, ast.Subscript)):  # results["x"] = d: results has a field x
            field = _key(target)
            return self._bind(target.value, _nest(field, kind) if field is not None else Kind(kind.level))
        if isinstance(target, ast.Name):
            names = self.scopes.setdefault(self.scope, {})
            merged = names.get(target.id, PLAIN) | kind
            if merged != names.get(target.id, PLAIN):
                names[target.id] = merged
                return True
        return False

    def _function(self, function: ast.AST) -> bool:
        """Bind its parameters named after a fixture here; note what it returns or yields."""
        changed = False
        if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for arg in function.args.args:
                if arg.arg in self.returns:
                    changed |= self._bind(ast.Name(id=arg.arg, ctx=ast.Store()), self.returns[arg.arg])
            kind = PLAIN
            for node in ast.walk(function):
                if isinstance(node, (ast.Return, ast.Yield, ast.YieldFrom)) and node.value is not None:
                    kind = kind | self.kind(node.value)
            if kind != self.returns.get(function.name, PLAIN):
                self.returns[function.name] = kind | self.returns.get(function.name, PLAIN)
                changed = True
        return changed

    def _step(self) -> bool:
        changed = False
        for index, statement in enumerate(self.tree.body):
            self.scope = index if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) else -1
            for node in ast.walk(statement):
                changed |= self._node(node)
        return changed

    def _node(self, node: ast.AST) -> bool:
        if isinstance(node, ast.Assign):
            if isinstance(node.value, ast.Lambda) and self.kind(node.value.body).level == DURATION:
                names = [t.id for t in node.targets if isinstance(t, ast.Name) and t.id not in self.returns]
                self.returns.update({n: SPAN for n in names})
                return bool(names)
            return any([self._bind(t, self.kind(node.value), node.value) for t in node.targets])
        if isinstance(node, (ast.AnnAssign, ast.AugAssign, ast.NamedExpr)) and node.value is not None:
            return self._bind(node.target, self.kind(node.value), node.value)
        if isinstance(node, (ast.For, ast.comprehension)):
            return self._bind(node.target, Kind(self.kind(node.iter).level))
        if isinstance(node, ast.withitem) and node.optional_vars is not None:
            return self._bind(node.optional_vars, self.kind(node.context_expr))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr in ("append", "extend", "add", "insert"):  # draws.append(d): a list of durations
            return self._bind(node.func.value, Kind(max((self.kind(a).level for a in node.args), default=NONE)))
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return self._function(node)
        return False

    def duration_asserts(self) -> Iterator[ast.Assert]:
        for index, statement in enumerate(self.tree.body):
            self.scope = index if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) else -1
            for node in ast.walk(statement):
                if isinstance(node, ast.Assert) and any(self._compares_a_duration(c) for c in ast.walk(node.test)
                                                        if isinstance(c, ast.Compare)):
                    yield node

    def _compares_a_duration(self, compare: ast.Compare) -> bool:
        if all(isinstance(op, (ast.In, ast.NotIn, ast.Is, ast.IsNot)) for op in compare.ops):
            return False
        return any(self.kind(operand).level == DURATION for operand in [compare.left, *compare.comparators])


def duration_asserts(source: str, filename: str = "<test>") -> List[Location]:
    """(file, line, source text) of every assert in ``source`` that compares a duration read from a clock."""
    module = _Module(ast.parse(source, filename))
    lines = source.splitlines()
    return [(filename, node.lineno, lines[node.lineno - 1].strip()) for node in module.duration_asserts()]


def _test_files() -> Iterable[Path]:
    return sorted(p for p in TESTS.rglob("*.py") if "corpus" not in p.relative_to(TESTS).parts)


def test_no_test_asserts_a_duration():
    found = [hit for path in _test_files()
             for hit in duration_asserts(path.read_text(encoding="utf-8"), str(path.relative_to(ROOT)))]
    assert not found, ("tests must not pass or fail on a duration (a busy machine fails them); assert the work done "
                       "and move the speed figure to `make bench` (benchmarks/):\n"
                       + "\n".join(f"  {f}:{line}: {text}" for f, line, text in found))


# -- the checker catches what it should, and only that ----------------------------------------------

CAUGHT = {
    "elapsed": """
import time
def test():
    started = time.perf_counter()
    work()
    elapsed = time.perf_counter() - started
    assert elapsed < 0.05
""",
    "inline": """
import time
def test():
    started = time.monotonic()
    work()
    assert time.monotonic() - started < 1.5
""",
    "from-import alias": """
from time import process_time as cpu
def test():
    t0 = cpu()
    work()
    cpu_s = cpu() - t0
    assert simulated_s / cpu_s >= 20.0, "only so many times real time"
""",
    "best of a helper": """
import time
def test():
    def one_run():
        begin = time.perf_counter()
        work()
        return time.perf_counter() - begin
    best = min(one_run() for _ in range(5))
    assert best < 0.020
""",
    "list of draws": """
import time
def test():
    draws = []
    for _ in range(10):
        started = time.monotonic()
        draw()
        draws.append(time.monotonic() - started)
    assert max(draws) < 0.1
""",
    "tuple unpacking": """
import time
def timed():
    started = time.time()
    result = work()
    return result, time.time() - started
def test():
    result, took = timed()
    assert result and took <= 2.0
""",
    "approx": """
import time, pytest
def test():
    a = time.monotonic()
    wait()
    assert time.monotonic() - a == pytest.approx(0.5, abs=0.1)
""",
    "a fixture's record": """
import time, pytest
from dataclasses import dataclass
@dataclass
class Study:
    trials: int
    record_s: float
@pytest.fixture
def study():
    started = time.monotonic()
    trials = record()
    yield Study(trials, time.monotonic() - started)
def test(study):
    assert study.trials == 4
    assert study.record_s < 120
""",
    "a fixture's tuple": """
import time, pytest
@pytest.fixture
def built(tmp_path):
    started = time.monotonic()
    setup = run_setup(tmp_path)
    assert setup.returncode == 0
    return tmp_path, {"seconds": time.monotonic() - started}
def test(built):
    folder, timing = built
    assert folder.is_dir()
    assert timing["seconds"] < 60
""",
    "a recorded stamp minus a wall-clock instant": """
import time
def test(ros_master):
    pub.stop()
    silent_at = time.time()
    msgs = read_topics(bag)
    back_to_zero = next(t for t, m in msgs if t > silent_at and m.linear.x == 0.0)
    assert back_to_zero - silent_at < 2.0
""",
    "timeit": """
import timeit
def test():
    assert timeit.timeit("work()", number=10) < 1.0
""",
}

LEFT_ALONE = {
    "deadline loop": """
import time
def test():
    deadline = time.monotonic() + 20
    while not ready() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert ready(), "not ready within 20 s"
""",
    "ordered instants": """
import time
def test():
    before = time.monotonic()
    assert before <= clock.wait_started() <= clock.now() <= time.monotonic()
""",
    "printed duration": """
import time
def test():
    started = time.monotonic()
    result = work()
    print(f"took {time.monotonic() - started:.1f} s")
    assert result == 42
""",
    "simulated time": """
def test():
    record = run_lab(script)
    assert record.duration_s() > 10.0 and record.ticks == 1000
""",
    "a stamp in the past": """
import time
def test():
    stamp = time.time() - 3.0
    assert widget.age_text(stamp) in ("3 s ago", "4 s ago")
""",
}


@pytest.mark.parametrize("name", sorted(CAUGHT))
def test_the_check_catches_an_assert_on_a_measured_duration(name):
    found = duration_asserts(CAUGHT[name])
    assert len(found) == 1, (name, found)
    assert found[0][2].startswith("assert ")


@pytest.mark.parametrize("name", sorted(LEFT_ALONE))
def test_the_check_leaves_hang_guards_and_orderings_alone(name):
    assert duration_asserts(LEFT_ALONE[name]) == []


def test_the_check_reads_every_test_file():
    files = [p.relative_to(TESTS).as_posix() for p in _test_files()]
    assert "unit/test_no_duration_asserts.py" in files and "integration/test_doctor.py" in files
    assert not any(f.startswith("grading/corpus/") for f in files)  # student packages, not tests
