"""core.yamlfile.load_bounded(_all): a stranger's YAML, safe and bounded, read as rosparam reads honest files.

rosparam's loader evaluates ``!radians`` with eval; yaml.safe_load builds an alias bomb's billion
values (cheaply, as shared lists) that the first json.dumps writes out. The bounded loader gives
honest files exactly what rosparam gives, and refuses the rest in one line.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.yamlfile import (
    BoundedYamlError,
    arithmetic,
    disarm_rosparam_tags,
    load_bounded,
    load_bounded_all,
    read_yaml,
)

REPO = Path(__file__).resolve().parents[2]

HONEST = """\
robot_name: FER
robot_number: 1
robot_mass: 18.0
load_gripper: true
mixed_list: ['text', 1.0, 1]
gains: {p: 10.0, i: 1.0, d: 5.0}
quarter: !radians pi/2
turn: !radians 2 * pi
neg: !radians -pi / 4
plain: !radians 1.5
paren: !radians (pi + 1) * 2
written: rad(pi/3)
deg_tag: !degrees 90
deg_plain: deg(180)
deg_neg: !degrees -45.5
date: 2026-11-29
binary: !!binary aGVsbG8=
defaults: &d {a: 1, b: [1, 2]}
merged:
  <<: *d
  c: 3
"""

BOMB = "a: &a [" + ", ".join(["lol"] * 9) + "]\n" + "".join(
    f"{c}: &{c} [" + ", ".join([f"*{p}"] * 9) + "]\n" for p, c in zip("abcdefgh", "bcdefghi"))


def _rosparam_load(text: str):
    rosparam = pytest.importorskip("rosparam")
    return rosparam.load_str(text, "test.yaml", default_namespace="/")


def test_honest_files_load_exactly_as_rosparam_loads_them() -> None:
    ours = load_bounded_all(HONEST)
    theirs = [doc for doc, _ns in _rosparam_load(HONEST)]
    assert len(ours) == len(theirs) == 1
    binary_ours, binary_theirs = ours[0].pop("binary"), theirs[0].pop("binary")
    assert binary_ours == bytes(binary_theirs.data) == b"hello"  # rosparam wraps it in xmlrpc's Binary
    assert ours == theirs
    assert ours[0]["quarter"] == math.pi / 2 and ours[0]["deg_tag"] == math.pi / 2
    assert type(ours[0]["robot_number"]) is int and type(ours[0]["robot_mass"]) is float


def test_the_lab_and_answer_key_yaml_files_load_as_safe_load_loads_them() -> None:
    files = [p for folder in ("solutions/hri_lab", "hri_lab") for p in sorted((REPO / folder).rglob("*.yaml"))]
    assert files
    for path in files:
        text = path.read_text()
        assert load_bounded_all(text) == list(yaml.safe_load_all(text)), path


def test_several_documents_and_empty_files() -> None:
    assert load_bounded_all("") == [] and load_bounded("# only a comment\n") is None
    assert load_bounded_all("a: 1\n---\nb: 2\n") == [{"a": 1}, {"b": 2}]
    with pytest.raises(yaml.YAMLError):
        load_bounded("a: 1\n---\nb: 2\n")  # one document expected, as safe_load


def test_syntax_errors_are_yamls_own() -> None:
    text = "a: [1, 2\nb: 3\n"
    with pytest.raises(yaml.YAMLError) as ours:
        load_bounded_all(text)
    with pytest.raises(yaml.YAMLError) as theirs:
        list(yaml.safe_load_all(text))
    assert str(ours.value) == str(theirs.value)


def test_an_alias_bomb_is_refused_in_one_line() -> None:
    assert len(BOMB) < 700
    with pytest.raises(BoundedYamlError) as caught:
        load_bounded(BOMB)
    assert "aliases" in str(caught.value) and "\n" not in str(caught.value)
    assert isinstance(caught.value, HriTeleopError)
    with pytest.raises(BoundedYamlError):
        load_bounded_all(BOMB)


def test_a_long_string_repeated_through_aliases_is_refused_too() -> None:
    text = "s: &s " + "x" * 100_000 + "\nl: [" + ", ".join(["*s"] * 20) + "]\n"
    with pytest.raises(BoundedYamlError):
        load_bounded(text)


def test_recursive_anchors_deep_nesting_and_huge_files_are_refused() -> None:
    with pytest.raises(BoundedYamlError):
        load_bounded("a: &a [*a]\n")
    with pytest.raises(BoundedYamlError):
        load_bounded("[" * 5000 + "]" * 5000)
    with pytest.raises(BoundedYamlError):
        load_bounded("a: " + "x" * 300_000)


@pytest.mark.parametrize("text", [
    "x: !!python/object/apply:os.system ['touch /tmp/hri-bounded-yaml-owned']",
    "x: !!python/name:os.system",
    "x: !!python/object:collections.OrderedDict {}",
])
def test_python_tags_are_refused(text: str) -> None:
    with pytest.raises(yaml.YAMLError):
        load_bounded(text)
    assert not Path("/tmp/hri-bounded-yaml-owned").exists()


@pytest.mark.parametrize("payload", [
    "__import__('os').system('touch /tmp/hri-bounded-yaml-owned')",
    "open('/etc/passwd').read()",
    "(lambda: 1)()",
    "math.pi",
    "2 ** 10000000",
    "[1][0]",
    "x",
    "True + 1",
])
def test_radians_runs_no_code(payload: str) -> None:
    with pytest.raises(BoundedYamlError) as caught:
        load_bounded(f"x: !radians {payload!r}\n")
    assert "invalid radian expression" in str(caught.value) and "\n" not in str(caught.value)
    try:  # rad(...) is the tag only when no ")" comes before the end (rosparam's pattern); else a string
        assert isinstance(load_bounded(f"x: rad({payload})\n")["x"], str)
    except (BoundedYamlError, yaml.YAMLError):  # not YAML at all with a ": " in it
        pass
    assert not Path("/tmp/hri-bounded-yaml-owned").exists()


def test_arithmetic_is_numbers_pi_and_four_operators() -> None:
    assert arithmetic("pi") == math.pi
    assert arithmetic(" -pi/2 + 3*2 - +1 ") == -math.pi / 2 + 5
    assert arithmetic("1e3 / 4") == 250.0
    for bad in ("1/0", "", "pi pi", "a" * 2000):
        with pytest.raises(BoundedYamlError):
            arithmetic(bad)


def test_degrees_as_rosparam_reads_them() -> None:
    assert load_bounded("a: !degrees 180") == {"a": math.pi}
    with pytest.raises(BoundedYamlError) as caught:
        load_bounded("a: !degrees __import__('os')")
    assert "invalid degree value" in str(caught.value)


# --- the bounds at their edges ------------------------------------------------------------------------------


def test_a_document_weighs_one_per_node_plus_its_scalars_characters_and_passes_at_exactly_its_weight() -> None:
    """abc: 1 + 3; [ab, c]: 1 + 3 + 2; {a: bc}: 1 + (1 + 1) + (1 + 2); an alias counts again at each use."""
    for text, weight in (("abc", 4), ("[ab, c]", 6), ("{a: bc}", 6), ("{a: bcd}", 7), ("a: &x [1, 2]\nb: *x\n", 15)):
        assert load_bounded(text, max_weight=weight) == yaml.safe_load(text)
        assert load_bounded_all(text, max_weight=weight) == [yaml.safe_load(text)]
        with pytest.raises(BoundedYamlError, match=f"^the YAML expands to more than {weight - 1} values"):
            load_bounded(text, max_weight=weight - 1)


def test_a_recursive_anchor_is_named_as_such_not_as_deep_nesting() -> None:
    for text in ("&a [*a]", "&m {k: *m}"):
        with pytest.raises(BoundedYamlError, match="^the YAML refers to itself through an alias"):
            load_bounded(text)


def test_a_text_of_exactly_max_chars_is_read_and_one_more_is_refused() -> None:
    assert load_bounded("a: 1", max_chars=4) == {"a": 1}
    assert load_bounded_all("a: 1", max_chars=4) == [{"a": 1}]
    for load in (load_bounded, load_bounded_all):
        with pytest.raises(BoundedYamlError, match="^the YAML is larger than 0 kB"):
            load("a: 12", max_chars=4)


def test_the_plain_deg_and_rad_forms_read_the_number_inside_the_brackets() -> None:
    assert load_bounded("a: deg(90)\nb: deg(-45.5)\nc: rad(pi/4)\n") == {
        "a": math.pi / 2, "b": -45.5 * math.pi / 180.0, "c": math.pi / 4}


def test_an_expression_of_1000_characters_is_evaluated_and_one_of_1001_is_refused() -> None:
    assert arithmetic("pi/2" + " " * 996) == math.pi / 2
    with pytest.raises(BoundedYamlError, match="is longer than 1000 characters"):
        arithmetic("pi/2" + " " * 997)


# --- read_yaml: the file's own errors, in one line -----------------------------------------------------------


class _Refused(Exception):
    pass


def test_a_syntax_error_names_the_file_its_line_and_yamls_problem(tmp_path) -> None:
    path = tmp_path / "teleop.yaml"
    path.write_text("rate: 50\nname: 'open\n")
    with pytest.raises(_Refused) as info:
        read_yaml(path, _Refused)
    assert str(info.value) == (f"{path}:3: found unexpected end of stream; fix the YAML syntax "
                               "(indent with spaces, `key: value`)")


def test_a_character_yaml_does_not_read_names_the_file_and_the_character(tmp_path) -> None:
    """A control character is a ReaderError: no line mark and no problem of its own, only its text."""
    path = tmp_path / "teleop.yaml"
    path.write_text("rate: \x07\n")
    with pytest.raises(_Refused) as info:
        read_yaml(path, _Refused)
    assert str(info.value) == (f"{path}: unacceptable character #x0007: special characters are not allowed; fix the "
                               "YAML syntax (indent with spaces, `key: value`)")


def test_a_utf8_file_is_read_as_utf8_also_in_the_c_locale(tmp_path) -> None:
    import locale

    path = tmp_path / "teleop.yaml"
    path.write_bytes("label: Kraft ≤ 20 N\n".encode("utf-8"))
    before = locale.setlocale(locale.LC_CTYPE)
    locale.setlocale(locale.LC_CTYPE, "C")
    try:
        assert read_yaml(path, _Refused) == {"label": "Kraft ≤ 20 N"}
    finally:
        locale.setlocale(locale.LC_CTYPE, before)


# --- roslaunch's loaders, disarmed ---------------------------------------------------------------------------


@pytest.mark.parametrize("loader", [yaml.SafeLoader, yaml.Loader, yaml.FullLoader, yaml.UnsafeLoader])
def test_once_disarmed_every_pyyaml_loader_reads_angles_by_arithmetic_and_runs_no_code(loader, monkeypatch) -> None:
    """From a loader without the angle tags (as before rosparam's import), whatever earlier tests left there."""
    monkeypatch.setattr(loader, "yaml_constructors", {tag: build for tag, build in loader.yaml_constructors.items()
                                                      if tag not in ("!radians", "!degrees")})
    disarm_rosparam_tags()
    assert yaml.load("a: !radians pi/2\nb: !degrees 90\n", Loader=loader) == {"a": math.pi / 2, "b": math.pi / 2}
    with pytest.raises(BoundedYamlError, match="^invalid radian expression"):
        yaml.load("a: !radians __import__('os').getcwd()\n", Loader=loader)
    with pytest.raises(yaml.constructor.ConstructorError, match="could not determine a constructor for the tag"):
        yaml.load("a: !other 1\n", Loader=loader)  # an unknown tag stays unknown: the angle tags take their own only
