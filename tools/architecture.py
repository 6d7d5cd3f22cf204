"""Draw docs/architecture.md's layer plan from the code: which layer imports which, in what order.

The block between the two ``architecture.py`` markers of docs/architecture.md is this script's
output, so the page cannot drift from the imports: ``python tools/architecture.py`` rewrites it,
``--check`` exits 1 when it is stale (tests/unit/test_architecture_doc.py runs that check).
"""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path
from typing import Dict, List, Sequence, Set, Tuple

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "hri_teleop"
DOC = REPO / "docs" / "architecture.md"
BEGIN = "<!-- begin: drawn by tools/architecture.py from the imports; do not edit by hand -->"
END = "<!-- end: drawn by tools/architecture.py -->"

#: What each layer holds, in a few words (the order and the arrows come from the imports).
HOLDS: Dict[str, str] = {
    "core": "the lab's rules, plain Python: fsr, mapping, limits, teleop, gripper, gamepad/, experiment/, modes",
    "plots": "the figures (matplotlib, Agg) demos, the study and the grader's feedback share",
    "sim": "the lock-step simulation, pure: Panda arm and joints, hand, object, board, world, scripted pad, operators, study",
    "hardware": "the boundary, real | simulated: real/ (pygame pad, serial board), sim/ (the board's serial protocols)",
    "ros": "what the ROS shells share: parameters, clocks, private masters, bags, the kernel, the demos', the doctor's "
           "and the trials' work, the lab twin's nodes",
    "student": "what students' files import, versioned (student-api.md)",
    "grading": "the autograder, one subpackage per step (below)",
    "course": "what notebooks import (a facade), the kernel's ROS node, widgets/, release tools",
    "apps": "every command a person types (make targets, hri-grade, python -m): argument parsing and printing",
}


def modules(package: Path = PACKAGE) -> Dict[str, Path]:
    """Dotted module name -> file, for every module of the package."""
    found = {}
    for path in sorted(package.rglob("*.py")):
        parts = path.relative_to(package.parent).with_suffix("").parts
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def import_graph(package: Path = PACKAGE) -> Dict[str, Set[str]]:
    """Module -> the package's modules it imports anywhere in its text (in functions and under
    TYPE_CHECKING too); ``from package import module`` counts as importing that module."""
    known = modules(package)
    graph: Dict[str, Set[str]] = {name: set() for name in known}
    for name, path in known.items():
        package_parts = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets: List[str] = []
            if isinstance(node, ast.ImportFrom):
                base = ".".join(package_parts[:len(package_parts) - node.level + 1] + [node.module or ""]).strip(".") \
                    if node.level else node.module or ""
                targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base for alias in node.names]
            elif isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            for target in targets:
                while target and target not in known and "." in target:
                    target = target.rsplit(".", 1)[0]
                if target in known and target != name:
                    graph[name].add(target)
    return graph


def group_of(module: str, depth: int) -> str:
    """The module's group ``depth`` levels below the package (``hri_teleop.grading.run.x`` at 2: ``run``)."""
    parts = module.split(".")
    return parts[depth] if len(parts) > depth + 1 or (len(parts) == depth + 1 and depth > 0) else ""


def group_graph(graph: Dict[str, Set[str]], prefix: str) -> Dict[str, Set[str]]:
    """The import graph between the groups one level below ``prefix`` (a package's subpackages and modules)."""
    depth = prefix.count(".") + 1
    groups: Dict[str, Set[str]] = {}
    for module, targets in graph.items():
        if not module.startswith(prefix + ".") or module.count(".") < depth:
            continue
        here = module.split(".")[depth]
        groups.setdefault(here, set())
        for target in targets:
            if target.startswith(prefix + ".") and target.count(".") >= depth:
                there = target.split(".")[depth]
                if there != here:
                    groups[here].add(there)
                    groups.setdefault(there, set())
    return groups


def components(groups: Dict[str, Set[str]]) -> Dict[str, str]:
    """Group -> its strongly connected component's name ("a ~ b" for groups that import each other)."""
    reach = {g: set(deps) for g, deps in groups.items()}
    changed = True
    while changed:  # transitive closure: a few dozen groups at most
        changed = False
        for g in reach:
            more = set().union(*(reach.get(d, set()) for d in reach[g])) - reach[g]
            if more:
                reach[g] |= more
                changed = True
    return {g: " ~ ".join(sorted(h for h in groups if h == g or (h in reach[g] and g in reach[h])))
            for g in groups}


