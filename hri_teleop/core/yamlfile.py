"""Read a YAML file that a person wrote: every problem becomes one line naming the file and the fix.

Why one function: the teleop config, the gamepad layouts and the pad scripts are all
edited by students, and the lab's rule for bad input is one line with the cause and the
fix, never a traceback.  Each module passes its own error class, so callers keep
catching ``ConfigError`` / ``GamepadError`` as before.
"""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path
from typing import Any, Callable, Dict, List, Set, Type, Union

import yaml

from hri_teleop.core.errors import HriTeleopError

__all__ = ["read_yaml", "BoundedYamlError", "YAML_CAP_CHARS", "YAML_CAP_WEIGHT", "load_bounded_all",
           "load_bounded", "arithmetic", "disarm_rosparam_tags"]


def read_yaml(
    path: Union[str, Path],
    error: Type[Exception],
    *,
    what: str = "file",
    missing_fix: str = "check the path",
) -> object:
    """The parsed content of the YAML file ``path`` (None for an empty file).

    Raises ``error`` with a one-line message that names the file as ``str(path)`` spells it:

    * missing: ``<what> not found: <path>; <missing_fix>``
    * a directory: ``<path> is a directory, not a YAML file; pass the file's path``
    * unreadable (permissions, not UTF-8): ``<path>: cannot read (<Error>: <detail>); check
      the file's permissions and encoding``
    * a syntax error: ``<path>:<line>: <problem>; fix the YAML syntax (...)``

    The shape of the content is not checked: each caller expects its own (a mapping, a
    list of steps) and says so in its own words.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{what} not found: {source}; {missing_fix}") from None
    except IsADirectoryError:
        raise error(f"{source} is a directory, not a YAML file; pass the file's path") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{source}: cannot read ({exc.__class__.__name__}: {exc}); "
                    "check the file's permissions and encoding") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark is not None else source
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise error(f"{where}: {problem}; fix the YAML syntax (indent with spaces, `key: value`)") from None


# -- YAML a stranger wrote: bounded, safe, no code -------------------------------------------------------

#: The most characters a stranger's YAML may hold (a robot_params.yaml or graph.yaml is about 1 kB).
YAML_CAP_CHARS = 256 * 1024
#: The most a document may expand to: one per node and per character of a scalar, an alias counted each
#: time it is used. A 617-byte alias bomb expands to billions; honest files to a few thousand.
YAML_CAP_WEIGHT = 1_000_000
_EXPRESSION_CAP_CHARS = 1000


class BoundedYamlError(HriTeleopError, ValueError):
    """A stranger's YAML is too large, expands too far through aliases, or holds an expression that is not
    arithmetic (one line: what, and how to write it)."""


_OPERATORS: Dict[type, Callable[[float, float], float]] = {
    ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b}


def arithmetic(text: str) -> float:
    """The value of ``text``, arithmetic over numbers and ``pi`` (``+ - * /``, unary signs, parentheses)
    and nothing else: no names, calls, attributes or powers. What rosparam's ``!radians`` tag evaluates
    with ``eval``, without ``eval``. BoundedYamlError when ``text`` is anything more."""
    if len(text) > _EXPRESSION_CAP_CHARS:
        raise BoundedYamlError(f"the expression {text[:40]!r}... is longer than {_EXPRESSION_CAP_CHARS} characters; "
                               "write the angle as a number or a short expression such as pi/2")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError):
        raise BoundedYamlError(f"invalid radian expression: {text!r}; write e.g. pi/2 or 1.5708") from None

    def value(node: ast.AST) -> float:
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.Name) and node.id == "pi":
            return math.pi
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
            operand = value(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and type(node.op) in _OPERATORS:
            return _OPERATORS[type(node.op)](value(node.left), value(node.right))
        raise BoundedYamlError(f"invalid radian expression: {text!r} (only numbers, pi, + - * / and parentheses "
                               "are allowed); write e.g. pi/2 or 1.5708")

    try:
        return float(value(tree.body))
    except ZeroDivisionError:
        raise BoundedYamlError(f"invalid radian expression: {text!r} divides by zero; write the angle itself") from None


def _radians(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    """rosparam's ``!radians`` (and plain ``rad(...)``), as rosparam reads it, without eval."""
    value = str(loader.construct_scalar(node)).strip()  # type: ignore[arg-type]
    return arithmetic(value[4:-1] if value.startswith("rad(") else value)


