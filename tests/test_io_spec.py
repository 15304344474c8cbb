"""mobman.io.spec: reading specification files and checking each field, with one-line errors naming it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from mobman.errors import InputError, ModelError
from mobman.io import spec

# --- read_text -------------------------------------------------------------------------------------------


def test_read_text_returns_the_utf8_text(tmp_path: Path):
    path = tmp_path / "spec.toml"
    path.write_bytes('name = "Ω-robot"\n'.encode())
    assert spec.read_text(path, "--spec") == 'name = "Ω-robot"\n'


def test_read_text_accepts_a_file_of_exactly_the_limit(tmp_path: Path):
    path = tmp_path / "spec.toml"
    path.write_bytes(b"x = 12")
    assert spec.read_text(path, "--spec", limit=6) == "x = 12"


@pytest.mark.parametrize(
    ("content", "phrase"),
    [
        (b"x = 123", "larger than"),
        (b"a\0b", "binary content (a NUL byte at 1)"),
        (b"x='\xff'", "not UTF-8 text (byte 3)"),
    ],
    ids=["too-large", "nul-byte", "not-utf8"],
)
def test_read_text_rejects_bad_content(tmp_path: Path, content: bytes, phrase: str):
    path = tmp_path / "spec.toml"
    path.write_bytes(content)
    with pytest.raises(InputError) as info:
        spec.read_text(path, "--spec", limit=6)
    message = str(info.value)
    assert message.startswith("--spec: ")
    assert phrase in message
    assert "\n" not in message


def test_read_text_of_a_missing_file_names_the_field(tmp_path: Path):
    with pytest.raises(InputError, match=r"^--spec: cannot read \(No such file or directory\)$"):
        spec.read_text(tmp_path / "absent.toml", "--spec")


def test_read_text_of_a_folder_names_the_field(tmp_path: Path):
    with pytest.raises(InputError, match=r"^--spec: cannot read \("):
        spec.read_text(tmp_path, "--spec")


# --- read_toml -------------------------------------------------------------------------------------------


def test_read_toml_returns_the_document(tmp_path: Path):
    path = tmp_path / "spec.toml"
    path.write_text('[robot]\nname = "bayle-planar"\n[robot.params]\nl1 = 0.6\nsteps = [1, 2]\n')
    assert spec.read_toml(path) == {"robot": {"name": "bayle-planar", "params": {"l1": 0.6, "steps": [1, 2]}}}


def test_read_toml_accepts_the_deepest_allowed_nesting(tmp_path: Path):
    path = tmp_path / "spec.toml"
    path.write_text("a = [[[[[[[1]]]]]]]\n")  # the document, then seven arrays: eight levels
    assert spec.read_toml(path) == {"a": [[[[[[[1]]]]]]]}


@pytest.mark.parametrize(
    ("content", "phrase"),
    [
        ("robot = \n", "invalid TOML"),
        ("[robot]\n[robot]\n", "invalid TOML"),
        ("a = [[[[[[[[1]]]]]]]]\n", "nested deeper than 8 levels"),
        ("[a.b.c.d.e.f.g.h]\nx = 1\n", "nested deeper than 8 levels"),
        ("a = " + "[" * 5000 + "]" * 5000 + "\n", "nested deeper than 8 levels"),
    ],
    ids=["no-value", "table-twice", "arrays-9-levels", "tables-9-levels", "arrays-5000-levels"],
)
def test_read_toml_rejects_invalid_or_too_deep_documents(tmp_path: Path, content: str, phrase: str):
    path = tmp_path / "spec.toml"
    path.write_text(content)
    with pytest.raises(InputError) as info:
        spec.read_toml(path)
    assert str(info.value).startswith(f"{path}: ")
    assert phrase in str(info.value)


def test_read_toml_names_the_file_when_it_is_not_text(tmp_path: Path):
    path = tmp_path / "spec.toml"
    path.write_bytes(b"\x89PNG\0\0")
    with pytest.raises(InputError, match="binary content") as info:
        spec.read_toml(path)
    assert str(info.value).startswith(f"{path}: ")


# --- naming ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("as_text", [False, True], ids=["path", "str"])
def test_naming_prefixes_an_input_error_with_the_file(tmp_path: Path, as_text: bool):
    path = tmp_path / "spec.toml"
    with pytest.raises(InputError) as info:
        with spec.naming(str(path) if as_text else path):
            raise InputError("gains.W: must be > 0, got -1")
    assert str(info.value) == f"{path}: gains.W: must be > 0, got -1"


def test_naming_prefixes_only_once(tmp_path: Path):
    path = tmp_path / "spec.toml"
    with pytest.raises(InputError) as info:
        with spec.naming(path):
            with spec.naming(path):
                raise InputError("reference.period: missing (a number)")
    assert str(info.value) == f"{path}: reference.period: missing (a number)"


def test_naming_leaves_other_errors_and_good_blocks_alone(tmp_path: Path):
    with spec.naming(tmp_path / "spec.toml"):
        value = 3
    assert value == 3
    with pytest.raises(ModelError, match="^robot: bad$"):
        with spec.naming(tmp_path / "spec.toml"):
            raise ModelError("robot: bad")


# --- table, keys, kind -----------------------------------------------------------------------------------


def test_table_returns_the_sub_table_or_none():
    data = {"robot": {"name": "bayle-planar"}}
    assert spec.table(data, "robot", "robot") == {"name": "bayle-planar"}
    assert spec.table(data, "law", "law", required=False) is None


def test_table_missing_when_required():
    with pytest.raises(InputError, match=r"^law: missing \(a \[law\] table\)$"):
        spec.table({}, "law", "law")


def test_table_of_the_wrong_type():
    with pytest.raises(InputError, match="^robot: must be a table, got 3$"):
        spec.table({"robot": 3}, "robot", "robot")


def test_a_long_wrong_value_is_shown_shortened():
    with pytest.raises(InputError) as info:
        spec.table({"robot": "x" * 500}, "robot", "robot")
    shown = str(info.value).removeprefix("robot: must be a table, got ")
    assert shown.endswith("...")
    assert len(shown) == 60


def test_keys_accepts_allowed_keys():
    assert spec.keys({"period": 1.0, "kind": "circle"}, "reference", ("kind", "period", "radius")) is None


def test_keys_rejects_an_unknown_key_suggesting_the_closest():
    with pytest.raises(InputError) as info:
        spec.keys({"perod": 1.0}, "reference", ("kind", "period", "radius"))
    assert (
        str(info.value)
        == "reference.perod: unknown key; did you mean 'period'? allowed: kind, period, radius"
    )


def test_keys_rejects_an_unknown_key_without_a_close_one():
    with pytest.raises(InputError) as info:
        spec.keys({"zzz": 1.0}, "", ("kind", "period"))
    assert str(info.value) == "zzz: unknown key; allowed: kind, period"


def test_kind_selects_the_value():
    kinds = {"circle": 1, "line": 2}
    assert spec.kind({"kind": "line"}, "reference", kinds) == 2


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ({"kind": "circel"}, "reference.kind: 'circel' not one of circle, line (did you mean 'circle'?)"),
        ({"kind": "spiral"}, "reference.kind: 'spiral' not one of circle, line"),
        ({}, "reference.kind: None not one of circle, line"),
        ({"kind": 3}, "reference.kind: 3 not one of circle, line"),
    ],
    ids=["typo", "unknown", "missing", "not-a-string"],
)
def test_kind_rejects_an_unknown_kind(entries: dict, message: str):
    with pytest.raises(InputError) as info:
        spec.kind(entries, "reference", {"circle": 1, "line": 2})
    assert str(info.value) == message


# --- text, integer, number -------------------------------------------------------------------------------


def test_text_returns_the_string_or_the_default():
    entries = {"method": "rk4"}
    assert spec.text(entries, "method", "simulation", allowed=("euler", "rk4")) == "rk4"
    assert spec.text(entries, "name", "simulation") is None
    assert spec.text(entries, "name", "simulation", default="run") == "run"


@pytest.mark.parametrize(
    ("value", "phrase"),
    [
        (3, "must be a string (at most 200 characters), got 3"),
        ("a" * 201, "must be a string (at most 200 characters)"),
        ("eulr", "'eulr' not one of euler, RK4 (did you mean 'euler'?)"),
        ("RK4 ", "'RK4 ' not one of euler, RK4 (did you mean 'RK4'?)"),
        ("rk4", "'rk4' not one of euler, RK4 (did you mean 'RK4'?)"),
        ("midpoint", "'midpoint' not one of euler, RK4"),
    ],
    ids=["not-a-string", "too-long", "typo", "trailing-space", "case", "unknown"],
)
def test_text_rejects_bad_strings(value: object, phrase: str):
    with pytest.raises(InputError) as info:
        spec.text({"method": value}, "method", "simulation", allowed=("euler", "RK4"))
    assert str(info.value).startswith("simulation.method: ")
    assert phrase in str(info.value)
    if phrase.endswith("RK4"):
        assert "did you mean" not in str(info.value)


def test_text_without_a_field_names_the_key():
    with pytest.raises(InputError, match="^method: must be a string"):
        spec.text({"method": 1.5}, "method", "")


def test_integer_returns_the_integer_or_the_default():
    assert spec.integer({"steps": 10**6}, "steps", "simulation", minimum=1) == 10**6
    assert spec.integer({"steps": -3}, "steps", "simulation") == -3
    assert spec.integer({}, "steps", "simulation", default=50) == 50
    assert spec.integer({}, "steps", "simulation") is None


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (True, "simulation.steps: must be an integer, got True"),
        (2.0, "simulation.steps: must be an integer, got 2.0"),
        ("10", "simulation.steps: must be an integer, got '10'"),
        (10**6 + 1, "simulation.steps: must be an integer, got 1000001"),
        (-(10**6) - 1, "simulation.steps: must be an integer, got -1000001"),
        (0, "simulation.steps: must be ≥ 1, got 0"),
    ],
    ids=["bool", "float", "string", "too-large", "too-negative", "below-minimum"],
)
def test_integer_rejects_bad_values(value: object, message: str):
    with pytest.raises(InputError) as info:
        spec.integer({"steps": value}, "steps", "simulation", minimum=1)
    assert str(info.value) == message


def test_number_returns_a_float():
    value = spec.number({"period": 4}, "period", "reference")
    assert value == 4.0 and type(value) is float
    assert spec.number({"period": -1e6}, "period", "reference") == -1e6
    assert spec.number({"period": 0.5}, "period", "reference", positive=True) == 0.5
    assert spec.number({}, "period", "reference", default=2.5) == 2.5


@pytest.mark.parametrize(
    ("value", "phrase"),
    [
        (True, "must be a finite number, got True"),
        ("1.0", "must be a finite number, got '1.0'"),
        ([1.0], "must be a finite number, got [1.0]"),
        (float("nan"), "must be a finite number with |value| ≤ 1e+06, got nan"),
        (float("inf"), "must be a finite number with |value| ≤ 1e+06, got inf"),
        (-float("inf"), "must be a finite number with |value| ≤ 1e+06, got -inf"),
        (1.5e6, "must be a finite number with |value| ≤ 1e+06, got 1500000.0"),
        (10**400, "must be a finite number with |value| ≤ 1e+06"),
        (0, "must be > 0, got 0"),
        (-2.0, "must be > 0, got -2.0"),
    ],
    ids=["bool", "string", "list", "nan", "inf", "-inf", "too-large", "huge-integer", "zero", "negative"],
)
def test_number_rejects_bad_values(value: object, phrase: str):
    with pytest.raises(InputError) as info:
        spec.number({"period": value}, "period", "reference", positive=True)
    assert str(info.value) == f"reference.period: {phrase}"


@pytest.mark.parametrize(("field", "name"), [("reference", "reference.period"), ("", "period")])
def test_number_missing(field: str, name: str):
    with pytest.raises(InputError) as info:
        spec.number({}, "period", field)
    assert str(info.value) == f"{name}: missing (a number)"


# --- array -----------------------------------------------------------------------------------------------


def test_array_of_a_number_and_of_nested_lists():
    scalar = spec.array(2, "gains.k")
    assert scalar.shape == () and scalar.dtype == np.float64 and scalar == 2.0
    matrix = spec.array([[1, 2.5], [3, -4]], "gains.W")
    assert matrix.dtype == np.float64
    np.testing.assert_array_equal(matrix, np.array([[1.0, 2.5], [3.0, -4.0]]))
    np.testing.assert_array_equal(spec.array((1, 2), "gains.k"), [1.0, 2.0])
    np.testing.assert_array_equal(spec.array(np.arange(3), "gains.k"), [0.0, 1.0, 2.0])


@pytest.mark.parametrize(
    ("value", "phrase"),
    [
        ([1.0, True], "must be a number or an array of numbers"),
        ([1.0, "2"], "must be a number or an array of numbers"),
        (None, "must be a number or an array of numbers"),
        ([[1.0, {"a": 1}]], "must be a number or an array of numbers"),
        ([[1.0], [float("nan")]], "must be a finite number with |value| ≤ 1e+06"),
        ([float("inf")], "must be a finite number with |value| ≤ 1e+06"),
        ([1.0, -2e6], "must be a finite number with |value| ≤ 1e+06"),
        (np.array([1.0, np.nan]), "must be a finite number with |value| ≤ 1e+06"),
        ([10**400], "must be finite numbers with |value| ≤ 1e+06"),
        ([[1.0, 2.0], [3.0]], "must be a rectangular array of numbers"),
    ],
    ids=["bool", "string", "none", "table", "nan", "inf", "too-large", "numpy-nan", "huge-integer", "ragged"],
)
def test_array_rejects_bad_values(value: object, phrase: str):
    with pytest.raises(InputError) as info:
        spec.array(value, "gains.W")
    assert str(info.value).startswith(f"gains.W: {phrase}")


# --- build -----------------------------------------------------------------------------------------------


def _circle(radius: float = 1.0) -> tuple[str, float]:
    if radius <= 0:
        raise ModelError(f"circle: radius must be > 0,\n    got {radius}")
    return ("circle", radius)


def test_build_returns_what_the_constructor_builds():
    assert spec.build("reference", _circle, radius=2.0) == ("circle", 2.0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"radius": -1.0}, "reference: circle: radius must be > 0, got -1.0"),
        ({"radus": 1.0}, "reference: _circle() got an unexpected keyword argument 'radus'"),
    ],
    ids=["model-error", "unknown-argument"],
)
def test_build_turns_constructor_errors_into_input_errors(kwargs: dict, message: str):
    with pytest.raises(InputError) as info:
        spec.build("reference", _circle, **kwargs)
    assert str(info.value) == message


def test_build_turns_a_value_error_into_an_input_error():
    with pytest.raises(InputError, match="^gains.W: could not convert string to float: 'x'$"):
        spec.build("gains.W", lambda: float("x"))


def test_build_lets_unexpected_errors_through():
    def broken() -> None:
        raise RuntimeError("internal")

    with pytest.raises(RuntimeError, match="^internal$"):
        spec.build("reference", broken)


# --- dataclass_values ------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class _Limits:
    low: float
    high: float


def _limits(value: object, name: str) -> _Limits:
    entries = spec.table({"x": value}, "x", name)
    spec.keys(entries, name, ("low", "high"))
    return _Limits(spec.number(entries, "low", name), spec.number(entries, "high", name))


@dataclasses.dataclass
class _Settings:
    method: str = "euler"
    steps: int = 10
    dt: float = 0.1
    verbose: bool = False
    gains: np.ndarray = dataclasses.field(default_factory=lambda: np.ones(2))
    weights: npt.ArrayLike = 1.0
    scale: npt.ArrayLike | None = None
    limit: float | None = None
    span: tuple[float, float] = (0.0, 1.0)
    levels: tuple[int, ...] = ()
    bounds: _Limits | None = None
    tags: list[str] = dataclasses.field(default_factory=list)
    cache: int = dataclasses.field(default=0, init=False)


_CONVERT = {_Limits: _limits}


def test_dataclass_values_reads_each_annotation():
    entries = {
        "kind": "settings",
        "method": "rk4",
        "steps": 20,
        "dt": 1,
        "verbose": True,
        "gains": [[1, 2], [3, 4]],
        "weights": 3,
        "scale": [0.5, 2],
        "limit": 2,
        "span": [0, 2.5],
        "levels": [1, 2, 3],
        "bounds": {"low": -1, "high": 1},
    }
    values = spec.dataclass_values(
        _Settings, entries, "law", choices={"method": ("euler", "rk4")}, convert=_CONVERT
    )
    assert set(values) == set(entries) - {"kind"}
    assert values["method"] == "rk4"
    assert values["steps"] == 20 and type(values["steps"]) is int
    assert values["dt"] == 1.0 and type(values["dt"]) is float
    assert values["verbose"] is True
    np.testing.assert_array_equal(values["gains"], np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert values["gains"].dtype == np.float64
    assert isinstance(values["weights"], np.ndarray) and values["weights"] == 3.0
    np.testing.assert_array_equal(values["scale"], [0.5, 2.0])
    assert values["limit"] == 2.0 and type(values["limit"]) is float
    assert values["span"] == (0.0, 2.5) and all(type(v) is float for v in values["span"])
    assert values["levels"] == (1, 2, 3)
    assert values["bounds"] == _Limits(-1.0, 1.0)
    assert _Settings(**values).method == "rk4"


def test_dataclass_values_leaves_absent_keys_to_the_defaults():
    assert spec.dataclass_values(_Settings, {"kind": "x"}, "law", convert=_CONVERT) == {}
    assert spec.dataclass_values(_Settings, {}, "law", convert=_CONVERT) == {}


def test_dataclass_values_passes_the_field_name_to_a_converter():
    with pytest.raises(InputError) as info:
        spec.dataclass_values(_Settings, {"bounds": {"low": 0, "hihg": 1}}, "law", convert=_CONVERT)
    assert str(info.value).startswith("law.bounds.hihg: unknown key; did you mean 'high'?")


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ({"method": "rk5"}, "law.method: 'rk5' not one of euler, rk4 (did you mean 'rk4'?)"),
        ({"steps": 1.5}, "law.steps: must be an integer, got 1.5"),
        ({"dt": "0.1"}, "law.dt: must be a finite number, got '0.1'"),
        ({"verbose": 1}, "law.verbose: must be true or false, got 1"),
        ({"gains": [1, "a"]}, "law.gains: must be a number or an array of numbers, got [1, 'a']"),
        ({"weights": [float("nan")]}, "law.weights: must be a finite number with |value| ≤ 1e+06, got nan"),
        ({"limit": float("inf")}, "law.limit: must be a finite number with |value| ≤ 1e+06, got inf"),
        ({"span": [0, 1, 2]}, "law.span: 2 values, got 3"),
        ({"span": 1.0}, "law.span: must be an array, got 1.0"),
        ({"levels": [1, 2.5]}, "law.levels[1]: must be an integer, got 2.5"),
        ({"span": [0, True]}, "law.span[1]: must be a finite number, got True"),
    ],
    ids=[
        "choice",
        "int",
        "float",
        "bool",
        "ndarray",
        "array-like",
        "optional",
        "length",
        "not-a-list",
        "variadic-item",
        "tuple-item",
    ],
)
def test_dataclass_values_rejects_values_of_the_wrong_type(entries: dict, message: str):
    with pytest.raises(InputError) as info:
        spec.dataclass_values(
            _Settings, entries, "law", choices={"method": ("euler", "rk4")}, convert=_CONVERT
        )
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("entries", "options", "name"),
    [
        ({"stpes": 3}, {}, "law.stpes"),
        ({"tags": ["a"]}, {}, "law.tags"),
        ({"cache": 1}, {}, "law.cache"),
        ({"bounds": {"low": 0, "high": 1}}, {"convert": None}, "law.bounds"),
        ({"steps": 3}, {"names": ("dt", "method")}, "law.steps"),
        ({"kind": "x"}, {"other_keys": ()}, "law.kind"),
    ],
    ids=["typo", "not-readable", "not-init", "no-converter", "not-named", "kind-not-allowed"],
)
def test_dataclass_values_rejects_keys_a_file_cannot_give(entries: dict, options: dict, name: str):
    options = {"convert": _CONVERT, **options}
    with pytest.raises(InputError) as info:
        spec.dataclass_values(_Settings, entries, "law", **options)
    message = str(info.value)
    assert message.startswith(f"{name}: unknown key; ")
    allowed = message.split("allowed: ", 1)[1].split(", ")
    assert name.removeprefix("law.") not in allowed
    assert "tags" not in allowed and "cache" not in allowed


def test_dataclass_values_suggests_the_closest_field():
    with pytest.raises(InputError, match="^law.stpes: unknown key; did you mean 'steps'\\? allowed: kind, "):
        spec.dataclass_values(_Settings, {"stpes": 3}, "law", convert=_CONVERT)


def test_dataclass_values_with_names_keeps_only_those():
    values = spec.dataclass_values(_Settings, {"dt": 0.5}, "gains", names=("dt",), other_keys=())
    assert values == {"dt": 0.5}
    with pytest.raises(InputError, match=r"allowed: dt$"):
        spec.dataclass_values(_Settings, {"steps": 2}, "gains", names=("dt",), other_keys=())
