"""The student API's checker: what a name of hri_teleop.student is, its committed list
(tests/unit/student_api.yaml) version by version, and where the module or the list break the rules
(tests/unit/test_student_api.py; docs/student-api.md)."""

from __future__ import annotations

import dataclasses
import hashlib
import inspect
import types
import typing
import warnings
from pathlib import Path
from typing import Any, Dict, List, Tuple

import yaml

LISTED = Path(__file__).with_name("student_api.yaml")

Version = Tuple[int, ...]


def version(text: str) -> Version:
    return tuple(int(part) for part in str(text).split("."))


# -- what a name is -------------------------------------------------------------------------------

def parameters(obj: Any) -> str:
    """A callable's parameters as callers see them: names, order, kinds, which have a default."""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return "(?)"
    parts: List[str] = []
    starred = False
    for p in signature.parameters.values():
        if p.kind is p.VAR_POSITIONAL:
            parts.append(f"*{p.name}")
            starred = True
        elif p.kind is p.VAR_KEYWORD:
            parts.append(f"**{p.name}")
        else:
            if p.kind is p.KEYWORD_ONLY and not starred:
                parts.append("*")
                starred = True
            parts.append(p.name + ("=..." if p.default is not p.empty else ""))
        if p.kind is p.POSITIONAL_ONLY:
            parts[-1] += "/"
    return "(" + ", ".join(parts) + ")"


def describe(obj: Any) -> Tuple[str, str]:
    """(kind, signature): a class or function with its parameters, an exception with the built-in ones it
    is caught as, a constant with its type."""
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        builtin = [c.__name__ for c in obj.__mro__ if c.__module__ == "builtins"]
        return "exception", ", ".join(n for n in builtin if n not in ("object", "BaseException", "Exception"))
    if inspect.isclass(obj):
        return "class", parameters(obj)
    if callable(obj):
        return "function", parameters(obj)
    return "constant", type(obj).__name__


def member(cls: Any, name: str) -> str:
    """How a class's method, property or dataclass field looks to a caller ("missing" when it is gone)."""
    if dataclasses.is_dataclass(cls) and name in {f.name for f in dataclasses.fields(cls)}:
        return "field"
    try:
        raw = inspect.getattr_static(cls, name)
    except AttributeError:
        return "missing"
    if isinstance(raw, property):
        return "property"
    if isinstance(raw, (classmethod, staticmethod)):
        return parameters(getattr(cls, name))
    if inspect.isfunction(raw):
        text = parameters(raw)
        return "(" + text[1:-1].split(", ", 1)[1] + ")" if ", " in text else "()"  # without self
    return "attribute"


def returned_class(func: Any) -> Any:
    """The class a function's return annotation names (the element class of a ``List[...]``)."""
    hint = typing.get_type_hints(func).get("return")
    args = typing.get_args(hint)
    return args[0] if typing.get_origin(hint) in (list, List) and args else hint


def _split(signature: str) -> Tuple[List[str], List[str], List[str]]:
    """(positional parameters, keyword-only parameters, ``*args``/``**kwargs``) of a :func:`parameters` text."""
    positional: List[str] = []
    keyword: List[str] = []
    stars: List[str] = []
    starred = False
    for part in [p for p in signature.strip()[1:-1].split(", ") if p]:
        if part.startswith("*"):
            starred = True
            stars += [part] if part != "*" else []
        else:
            (keyword if starred else positional).append(part.rstrip("/"))
    return positional, keyword, stars


def _star(part: str) -> str:
    return "**" if part.startswith("**") else "*"


def breaks(old: str, new: str) -> str:
    """Why a call written for signature ``old`` fails with ``new`` ("" when every such call still works)."""
    if old.startswith("(") is not new.startswith("("):
        return f"{old} became {new}"
    if not old.startswith("("):
        return "" if old == new else f"a {old} became a {new}"
    old_pos, old_kw, old_stars = _split(old)
    new_pos, new_kw, new_stars = _split(new)
    for index, name in enumerate(old_pos):
        if index >= len(new_pos) or new_pos[index].split("=")[0] != name.split("=")[0]:
            return f"parameter {name.split('=')[0]} is no longer the {index + 1}. positional one"
        if name.endswith("=...") and not new_pos[index].endswith("=..."):
            return f"parameter {name.split('=')[0]} lost its default"
    for name in new_pos[len(old_pos):] + [k for k in new_kw if k not in old_kw]:
        if not name.endswith("=...") and not any(name.split("=")[0] == o.split("=")[0] for o in old_kw):
            return f"new parameter {name} has no default"
    for name in old_kw:
        match = [n for n in new_pos + new_kw if n.split("=")[0] == name.split("=")[0]]
        if not match:
            return f"keyword parameter {name.split('=')[0]} is gone"
        if name.endswith("=...") and not match[0].endswith("=..."):
            return f"parameter {name.split('=')[0]} lost its default"
    missing = [s for s in old_stars if _star(s) not in {_star(n) for n in new_stars}]
    return f"{missing[0]} is gone" if missing else ""


