"""Fuzzing the command line's contract: generated option values, robot files and spec files (valid and invalid)
end in exit 0 with finite output or exit 2 with one line on standard error, never another exit status."""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
import tomllib
from pathlib import Path

from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from mobman.cli import main
from mobman.errors import MobmanError
from mobman.io import robot_file
from mobman.model.robot import MobileManipulator

ROOT = Path(__file__).resolve().parents[1]
ROBOT = tomllib.loads((ROOT / "docs" / "examples" / "planar_robot.toml").read_text())
SPEC = {
    "duration": 0.2,
    "dt": 0.02,
    "q0": [0.0, 0.0, 0.0, -0.785, 1.57],
    "robot": {"name": "bayle-planar"},
    "task": {"kind": "position", "components": "xy"},
    "reference": {"kind": "line", "start": [0.707, 0.0], "end": [0.807, 0.05], "duration": 0.2},
    "law": {"kind": "bayle"},
    "gains": {"W": 2.0},
}
FUZZ = settings(
    max_examples=20, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return (
            "nan"
            if math.isnan(value)
            else ("inf" if value > 0 else "-inf")
            if math.isinf(value)
            else repr(value)
        )
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return (
        "{"
        + ", ".join(f"{json.dumps(str(k), ensure_ascii=False)} = {toml_value(v)}" for k, v in value.items())
        + "}"
    )


def toml_document(data: dict) -> str:
    """TOML text of ``data``: scalars first, then one [table] or [[array of tables]] per nested value."""
    lines = [
        f"{json.dumps(k, ensure_ascii=False)} = {toml_value(v)}" for k, v in data.items() if not _section(v)
    ]
    for key, value in data.items():
        if isinstance(value, dict) and _section(value):
            lines += [f"[{json.dumps(key, ensure_ascii=False)}]"] + [
                f"{json.dumps(k, ensure_ascii=False)} = {toml_value(v)}" for k, v in value.items()
            ]
        elif _section(value):
            for entry in value:
                lines += [f"[[{json.dumps(key, ensure_ascii=False)}]]"] + [
                    f"{json.dumps(k, ensure_ascii=False)} = {toml_value(v)}" for k, v in entry.items()
                ]
    return "\n".join(lines) + "\n"


def _section(value) -> bool:
    return isinstance(value, dict) or (
        isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)
    )


scalars = st.one_of(
    st.booleans(),
    st.integers(-(10**20), 10**20),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -1.0, 0.5, 1e6, 1e7, 1e308, -1e-300]),
    st.text(max_size=8),
    st.sampled_from(["xy", "xyz", "RR", "RP", "dh", "modified-dh", "differential", "car", "line", "bayle"]),
)
values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=6,
)


def _paths(data, prefix=()):
    yield prefix
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _paths(value, (*prefix, key))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _paths(value, (*prefix, i))


@st.composite
def mutated(draw, base: dict, plausible: bool = True) -> dict:
    """``base`` with one to three edits: a number changed within a plausible range (the file often stays
    valid), a value replaced by anything, a key added (often a misspelt one) or removed."""
    data = json.loads(json.dumps(base))
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from([p for p in _paths(data) if p]))
        parent = data
        for key in path[:-1]:
            parent = parent[key]
        actions = ["plausible"] * 3 * plausible + ["replace", "add", "remove"]
        action = draw(st.sampled_from(actions))
        if action == "plausible":
            if isinstance(parent[path[-1]], float) and not isinstance(parent[path[-1]], bool):
                parent[path[-1]] = draw(st.floats(-2.0, 2.0))
        elif action == "replace":
            parent[path[-1]] = draw(values)
        elif action == "add" and isinstance(parent, dict):
            name = draw(st.one_of(st.text(min_size=1, max_size=6), st.just(str(path[-1]) + "s")))
            parent[name] = draw(values)
        elif isinstance(parent, dict):
            del parent[path[-1]]
    return data


def _finite(value) -> bool:
    """No NaN (written as null inside arrays) or infinity anywhere in a JSON result."""
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    if isinstance(value, list):
        return all(v is not None and _finite(v) for v in value)
    return not isinstance(value, float) or math.isfinite(value)