def _degrees(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    """rosparam's ``!degrees`` (and plain ``deg(...)``): a number times pi/180."""
    value = str(loader.construct_scalar(node))  # type: ignore[arg-type]
    text = value.strip()[4:-1] if value.startswith("deg(") else value
    try:
        return float(text) * math.pi / 180.0
    except ValueError:
        raise BoundedYamlError(f"invalid degree value: {value}; write e.g. !degrees 90") from None


class _BoundedLoader(yaml.SafeLoader):
    """YAML's standard tags only (whatever another library added to SafeLoader), plus rosparam's angle tags."""


_BoundedLoader.yaml_constructors = {tag: build for tag, build in yaml.constructor.SafeConstructor.yaml_constructors.items()
                                    if tag is None or tag.startswith("tag:yaml.org,2002:")}
_BoundedLoader.yaml_implicit_resolvers = {first: list(pairs) for first, pairs in
                                          yaml.resolver.Resolver.yaml_implicit_resolvers.items()}
_BoundedLoader.add_constructor("!radians", _radians)
_BoundedLoader.add_constructor("!degrees", _degrees)
_BoundedLoader.add_implicit_resolver("!degrees", re.compile(r"^deg\([^\)]*\)$"), list("deg("))
_BoundedLoader.add_implicit_resolver("!radians", re.compile(r"^rad\([^\)]*\)$"), list("rad("))


def disarm_rosparam_tags() -> None:
    """Put :func:`arithmetic` in place of eval behind ``!radians`` on every PyYAML loader (rosparam puts its
    eval-based constructor there when it is imported, and roslaunch reads ``<rosparam>`` with them)."""
    for loader in (yaml.SafeLoader, yaml.Loader, yaml.FullLoader, yaml.UnsafeLoader):
        loader.add_constructor("!radians", _radians)
        loader.add_constructor("!degrees", _degrees)


def _weigh(node: yaml.Node, budget: int, memo: Dict[int, int], active: Set[int]) -> int:
    """How far ``node`` expands (nodes plus scalar characters, a shared node counted at each use)."""
    key = id(node)
    if key in memo:
        return memo[key]
    if key in active:
        raise BoundedYamlError("the YAML refers to itself through an alias (a recursive anchor); write the values "
                               "out instead")
    active.add(key)
    if isinstance(node, yaml.ScalarNode):
        weight = 1 + len(str(node.value))
    elif isinstance(node, yaml.SequenceNode):
        weight = 1 + sum(_weigh(child, budget, memo, active) for child in node.value)
    else:
        weight = 1 + sum(_weigh(k, budget, memo, active) + _weigh(v, budget, memo, active) for k, v in node.value)
    active.discard(key)
    memo[key] = weight
    if weight > budget:
        raise BoundedYamlError(f"the YAML expands to more than {budget} values through its aliases (*name); write "
                               "the values out instead of repeating anchors")
    return weight


def load_bounded_all(text: str, max_chars: int = YAML_CAP_CHARS, max_weight: int = YAML_CAP_WEIGHT) -> List[Any]:
    """Every document of ``text``, as ``yaml.safe_load_all`` reads it plus rosparam's ``!radians`` and
    ``!degrees`` (evaluated by :func:`arithmetic`, never by eval), bounded: at most ``max_chars``
    characters, each document expanding to at most ``max_weight`` (aliases counted at each use, a recursive
    anchor refused). yaml.YAMLError for a syntax error (the same as safe_load's), BoundedYamlError past a bound."""
    if len(text) > max_chars:
        raise BoundedYamlError(f"the YAML is larger than {max_chars // 1024} kB; write only the values asked for")
    loader = _BoundedLoader(text)
    documents: List[Any] = []
    try:
        while loader.check_node():
            node = loader.get_node()
            if node is not None:
                _weigh(node, max_weight, {}, set())
            documents.append(loader.construct_document(node) if node is not None else None)
    except RecursionError:
        raise BoundedYamlError("the YAML is nested too deep; write the values at a few levels at most") from None
    finally:
        loader.dispose()
    return documents


def load_bounded(text: str, max_chars: int = YAML_CAP_CHARS, max_weight: int = YAML_CAP_WEIGHT) -> Any:
    """The single document of ``text`` (None when empty), as :func:`load_bounded_all` reads it; more than one
    document is yaml's own ComposerError, as for ``yaml.safe_load``."""
    if len(text) > max_chars:
        raise BoundedYamlError(f"the YAML is larger than {max_chars // 1024} kB; write only the values asked for")
    loader = _BoundedLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _weigh(node, max_weight, {}, set())
        return loader.construct_document(node)
    except RecursionError:
        raise BoundedYamlError("the YAML is nested too deep; write the values at a few levels at most") from None
    finally:
        loader.dispose()