# -- the committed list -----------------------------------------------------------------------------

def signature_at(entry: Dict[str, Any], at: Version) -> str:
    changes = sorted((version(v), s) for v, s in (entry.get("changed") or {}).items() if version(v) <= at)
    return changes[-1][1] if changes else str(entry["signature"])


def members_at(entry: Dict[str, Any], key: str, at: Version) -> Dict[str, str]:
    """The ``members`` (of a class) or ``returns`` (members of what a function returns) listed by version ``at``:
    a member is ``name: form``, or ``name: {form: ..., since: ...}`` when it came after its name."""
    found = {}
    for name, value in (entry.get(key) or {}).items():
        since = value.get("since", entry["since"]) if isinstance(value, dict) else entry["since"]
        if version(since) <= at:
            found[name] = str(value["form"]) if isinstance(value, dict) else str(value)
    return found


def surface_at(listed: Dict[str, Any], at: Version) -> Dict[str, Dict[str, Any]]:
    """name -> {kind, signature, members, returns, deprecated, use} of the names version ``at`` gives."""
    found = {}
    for name, entry in listed["names"].items():
        if version(entry["since"]) > at or ("removed" in entry and version(entry["removed"]) <= at):
            continue
        deprecated = "deprecated" in entry and version(entry["deprecated"]) <= at
        found[name] = {"kind": entry["kind"], "signature": signature_at(entry, at), "deprecated": deprecated,
                       "use": entry.get("use", "") if deprecated else "",
                       "members": members_at(entry, "members", at), "returns": members_at(entry, "returns", at)}
    return found


def digest(surface: Dict[str, Dict[str, Any]]) -> str:
    def extra(entry: Dict[str, Any]) -> str:
        return " ".join(f"{key}.{m}{form}" for key in ("members", "returns") for m, form in sorted(entry[key].items()))

    lines = sorted(f"{n} {e['kind']} {e['signature']} {'deprecated:' + e['use'] if e['deprecated'] else ''} {extra(e)}"
                   for n, e in surface.items())
    return hashlib.sha256("\n".join(lines).encode()).hexdigest()[:16]


def list_problems(listed: Dict[str, Any]) -> List[str]:
    """What is wrong with the list itself: edited released versions, versions out of order, bad entries."""
    problems: List[str] = []
    versions = list(listed["versions"])
    if [version(v) for v in versions] != sorted(version(v) for v in versions):
        problems.append(f"versions {versions} are not in ascending order")
    known = set(versions)
    for name, entry in listed["names"].items():
        used = [entry["since"], entry.get("deprecated"), entry.get("removed"), *(entry.get("changed") or {}),
                *_member_sinces(entry)]
        unknown = [str(v) for v in used if v is not None and str(v) not in known]
        if unknown:
            problems.append(f"{name}: version {unknown[0]} is not under versions: add it with the digest printed "
                            "below and raise hri_teleop.student.API_VERSION")
        if "deprecated" in entry and entry.get("use") not in listed["names"]:
            problems.append(f"{name}: deprecated without 'use: <the listed name to use instead>'")
        if "removed" in entry:
            gone, since = version(entry["removed"]), version(entry.get("deprecated", entry["removed"]))
            if gone[0] <= since[0] or gone[1:] != (0,) * len(gone[1:]):
                problems.append(f"{name}: removed in {entry['removed']}, but a name goes only in the major version "
                                "after the one that deprecated it (e.g. deprecated 1.2, removed 2.0)")
        changes = [str(entry["signature"])] + [s for _, s in sorted((version(v), s) for v, s in
                                                                  (entry.get("changed") or {}).items())]
        for old, new in zip(changes, changes[1:]):
            why = breaks(old, new)
            if why:
                problems.append(f"{name}: {why} ({old} -> {new}): keep old calls working or deprecate the name")
    for v, pinned in listed["versions"].items():
        found = digest(surface_at(listed, version(v)))
        if found != pinned:
            problems.append(f"the surface of released version {v} changed (digest {found}, pinned {pinned}): "
                            "never edit a released version; list the change under a new version "
                            "(see the head of tests/unit/student_api.yaml)")
    used = {str(v) for e in listed["names"].values()
            for v in [e["since"], e.get("deprecated"), e.get("removed"), *(e.get("changed") or {}), *_member_sinces(e)]
            if v is not None}
    for v in sorted(used - known, key=version):
        problems.append(f"version {v}'s digest would be {digest(surface_at(listed, version(v)))}")
    return problems


