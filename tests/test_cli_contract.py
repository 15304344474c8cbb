"""The command line's contract: no code from input, hostile files and output folders refused with one line and
exit 2 (nothing touched), exit codes 1 / 3 / 130, budgets checked before work."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from cli_runs import run_cli as run
from subprocesses import DUMP_ON_USR1, communicate_or_dump

ROOT = Path(__file__).resolve().parents[1]
ROBOT_FILE = (ROOT / "docs" / "examples" / "planar_robot.toml").read_text()

SPEC = """
duration = 0.4
dt = 0.02
q0 = [0.0, 0.0, 0.0, -0.785, 1.57]
[robot]
name = "bayle-planar"
[task]
kind = "position"
components = "xy"
[reference]
kind = "line"
start = [0.707, 0.0]
end = [0.907, 0.1]
duration = 0.4
[law]
kind = "bayle"
[gains]
W = 2.0
"""


def escape_payload(marker: Path) -> str:
    """Python text that, evaluated even without builtins, runs a shell command creating ``marker``."""
    return (
        "[c for c in ().__class__.__base__.__subclasses__() if c.__name__ == '_wrap_close'][0]"
        f".__init__.__globals__['system']('touch {marker}')"
    )


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


# --- no code from input -------------------------------------------------------------------------------------


def test_escape_payload_as_an_option_value_runs_nothing(tmp_path, capsys):
    marker = tmp_path / "marker"
    for payload in (escape_payload(marker), "().__class__.__base__.__subclasses__()"):
        code, _, err = run(["analyze", "bayle-planar", "--q", f"0,0,0,0.3,{payload}"], capsys)
        assert code == 2 and one_line(err).startswith("error: --q:")
    assert not marker.exists()


def test_escape_payload_in_a_spec_file_runs_nothing(tmp_path, capsys):
    marker = tmp_path / "marker"
    for payload in ("().__class__.__base__.__subclasses__()", escape_payload(marker)):
        spec = tmp_path / "spec.toml"
        spec.write_text(SPEC.replace("q0 = [0.0, 0.0, 0.0, -0.785, 1.57]", f'q0 = "0, 0, 0, 0, {payload}"'))
        code, _, err = run(["simulate", str(spec)], capsys)
        assert code == 2 and "q0:" in one_line(err)
    assert not marker.exists()


# --- hostile files --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("content", "needles"),
    [
        (b"\x00\x01\x02binary", ("binary content",)),
        ('name = "caf\xe9"'.encode("latin-1"), ("not UTF-8",)),
        (("x = " + "[" * 3000 + "]" * 3000).encode(), ("nested deeper",)),
        (ROBOT_FILE.replace('kinds = "RR"', "kinds = 5").encode(), ("arms[0].kinds", "string")),
        (ROBOT_FILE.replace('kinds = "RR"', 'kinds = "RX"').encode(), ("arms[0].kinds", "R (revolute)")),
        (
            ROBOT_FILE.replace('kinds = "RR"', 'limits = [["-1", "1"], [-1, 1]]').encode(),
            ("arms[0].limits", "numbers"),
        ),
        (ROBOT_FILE.replace("[0.0, 0.0, 0.5, 0.0], [", "[0.0, 0.0, 1e308, 0.0], [").encode(), ("1e+06",)),
        (ROBOT_FILE.replace("half_track", "half_trak").encode(), ("did you mean 'half_track'",)),
        (
            ROBOT_FILE.replace("wheel_radius = 0.1", 'wheel_radius = "big"').encode(),
            ("platform.wheel_radius",),
        ),
        (ROBOT_FILE.replace('convention = "dh"', "convention = [1]").encode(), ("arms[0].convention",)),
        (ROBOT_FILE.replace('kind = "differential"', 'kind = "diferential"').encode(), ("'differential'",)),
    ],
)
def test_hostile_robot_files_are_one_line_naming_file_and_key(tmp_path, capsys, content, needles):
    path = tmp_path / "robot.toml"
    path.write_bytes(content)
    code, _, err = run(["analyze", str(path)], capsys)
    line = one_line(err)
    assert code == 2 and line.startswith(f"error: {path}:"), line
    assert all(n in line for n in needles), line


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        ("[gains]", "[gians]", ("spec.gians", "did you mean 'gains'")),
        ("W = 2.0", "W = 2.0\nk = [[[[[[[[[1]]]]]]]]]", ("nested deeper",)),
        ('kind = "line"', "kind = 5", ("reference.kind",)),
        ('kind = "bayle"', 'kind = ["bayle"]', ("law.kind",)),
        ("duration = 0.4\ndt", "duration = 1e300\ndt", ("duration", "1e+06")),
        ('components = "xy"', "components = 7", ("task",)),
    ],
)
def test_hostile_spec_files_are_one_line_naming_file_and_key(tmp_path, capsys, old, new, needles):
    path = tmp_path / "spec.toml"
    assert old in SPEC
    path.write_text(SPEC.replace(old, new, 1))
    code, _, err = run(["simulate", str(path)], capsys)
    line = one_line(err)
    assert code == 2 and line.startswith(f"error: {path}:"), line
    assert all(n in line for n in needles), line


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        (b"\x00\xff\xfe\x00", "binary content"),
        (b"0,0,0,0.3,\xe9", "not UTF-8"),
        (b"x,y,theta,q4,q5\n0,0,,0.3,1", "row 1"),
    ],
)
def test_hostile_configuration_files(tmp_path, capsys, content, needle):
    path = tmp_path / "q.csv"
    path.write_bytes(content)
    code, _, err = run(["analyze", "bayle-planar", "--q-file", str(path)], capsys)
    assert code == 2 and needle in one_line(err) and "--q-file" in err


# --- output folders -------------------------------------------------------------------------------------------


def _refused(tmp_path, capsys, out: Path, needle: str) -> None:
    before = snapshot(tmp_path)
    code, _, err = run(["simulate", str(tmp_path / "spec.toml"), "--out", str(out)], capsys)
    assert code == 2 and needle in one_line(err), err
    assert snapshot(tmp_path) == before
    assert not [p for p in tmp_path.rglob(".*") if p.name.endswith(".partial")]


def test_out_onto_a_file_a_foreign_folder_or_an_unwritable_place_touches_nothing(tmp_path, capsys):
    (tmp_path / "spec.toml").write_text(SPEC)
    (tmp_path / "results.json").write_text("precious")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("precious too")
    _refused(tmp_path, capsys, tmp_path / "results.json", "not a folder")
    _refused(tmp_path, capsys, tmp_path / "results.json" / "sub", "not a folder")
    _refused(tmp_path, capsys, tmp_path / "mine", "not empty")
    _refused(tmp_path, capsys, Path("/proc/mobman-results"), "cannot write")


def test_out_of_another_command_is_refused_and_the_same_command_replaces_it(tmp_path, capsys):
    (tmp_path / "spec.toml").write_text(SPEC)
    out = tmp_path / "run"
    assert run(["simulate", str(tmp_path / "spec.toml"), "--out", str(out)], capsys)[0] == 0
    first = snapshot(out)
    assert {"results.json", "paths.png", "timeseries.png"} <= set(first)
    code, _, err = run(["plan", "tchon-car-rtr", "--target", "0,0,1", "--out", str(out)], capsys)
    assert code == 2 and "results of mobman simulate" in one_line(err)
    assert snapshot(out) == first
    (tmp_path / "spec.toml").write_text(SPEC.replace("W = 2.0", "W = 3.0"))
    assert run(["simulate", str(tmp_path / "spec.toml"), "--out", str(out)], capsys)[0] == 0
    assert snapshot(out)["results.json"] != first["results.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run", "spec.toml"]  # no staging left behind


# --- exit codes -----------------------------------------------------------------------------------------------


def test_interrupt_exits_130_with_one_line_and_removes_partial_output(tmp_path, capsys, monkeypatch):
    (tmp_path / "spec.toml").write_text(SPEC)
    out = tmp_path / "run"

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("mobman.cli.simulate.save_figure", interrupted)
    code, _, err = run(["simulate", str(tmp_path / "spec.toml"), "--out", str(out)], capsys)
    assert code == 130 and one_line(err).startswith("interrupted: mobman simulate")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]


def test_unexpected_failure_exits_1_with_one_line_asking_for_a_report(tmp_path, capsys, monkeypatch):
    (tmp_path / "spec.toml").write_text(SPEC)

    def broken(*args, **kwargs):
        raise RuntimeError("something\nunforeseen")

    monkeypatch.setattr("mobman.control.spec.Spec.simulate", broken)
    code, _, err = run(["simulate", str(tmp_path / "spec.toml")], capsys)
    line = one_line(err)
    assert code == 1 and "mobman simulate" in line and "please report" in line and "unforeseen" in line


def test_plan_not_converged_exits_3_with_its_results_written(tmp_path, capsys):
    out = tmp_path / "plan"
    args = [
        "plan",
        "tchon-car-rtr",
        "--target",
        "0,0,1",
        "--max-iterations",
        "1",
        "--json",
        "--out",
        str(out),
    ]
    code, stdout, err = run(args, capsys)
    assert code == 3 and "max_iterations" in one_line(err) and one_line(err).startswith("warning:")
    assert json.loads(stdout)["converged"] is False
    assert (out / "paths.png").stat().st_size > 0 and (out / "convergence.png").stat().st_size > 0


@pytest.mark.parametrize("steps", [10**8, 10**12])
def test_huge_runs_are_refused_before_any_work(tmp_path, capsys, steps):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.replace("duration = 0.4\ndt = 0.02", f"duration = 1000.0\ndt = {1000.0 / steps!r}"))
    code, _, err = run(["simulate", str(path)], capsys)
    line = one_line(err)
    assert code == 2 and "--max-steps" in line and f"{steps + 1:.3g} steps" in line
    if (
        steps == 10**12
    ):  # computed in pieces (memory holds one), but its files: about 260 TB, more than any disk
        out = tmp_path / "run"
        code, _, err = run(["simulate", str(path), "--max-steps", str(10 * steps), "--out", str(out)], capsys)
        assert code == 2 and "free there" in one_line(err) and not out.exists()


SLOW_WRITER = (
    DUMP_ON_USR1
    + """