def levels(groups: Dict[str, Set[str]]) -> List[List[str]]:
    """The groups bottom up: each level imports only the levels below it; groups that import each
    other (a circle between folders, not between modules) stand together as "a ~ b"."""
    name = components(groups)
    condensed: Dict[str, Set[str]] = {}
    for g, deps in groups.items():
        condensed.setdefault(name[g], set()).update(name[d] for d in deps if d in name and name[d] != name[g])
    placed: Set[str] = set()
    order: List[List[str]] = []
    while len(placed) < len(condensed):
        level = sorted(c for c, deps in condensed.items() if c not in placed and deps <= placed)
        order.append(level)
        placed |= set(level)
    return order


def order_text(order: List[List[str]]) -> str:
    return " < ".join("{" + ", ".join(level) + "}" if len(level) > 1 else level[0] for level in order)


def lines_of(paths: Sequence[Path]) -> int:
    return sum(len(p.read_text(encoding="utf-8").splitlines()) for p in paths)


def about(lines: int) -> str:
    """A size rounded to hundreds of lines, so the page changes with the plan, not with every edit."""
    return f"~{max(100, round(lines, -2))}"


def render(graph: Dict[str, Set[str]]) -> str:
    """The generated block: layers bottom up with what each imports, grading's steps, sizes."""
    known = modules()
    layers = group_graph(graph, "hri_teleop")
    for shim in [g for g in layers if (PACKAGE / f"{g}.py").is_file() or g == "gamepad"]:
        del layers[shim]  # last term's import paths, outside the layers (student-api.md)
    for deps in layers.values():
        deps &= set(layers)
    width = max(len(", ".join(deps)) for deps in layers.values()) + 1
    out = ["```", f"{'layer':<11} {'imports':<{width}} {'modules':>7} {'lines':>6}  holds"]
    for level in reversed(levels(layers)):
        for layer in level:
            files = [p for m, p in known.items() if m.startswith(f"hri_teleop.{layer}.") or m == f"hri_teleop.{layer}"]
            uses = ", ".join(sorted(layers[layer])) or "-"
            out.append(f"{layer + '/':<11} {uses:<{width}} {len(files):>7} {about(lines_of(files)):>6}  "
                       f"{HOLDS.get(layer, '')}")
    out.append("```")
    out.append("")
    out.append(f"Import order, bottom up (each imports only what stands left of it; siblings in braces): "
               f"{order_text(levels(layers))}.")
    grading = group_graph(graph, "hri_teleop.grading")
    def named(group: str) -> str:
        return " ~ ".join(g + ("/" if (PACKAGE / "grading" / g).is_dir() else ".py") for g in group.split(" ~ "))

    steps = [[named(g) for g in level] for level in levels(grading)]
    out.append(f"Inside `grading/`, in import order (a ~ b: they import each other): {order_text(steps)}.")
    scripts = sorted((REPO / "hri_lab" / "scripts").glob("*.py"))
    sizes = ", ".join(f"`{p.name}` {about(lines_of([p]))}" for p in sorted(scripts, key=lambda p: -lines_of([p]))[:4])
    out.append(f"The lab's node scripts (`hri_lab/scripts/`, lines): {sizes}; "
               f"{len(scripts)} scripts, {about(lines_of(scripts))} lines in all.")
    return "\n".join(out)


def split_doc(text: str) -> Tuple[str, str, str]:
    """(before, the generated block, after) of the page; ValueError without both markers."""
    if BEGIN not in text or END not in text:
        raise ValueError(f"{DOC}: the markers of the generated block are missing; put {BEGIN!r} and {END!r} back")
    head, rest = text.split(BEGIN, 1)
    block, tail = rest.split(END, 1)
    return head, block.strip("\n"), tail


def main(argv: Sequence[str] = ()) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if docs/architecture.md's block is stale")
    args = parser.parse_args(list(argv))
    head, block, tail = split_doc(DOC.read_text(encoding="utf-8"))
    drawn = render(import_graph())
    if args.check:
        if block != drawn:
            print("docs/architecture.md: the layer plan is stale; run: python tools/architecture.py", file=sys.stderr)
            return 1
        return 0
    DOC.write_text(f"{head}{BEGIN}\n{drawn}\n{END}{tail}", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