def _member_sinces(entry: Dict[str, Any]) -> List[str]:
    return [str(v["since"]) for key in ("members", "returns") for v in (entry.get(key) or {}).values()
            if isinstance(v, dict) and "since" in v]


def module_problems(listed: Dict[str, Any], module: types.ModuleType) -> List[str]:
    """Where ``module`` differs from the list's newest version: gone, changed, unlisted, not warning."""
    problems: List[str] = []
    newest = max(listed["versions"], key=version)
    if getattr(module, "API_VERSION", None) != newest:
        problems.append(f"{module.__name__}.API_VERSION is {getattr(module, 'API_VERSION', None)!r}, the list's "
                        f"newest version {newest!r}: raise one of them to the other")
    surface = surface_at(listed, version(newest))
    exported = list(getattr(module, "__all__", []))
    deprecated_table: Dict[str, Tuple[str, str]] = getattr(module, "DEPRECATED", {})
    for name, entry in sorted(surface.items()):
        if entry["deprecated"]:
            problems += _alias_problems(module, name, entry["use"], exported)
            continue
        if name not in exported or not hasattr(module, name):
            fix = (f"keep it, or list it as deprecated (use: <new name>) and add it to {module.__name__}.DEPRECATED "
                   "so the old name keeps working with a DeprecationWarning")
            problems.append(f"{name} is gone from {module.__name__} without a deprecation path: {fix}")
            continue
        kind, signature = describe(getattr(module, name))
        problems += _member_problems(name, getattr(module, name), entry)
        if (kind, signature) != (entry["kind"], entry["signature"]):
            why = breaks(entry["signature"], signature) if kind == entry["kind"] else f"a {entry['kind']} became a {kind}"
            problems.append(f"{name} is now {kind} {signature}, listed {entry['kind']} {entry['signature']}: "
                            + (f"a break ({why}): keep the old form working" if why else
                               "a compatible change: list it under changed: with a new version"))
    for name in exported:
        if name not in surface or surface[name]["deprecated"]:
            problems.append(f"{name} is in {module.__name__}.__all__ but not listed: list it in "
                            "tests/unit/student_api.yaml with since: <a new version> and raise API_VERSION")
    for name in deprecated_table:
        if name not in surface or not surface[name]["deprecated"]:
            problems.append(f"{name} is in {module.__name__}.DEPRECATED but not listed as deprecated")
    gone = [n for n, e in listed["names"].items() if n not in surface and version(e["since"]) <= version(newest)]
    problems += [f"{name} was removed but {module.__name__} still gives it" for name in gone
                 if name in exported or name in deprecated_table]
    return problems


def _member_problems(name: str, obj: Any, entry: Dict[str, Any]) -> List[str]:
    """A listed member that is gone or changed: a method, property or field students' files use."""
    problems = []
    for key, owner in (("members", obj), ("returns", returned_class(obj) if entry["returns"] else None)):
        for attr, listed_form in entry[key].items():
            form = member(owner, attr)
            if form == listed_form:
                continue
            why = "it is gone" if form == "missing" else breaks(listed_form, form) if listed_form.startswith("(") \
                else f"a {listed_form} became a {form}"
            if why:  # a compatible change (a new optional parameter) keeps every listed use working
                where = f"{name}.{attr}" if key == "members" else f"{attr} of what {name} returns"
                problems.append(f"{where} is now {form}, listed {listed_form}: a break ({why}): keep the old form "
                                "working")
    return problems


def _alias_problems(module: types.ModuleType, name: str, use: str, exported: List[str]) -> List[str]:
    if name in exported:
        return [f"{name} is deprecated but still in {module.__name__}.__all__: take it out of __all__"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            value = getattr(module, name)
        except AttributeError:
            return [f"{name} is deprecated but gone: it must keep working until the next major version"]
    said = [w for w in caught if issubclass(w.category, DeprecationWarning) and use in str(w.message)]
    if len(said) != 1 or "\n" in str(said[0].message):
        return [f"{module.__name__}.{name} must give one one-line DeprecationWarning naming {use}, gave "
                f"{[str(w.message) for w in caught]}"]
    if value is not getattr(module, use, None):
        return [f"{module.__name__}.{name} is not {use}"]
    return []


def committed() -> Dict[str, Any]:
    data: Dict[str, Any] = yaml.safe_load(LISTED.read_text(encoding="utf-8"))
    data["versions"] = {str(k): str(v) for k, v in data["versions"].items()}
    return data
