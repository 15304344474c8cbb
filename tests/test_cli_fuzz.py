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

import pytest
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


def _run(args: list[str]) -> tuple[object, io.StringIO, io.StringIO]:
    """``mobman ARGS`` in this process: its exit status, standard output and standard error."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            main(args)
            code: object = 0
        except SystemExit as exc:
            code = exc.code
    return code, out, err


def assert_contract(args: list[str], not_reached: bool = False) -> None:
    """Exit 0 with finite JSON, or exit 2 with one ``error:`` line; with ``not_reached`` also exit 3 with the
    report (saying it did not reach its goal) and a last ``warning:`` line."""
    code, out, err = _run(args)
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


def _exit_2_in_one_line(args: list[str]) -> str:
    """Run ``mobman ARGS``: exit 2 with one ``error:`` line, which it returns."""
    code, _, err = _run(args)
    lines = err.getvalue().strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), (args, code, err.getvalue())
    return lines[0]


URDF_LIES = {
    "velocity NaN": ('velocity="1" effort="10"', 'velocity="nan" effort="10"'),
    "velocity < 0": ('velocity="1" effort="10"', 'velocity="-1" effort="10"'),
    "effort < 0": ('velocity="1" effort="10"', 'velocity="1" effort="-10"'),
    "mass < 0": ('<link name="tool"/>', '<link name="tool"><inertial><mass value="-1"/></inertial></link>'),
    "link twice": ('<link name="tool"/>', '<link name="tool"/><link name="tool"/>'),
    "joint twice": ('joint name="wrist"', 'joint name="lift"'),
    "origin NaN": ('<origin xyz="0.3 0 0"/>', '<origin xyz="nan 0 0"/>'),
    "truncated": ("</robot>", ""),
    "cycle": (
        '<parent link="base_link"/><child link="lift_link"/>',
        '<parent link="tool"/><child link="lift_link"/>',
    ),
    "mesh /etc/passwd": (
        '<link name="tool"/>',
        '<link name="tool"><visual><geometry><mesh filename="file:///etc/passwd"/></geometry></visual></link>',
    ),
    "mesh outside": (
        '<link name="tool"/>',
        '<link name="tool"><visual><geometry><mesh filename="../outside.stl"/></geometry></visual></link>',
    ),
}


def test_urdf_files_that_lie_exit_2_in_one_line_naming_the_file(tmp_path):
    """Each lie of a small URDF robot (read as it is: exit 0) is exit 2 with one line naming the file; a joint
    cycle ends too (no walk through the tree runs forever), for ``analyze`` and ``sweep``."""
    from urdf_samples import husky

    (tmp_path / "outside.stl").write_bytes(b"solid x\nendsolid x\n")
    folder = tmp_path / "robot"
    folder.mkdir()
    good = husky(folder)
    options = ["--tip", "tool", "--base", "base_link", "--platform", "omnidirectional"]
    assert_contract(["analyze", str(good), *options, "--json"])
    for lie, (old, new) in URDF_LIES.items():
        text = good.read_text()
        assert old in text, lie
        path = folder / "lying.urdf"
        path.write_text(text.replace(old, new, 1))
        commands = [["analyze", str(path), *options, "--json"]]
        if lie == "cycle":
            commands.append(["sweep", str(path), *options, "--vary", "mount.x=0,0.1", "--samples", "10"])
        for args in commands:
            assert f"error: {path}: " in _exit_2_in_one_line(args), (lie, args)


def test_a_damaged_urdf_is_one_line_on_standard_error_and_not_yourdfpy_s(tmp_path):
    """yourdfpy's parser logs what it repairs: in a real process (no test's log capture), standard error is
    mobman's one line only."""
    import subprocess
    import sys

    from urdf_samples import husky

    path = husky(tmp_path)
    path.write_text(path.read_text()[:-40])
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from mobman.cli import main; main(sys.argv[1:])",
            "analyze",
            str(path),
        ]
        + ["--tip", "tool", "--base", "base_link"],
        capture_output=True,
        text=True,
        timeout=120,
        env={**__import__("os").environ, "MOBMAN_CACHE_DIR": "off"},
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"error: {path}: not well-formed XML ({done.stderr.split('XML (', 1)[1].split('): ')[0]}): a truncated or "
        "damaged file"
    ]


def _edit_map(store: Path, edit: str) -> None:
    """One field of a map's store changed, in its Zarr attributes or arrays."""
    import zarr

    group = zarr.open_group(str(store), mode="r+")
    meta = dict(group.attrs["mobman"])
    definition = meta["definition"]
    if edit == "no bounds":
        del definition["bounds"]
    elif edit == "step 0":
        definition["step"] = 0
    elif edit == "step 1e-7":
        definition["step"] = 1e-7
    elif edit == "arm 99":
        definition["arm"] = 99
    elif edit == "measure 5":
        definition["measure"] = 5
    elif edit == "score resized":
        del group["score"]
        group.create_array("score", shape=(7,), chunks=(7,), dtype="float64", fill_value=0.0)
    elif edit == "rows":
        meta["rows"] = "many"
    elif edit == "done missing":
        del group["done"]
    group.attrs["mobman"] = meta