def assert_contract(args: list[str], not_reached: bool = False) -> None:
    """Exit 0 with finite JSON, or exit 2 with one ``error:`` line; with ``not_reached`` also exit 3 with the
    report (saying it did not reach its goal) and a last ``warning:`` line."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            main(args)
            code = 0
        except SystemExit as exc:
            code = exc.code
    if code == 0:
        assert _finite(json.loads(out.getvalue())), args
    elif code == 3 and not_reached:
        assert json.loads(out.getvalue())["reached"] is False, args
        assert err.getvalue().strip().splitlines()[-1].startswith("warning: mobman "), (args, err.getvalue())
    else:
        lines = err.getvalue().strip().splitlines()
        assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), (args, code, err.getvalue())


number_text = st.one_of(
    st.floats(-4.0, 4.0).map(repr),
    st.sampled_from(
        ["pi", "-pi/2", "pi/2", "2*pi/3", "(1+2)/3", "1e308", "nan", "-inf", "", "1/0", "2**8", "q"]
    ),
    st.text(alphabet="0123456789.+-*/()pie_ ,;[]'x", max_size=12),
)


@FUZZ
@given(
    st.one_of(
        st.lists(
            st.floats(-4.0, 4.0).map(repr) | st.sampled_from(["pi", "-pi/2", "pi/2"]), min_size=5, max_size=5
        ),
        st.lists(number_text, min_size=0, max_size=7),
    ).map(",".join)
)
def test_configuration_values(text):
    assert_contract(["analyze", "bayle-planar", "--q", text, "--json"])


vector_text = st.one_of(
    st.lists(st.floats(-4.0, 4.0).map(repr), min_size=1, max_size=4).map(",".join),
    st.lists(number_text, min_size=0, max_size=5).map(",".join),
)


@st.composite
def one_option_changed(draw, valid: dict, changes: dict) -> list[str]:
    """Valid options ``valid`` with none or one of them changed (drawn from ``changes``), as arguments."""
    options = dict(valid)
    name = draw(st.sampled_from([None, *changes]))
    if name is not None:
        options[name] = draw(changes[name])
    return [word for key, value in options.items() if value is not None for word in (key, value)]


angles = st.floats(-4.0, 4.0).map(repr) | st.sampled_from(["pi", "-pi/2", "pi/2"])


@settings(FUZZ, max_examples=12)
@given(
    st.lists(angles, min_size=5, max_size=5)
    .map(",".join)
    .flatmap(
        lambda q: one_option_changed(
            {"--q": q, "--kind": "kinematic", "--eta": None},
            {
                "--q": vector_text,
                "--kind": st.sampled_from(["dynamic", "", "Kinematic", "ellipse"]),
                "--eta": vector_text,
            },
        )
    )
)
def test_ellipsoid_options(options):
    """bayle-planar has no dynamic model: ``--kind dynamic`` and ``--eta`` are errors (exit 2) too."""
    assert_contract(["ellipsoid", "bayle-planar", *options, "--json"])


@settings(FUZZ, max_examples=10)
@given(
    st.lists(st.floats(-3.0, 3.0).map(repr), min_size=3, max_size=3)
    .map(",".join)
    .flatmap(
        lambda target: one_option_changed(
            {"--target": target, "--start": "5,0,0,pi/6", "--harmonics": "2", "--extension": None},
            {
                "--extension": st.sampled_from(["x3, theta + x1", "q[100]", "x9", "", "theta +", "2, 3 +"]),
                "--target": vector_text,
                "--start": vector_text,
                "--harmonics": st.sampled_from(["1", "-1", "101", "two"]),
            },
        )
    )
)
@example(["--target", "0,0,1", "--start", "5,0,0,pi/6", "--extension", "x3, theta + x1"])
@example(["--target", "0,0,1", "--extension", "q[100]"])
@example(["--target", "0.5,-1,2", "--harmonics", "1", "--extension", "theta +"])
def test_plan_options(options):
    """Exit 3 (not converged within the 8 iterations) is the documented status of a plan that ends short."""
    args = ["plan", "tchon-car-rtr", *options, "--max-iterations", "8", "--json"]
    if "--extension" in options:
        args += ["--algorithm", "extended"]
    assert_contract(args, not_reached=True)


@settings(FUZZ, max_examples=40)
@given(mutated(ROBOT))
def test_robot_file_reader(data):
    """The reader alone (a new robot compiles new kernels, too slow for many command-line runs): a robot
    or a MobmanError."""
    try:
        robot = robot_file.parse(data)
    except MobmanError:
        return
    assert isinstance(robot, MobileManipulator)


@settings(FUZZ, max_examples=10)
@given(mutated(ROBOT, plausible=False))
def test_robot_files(data):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.toml"
        path.write_text(toml_document(data), encoding="utf-8")
        assert_contract(["analyze", str(path), "--json"])


@FUZZ
@given(
    st.one_of(
        st.binary(max_size=200), st.text(max_size=200).map(lambda t: t.encode("utf-8", "surrogatepass"))
    )
)
def test_arbitrary_bytes_as_robot_and_configuration_files(content):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.toml"
        path.write_bytes(content)
        assert_contract(["analyze", str(path), "--json"])
        assert_contract(["analyze", "bayle-planar", "--q-file", str(path), "--json"])


@settings(FUZZ, max_examples=8)
@given(mutated(SPEC))
def test_spec_files(data):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "spec.toml"
        path.write_text(toml_document(data), encoding="utf-8")
        assert_contract(["simulate", str(path), "--json"], not_reached=True)