import sys, time
import mobman.cli.simulate as command
from mobman.cli import main

def stalled(*args, **kwargs):
    print("writing", flush=True)  # results.json of the new run is written, the figures are not
    time.sleep(120)

command.save_figure = stalled
main(sys.argv[1:])
"""
)


def test_a_run_interrupted_while_writing_its_folder_leaves_the_old_results(tmp_path):
    """A real SIGINT in the middle of writing (SIGKILL of a file write: tests/test_io_output.py)."""
    from mobman.io.output import MARKER

    (tmp_path / "spec.toml").write_text(SPEC)
    out = tmp_path / "run"
    out.mkdir()
    for name, text in ((MARKER, "simulate\n"), ("results.json", "old"), ("paths.png", "old figure")):
        (out / name).write_text(text)
    before = snapshot(out)
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    args = [sys.executable, "-c", SLOW_WRITER, "simulate", str(tmp_path / "spec.toml"), "--out", str(out)]
    process = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "writing"
    process.send_signal(signal.SIGINT)
    _, err = communicate_or_dump(process)
    assert snapshot(out) == before
    assert process.returncode == 130 and one_line(err).startswith("interrupted: mobman simulate")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run", "spec.toml"]


RUNNING = (
    DUMP_ON_USR1
    + """
import atexit, sys
import mobman.control.simulation as simulation
from mobman.cli import main

