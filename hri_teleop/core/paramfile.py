"""Write the calibration value (Ex. 11) into a student's launch or YAML file, changing nothing else.

After calibrating, ``/max_sensor_force`` must survive the next ``roslaunch``, so it goes into the
student's own file, whose comments and layout an XML or YAML library would lose. So the edit is
textual: only the characters of the one value change, and the result is parsed again to prove it
now holds the new value. A file without a place for it is refused with one line saying what to add.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path
from typing import List, Optional, Tuple, Union

import yaml

from hri_teleop.core.checks import is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.files import replace_text
from hri_teleop.core.mapping import ADC_MAX_COUNT

__all__ = ["ParamFileError", "ParamEdit", "PARAM_NAME", "set_in_launch", "set_in_yaml", "write_max_sensor_force"]

#: The parameter Ex. 11 calibrates (docs/lab-facts.md: an int, ADC counts).
PARAM_NAME = "max_sensor_force"


class ParamFileError(HriTeleopError, ValueError):
    """The file cannot take the calibration value (one line: the file, the cause, the fix)."""


@dataclass(frozen=True)
class ParamEdit:
    """One edit: where (1-based line), what was there and what is there now."""

    line: int
    old: str
    new: str
    what: str  # e.g. '<arg name="max_sensor_force"> default'


def _check_value(value: object, source: str) -> str:
    if not is_int(value, numpy=True) or not 0 < int(value) <= ADC_MAX_COUNT:
        raise ParamFileError(f"{source}: /{PARAM_NAME} must be an integer ADC count 1..{ADC_MAX_COUNT}, "
                             f"got {value!r}; calibrate again with the piston pressed in")
    return str(int(value))


# -- launch files (XML) -------------------------------------------------------------------

# Comments, CDATA, processing instructions / declarations, and tags whose quoted attribute
# values may contain '>' (roslaunch's $(eval a > b)).
_XML_TOKEN = re.compile(
    r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<[?!][^>]*>"
    r"|<(?P<close>/)?(?P<tag>[A-Za-z_][\w.:-]*)(?P<attrs>(?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(?P<empty>/)?>",
    re.S)
_XML_ATTR = re.compile(r"(?P<name>[^\s=/>]+)\s*=\s*(?P<quote>[\"'])(?P<value>.*?)(?P=quote)", re.S)
_ARG_REF = re.compile(r"^\s*\$\(arg\s+(?P<name>[^\s)]+)\s*\)\s*$")


@dataclass
class _Tag:
    tag: str
    start: int  # offset of '<' in the text
    attrs: List[Tuple[str, str, int]]  # (name, value, offset of the value in the text)
    scope: str  # "global" or why it is not: "node" (or <test>) / "group ns" (or <include ns>)

    def get(self, name: str) -> Optional[Tuple[str, int]]:
        for key, value, offset in self.attrs:
            if key == name:
                return value, offset
        return None

    def value_of(self, name: str) -> Tuple[str, int]:
        """``get(name)`` of an attribute the caller has checked is there."""
        found = self.get(name)
        if found is None:
            raise KeyError(f"<{self.tag}> has no {name} attribute")
        return found


def _tags(text: str) -> List[_Tag]:
    """Every start tag with its attributes (value offsets) and whether it is in global scope."""
    found: List[_Tag] = []
    stack: List[str] = []  # per open element: "" (global scope) or the reason it is not
    for match in _XML_TOKEN.finditer(text):
        tag = match.group("tag")
        if tag is None:
            continue  # comment, CDATA, declaration
        if match.group("close"):
            if stack:
                stack.pop()
            continue
        attrs = [(m.group("name"), m.group("value"), match.start("attrs") + m.start("value"))
                 for m in _XML_ATTR.finditer(match.group("attrs") or "")]
        outer = next((reason for reason in reversed(stack) if reason), "")
        item = _Tag(tag, match.start(), attrs, outer or "global")
        found.append(item)
        if not match.group("empty"):
            inner = outer
            if not inner and tag in ("node", "test"):
                inner = "node"
            elif not inner and tag in ("group", "include"):
                ns = item.get("ns")
                if ns is not None and ns[0].strip() not in ("", "/"):
                    inner = "group ns"
            stack.append(inner)
    return found


def _line_of(text: str, offset: int) -> int:
    return text.count("\n", 0, offset) + 1


def _parse_xml(text: str, source: str, fix: str) -> None:
    try:
        ElementTree.fromstring(text)
    except ElementTree.ParseError as exc:
        line = getattr(exc, "position", (0, 0))[0]
        raise ParamFileError(f"{source}:{line}: not well-formed XML ({str(exc).split(':')[0]}); {fix}") from None


def set_in_launch(text: str, value: int, source: str = "<launch>") -> Tuple[str, List[ParamEdit]]:
    """``text`` with the calibration value set, and the edits made.

    The value set is a ``<param name="max_sensor_force" value="..."/>`` that sets the global
    parameter (outside ``<node>``/``<test>`` and a namespaced ``<group>``/``<include>``, or named
    ``/max_sensor_force``);
    if its value is ``$(arg X)``, the default (or value) of ``<arg name="X" .../>`` changes
    instead. Without such a param, ``<arg name="max_sensor_force" default="..."/>`` is used.

    Raises :class:`ParamFileError` if the file is not well-formed XML, has no
    ``max_sensor_force`` param or arg, or sets it with a substitution other than ``$(arg)``.
    """
    new_value = _check_value(value, source)
    _parse_xml(text, source, "fix the file first (roslaunch would refuse it too)")
    tags = _tags(text)
    params = []
    for tag in tags:
        name = tag.get("name")
        if tag.tag != "param" or name is None:
            continue
        if name[0] == "/" + PARAM_NAME or (name[0] == PARAM_NAME and tag.scope == "global"):
            params.append(tag)
    # The first <arg> of a name is its declaration (roslaunch reads in order); a later one inside an
    # <include> only passes a value on, often $(arg name) itself: reversed, so that the first one wins.
    args = {tag.value_of("name")[0]: tag for tag in reversed(tags)
            if tag.tag == "arg" and tag.get("name") is not None and tag.scope == "global"}

    targets: List[Tuple[_Tag, str]] = []  # (tag, attribute to change)
    for param in params:
        current = param.get("value")
        if current is None:
            raise ParamFileError(f"{source}:{_line_of(text, param.start)}: <param name=\"{PARAM_NAME}\"> has no "
                                 "value attribute; write it as <param name=\"max_sensor_force\" value=\"700\"/>")
        ref = _ARG_REF.match(current[0])
        if ref:
            arg = args.get(ref.group("name"))
            if arg is None:
                raise ParamFileError(f"{source}:{_line_of(text, param.start)}: <param name=\"{PARAM_NAME}\"> uses "
                                     f"$(arg {ref.group('name')}) but the file declares no such <arg>; "
                                     f"add <arg name=\"{ref.group('name')}\" default=\"700\"/>")
            attribute = "value" if arg.get("value") is not None else "default"
            if arg.get(attribute) is None:
                raise ParamFileError(f"{source}:{_line_of(text, arg.start)}: <arg name=\"{ref.group('name')}\"> has "
                                     "no default; give it one, e.g. default=\"700\"")
            targets.append((arg, attribute))
        elif "$(" in current[0]:
            raise ParamFileError(f"{source}:{_line_of(text, param.start)}: <param name=\"{PARAM_NAME}\"> is computed "
                                 f"({current[0].strip()}); write a number or $(arg ...) there to let the calibration "
                                 "set it")
        else:
            targets.append((param, "value"))
    if not params and PARAM_NAME in args:
        arg = args[PARAM_NAME]
        attribute = "value" if arg.get("value") is not None else "default"
        if arg.get(attribute) is None:
            raise ParamFileError(f"{source}:{_line_of(text, arg.start)}: <arg name=\"{PARAM_NAME}\"> has no default; "
                                 "give it one, e.g. default=\"700\"")
        targets.append((arg, attribute))
    if not targets:
        raise ParamFileError(f"{source}: no /{PARAM_NAME} parameter to set; add <param name=\"{PARAM_NAME}\" "
                             "value=\"700\"/> inside <launch> (Ex. 12 g) and calibrate again")

    edits: List[ParamEdit] = []
    spans = {}
    for tag, attribute in targets:
        old, offset = tag.value_of(attribute)
        if offset in spans:
            continue  # two params naming the same arg
        spans[offset] = (offset, offset + len(old))
        edits.append(ParamEdit(_line_of(text, offset), old, new_value,
                               f"<{tag.tag} name=\"{tag.value_of('name')[0]}\"> {attribute}"))
    result = text
    for start, end in sorted(spans.values(), reverse=True):
        result = result[:start] + new_value + result[end:]
    _parse_xml(result, source, "this is a bug of hri_teleop.core.paramfile; edit the file by hand")
    edits.sort(key=lambda e: e.line)
    return result, edits


# -- YAML files ---------------------------------------------------------------------------

_YAML_KEY = re.compile(
    r"^(?P<key>/?max_sensor_force|\"/?max_sensor_force\"|'/?max_sensor_force')(?P<sep>[ \t]*:[ \t]*)"
    r"(?P<value>[^#\r\n]*?)(?P<tail>[ \t]*(?:#[^\r\n]*)?)$", re.M)


def set_in_yaml(text: str, value: int, source: str = "<yaml>") -> Tuple[str, List[ParamEdit]]:
    """``text`` with the top-level ``max_sensor_force:`` value replaced (comment kept)."""
    new_value = _check_value(value, source)
    try:
        before = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark is not None else source
        raise ParamFileError(f"{where}: not valid YAML; fix the file first (rosparam load would refuse it "
                             "too)") from None
    matches = list(_YAML_KEY.finditer(text))
    if not isinstance(before, dict) or not matches:
        raise ParamFileError(f"{source}: no top-level `{PARAM_NAME}: ...` line; add `{PARAM_NAME}: 700` at the start "
                             "of a line and calibrate again")
    if len(matches) > 1:
        raise ParamFileError(f"{source}:{_line_of(text, matches[1].start())}: {PARAM_NAME} is set twice; keep one line")
    match = matches[0]
    if not match.group("value").strip():
        raise ParamFileError(f"{source}:{_line_of(text, match.start())}: {PARAM_NAME} has no value on its line; "
                             f"write `{PARAM_NAME}: 700`")
    result = text[:match.start("value")] + new_value + text[match.end("value"):]
    try:
        after = yaml.safe_load(result)
    except yaml.YAMLError:  # e.g. the value carried an anchor (&a 700) that an alias elsewhere needs
        after = None
    key = match.group("key").strip("\"'")
    if not isinstance(after, dict) or after.get(key) != int(new_value):
        raise ParamFileError(f"{source}: could not set {PARAM_NAME} without changing the file's structure; "
                             f"write it as a plain line `{PARAM_NAME}: 700`")
    edit = ParamEdit(_line_of(text, match.start()), match.group("value"), new_value, f"{key}:")
    return result, [edit]


# -- files --------------------------------------------------------------------------------


def _is_launch(path: Path, text: str) -> bool:
    suffix = path.suffix.lower()
    if suffix in (".launch", ".xml"):
        return True
    if suffix in (".yaml", ".yml"):
        return False
    return text.lstrip().startswith("<")


def write_max_sensor_force(path: Union[str, Path], value: int) -> List[ParamEdit]:
    """Set the calibration value in the launch or YAML file ``path`` in place; returns the edits.

    The file is replaced atomically (a crash leaves the old or the new file, never half of
    one) and keeps its permissions. Nothing is written when an error is raised.
    """
    file = Path(path)
    source = str(path)
    try:
        raw = file.read_bytes()
    except FileNotFoundError:
        raise ParamFileError(f"{source} not found; give the path of your teleoperation.launch, sensor.launch "
                             "or YAML file") from None
    except IsADirectoryError:
        raise ParamFileError(f"{source} is a directory; give the path of the launch or YAML file") from None
    except OSError as exc:
        raise ParamFileError(f"{source}: cannot read ({exc.strerror}); check the file's permissions") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ParamFileError(f"{source}: not UTF-8 text; save it as UTF-8") from None
    setter = set_in_launch if _is_launch(file, text) else set_in_yaml
    result, edits = setter(text, value, source)
    if result == text:
        return edits
    try:
        replace_text(file, result)
    except OSError as exc:
        raise ParamFileError(f"{source}: cannot write ({exc.strerror}); check the file's permissions") from None
    return edits