def test_a_map_store_is_checked_against_its_own_definition(tmp_path):
    """``place --map STORE``: each field of a good store edited is exit 2 with one line naming the field."""
    import shutil

    good = tmp_path / "good.zarr"
    small = ["--starts", "1", "--iterations", "5"]
    assert_contract(
        ["map", "bayle-planar", "--step", "0.4", *small, "--store", str(good), "--quiet", "--json"]
    )
    place = [
        "place",
        "bayle-planar",
        "--target",
        "0.3,-0.4,0",
        "--headings",
        "2",
        "--iterations",
        "5",
        "--json",
    ]
    place.append("--map")
    assert_contract([*place, str(good)])  # the store as written: exit 0
    fields = {
        "no bounds": "bounds",
        "step 0": "step",
        "step 1e-7": "step",
        "arm 99": "arm",
        "measure 5": "measure",
        "score resized": "score",
        "rows": "rows",
        "done missing": "done",
    }
    for edit, field in fields.items():
        store = tmp_path / f"{edit.replace(' ', '_')}.zarr"
        shutil.copytree(good, store)
        _edit_map(store, edit)
        line = _exit_2_in_one_line([*place, str(store)])
        assert field in line and "--map" in line, (edit, line)


REFUSED_BEFORE_WORK = {
    # too big to serve
    "map --step": (["map", "bayle-planar", "--step", "1e-9"], "--step 1e-09 m makes"),
    "map --iterations": (["map", "bayle-planar", "--iterations", "1000000000"], "--iterations must be"),
    "map --starts": (["map", "bayle-planar", "--starts", "1000000000"], "--starts 1,000,000,000: "),
    "place --iterations": (
        ["place", "bayle-planar", "--target", "0.5,0.5,0", "--iterations", "1000000000"],
        "from 1 to 10,000, got 1,000,000,000",
    ),
    "place --starts": (
        ["place", "bayle-planar", "--target", "0.5,0.5,0", "--starts", "100000000"],
        "--starts",
    ),
    "place --headings": (
        ["place", "bayle-planar", "--target", "0.5,0.5,0", "--headings", "1000000000"],
        "--headings 1,000,000,000: with radii 8, bearings 16, starts 4",
    ),
    "place --bearings": (
        ["place", "bayle-planar", "--target", "0.5,0.5,0", "--bearings", "100000000"],
        "--bearings 100,000,000: ",
    ),
    "sweep --samples": (
        ["sweep", "bayle-planar", "--vary", "l1=0.4,0.5", "--samples", "1000000000"],
        "--samples 1,000,000,000: ",
    ),
    "sweep --step": (
        ["sweep", "bayle-planar", "--vary", "l1=0.4,0.5", "--bounds", "0,1,0,1,0,0", "--step", "1e-7"],
        "more than 10,000,000",
    ),
    # out of range
    "map --seed": (["map", "bayle-planar", "--seed", "-1"], "--seed must be an integer ≥ 0"),
    "sweep --seed": (["sweep", "bayle-planar", "--vary", "l1=0.4,0.5", "--seed", "-1"], "--seed must be"),
    "map --scheduler http": (["map", "bayle-planar", "--scheduler", "http://host:8786"], "--scheduler must"),
    "map --scheduler tcp://:": (["map", "bayle-planar", "--scheduler", "tcp://:"], "--scheduler must"),
    "place --tolerance": (
        ["place", "bayle-planar", "--target", "0.5,0.5,0", "--tolerance", "1e300"],
        "--tolerance must be a number > 0 and ≤ 0.1",
    ),
}


def test_requests_too_big_or_out_of_range_are_refused_before_any_work(monkeypatch):
    """Each is exit 2 with one line naming the option, the request and the limit, before the solver runs
    (today's machine could not hold them, or they would run for days)."""
    from mobman.studies import maps, placement, reaching

    monkeypatch.setattr(reaching, "_solve", lambda *_, **__: pytest.fail("solved before refusing"))
    monkeypatch.setattr(placement, "reach", lambda *_, **__: pytest.fail("solved before refusing"))
    monkeypatch.setattr(maps, "reach", lambda *_, **__: pytest.fail("solved before refusing"))
    for case, (args, needle) in REFUSED_BEFORE_WORK.items():
        line = _exit_2_in_one_line([*args, "--json"] if args[0] == "place" else [*args, "--quiet"])
        assert needle in line, (case, line)


def test_a_figure_that_cannot_be_written_is_refused_before_the_map_is_computed(tmp_path, monkeypatch):
    from mobman.cli import maps

    monkeypatch.setattr(maps, "reachability_map", lambda *_, **__: pytest.fail("mapped before refusing"))
    (tmp_path / "file").write_text("")
    for figure, needle in ((tmp_path / "file" / "map.png", "does not exist"), (tmp_path, "must name a .png")):
        line = _exit_2_in_one_line(["map", "bayle-planar", "--figure", str(figure)])
        assert line.startswith("error: --figure") and needle in line, line