compiled, steps = simulation._run, []

def counted(*args):
    out = compiled(*args)
    steps.append(args[3])  # the steps of this compiled call
    if len(steps) == 1:
        print("running", flush=True)
    return out

simulation._run = counted
atexit.register(lambda: print("computed", sum(steps), flush=True))
main(sys.argv[1:])
"""
)


def test_ctrl_c_stops_a_long_simulation_within_seconds(tmp_path):
    """A real SIGINT during a QP simulation of minutes (100,001 steps, computed in calls of a second at most)
    ends it within seconds, with exit 130 and one line, leaving no results folder: the steps computed by
    then are a few calls' worth, not the whole run."""
    import time

    out = tmp_path / "run"
    target = ["manus-platform", "--target", "0.5,0.2,0.4", "--duration", "100", "--dt", "0.001"]
    args = [sys.executable, "-c", RUNNING, "simulate", *target, "--out", str(out)]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    process = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "running"
    sent = time.monotonic()
    process.send_signal(signal.SIGINT)
    stdout, err = communicate_or_dump(process, timeout=30.0)
    assert process.returncode == 130 and one_line(err).startswith("interrupted: mobman simulate")
    assert time.monotonic() - sent < 10.0 and not out.exists()
    assert int(stdout.split()[-1]) < 10_000


def test_every_exit_status_is_documented_in_the_readme():
    from mobman.cli.app import EXIT_CODES

    readme = (ROOT / "README.md").read_text()
    assert all(f"\n| {code} | " in readme for code in EXIT_CODES)


def test_reproduce_replaces_a_paper_folder_only_when_complete(tmp_path, capsys, monkeypatch):
    from types import SimpleNamespace

    from mobman.experiments.report import Reproduction

    def paper(figure: str, interrupt: bool):
        def run(out, quick=False):
            (out / "figure.png").write_text(figure)
            if interrupt:
                raise KeyboardInterrupt
            return Reproduction("tchon2002", "title", {"figure": figure}, "report")

        return lambda name: SimpleNamespace(run=run)

    out = tmp_path / "results"
    monkeypatch.setattr("mobman.cli.reproduce.module", paper("old", interrupt=False))
    assert run(["reproduce", "tchon2002", "--out", str(out)], capsys)[0] == 0
    before = snapshot(out)
    assert before["tchon2002/figure.png"] == b"old" and json.loads(before["tchon2002/results.json"]) == {
        "figure": "old"
    }
    monkeypatch.setattr("mobman.cli.reproduce.module", paper("new", interrupt=True))
    code, _, err = run(["reproduce", "tchon2002", "--out", str(out)], capsys)
    assert code == 130 and one_line(err).startswith("interrupted: mobman reproduce")
    assert snapshot(out) == before and sorted(p.name for p in out.iterdir()) == [
        ".mobman-results",
        "tchon2002",
    ]
    monkeypatch.setattr("mobman.cli.reproduce.module", paper("new", interrupt=False))
    assert run(["reproduce", "tchon2002", "--out", str(out)], capsys)[0] == 0
    assert snapshot(out)["tchon2002/figure.png"] == b"new"


EXTRA_OF = {
    "--store": "studies",  # a Zarr store
    "--scheduler": "studies",  # a Dask cluster
    "mobman view": "viewer",
    "tiago": "robots",
    "stretch": "robots",
    "export-mjcf": "physics",
}
"""What a README command line needs, by a word it holds, and the extra that installs it."""


def test_the_readme_first_command_installs_every_extra_its_command_lines_need():
    readme = (ROOT / "README.md").read_text()
    first = readme.split("```bash\n", 1)[1].splitlines()[0]
    installed = set(first.split('pip install -e ".[', 1)[1].split("]", 1)[0].split(","))
    commands = readme.split("## Command line\n\n```bash\n", 1)[1].split("```", 1)[0].splitlines()
    needed = {extra for line in commands for word, extra in EXTRA_OF.items() if word in line.split("#")[0]}
    assert {"studies", "viewer", "robots"} <= needed  # the lines this test is about are still there
    assert needed <= installed, f"the first command lacks {sorted(needed - installed)}"
