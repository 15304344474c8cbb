"""Reproduction of Tchoń, Jakubiak & Muszyński (2002) §4 (quick mode): the paper's claims on its output."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mobman.experiments import tchon2002
from mobman.planning.batch import plan_batch
from mobman.planning.endpoint import PlanningSetting, dexterity, endpoint

KEYS = {
    "start",
    "algorithm",
    "step",
    "converged",
    "iterations",
    "final_error",
    "lambda",
    "x",
    "dexterity_start",
    "dexterity_end",
    "error_history",
}


@pytest.fixture(scope="module")
def reproduction(tmp_path_factory):
    out = tmp_path_factory.mktemp("tchon2002")
    result = tchon2002.run(out, quick=True)
    result.write(out)
    return result, out


@pytest.fixture(scope="module")
def runs(reproduction):
    _, out = reproduction
    return json.loads((out / "results.json").read_text())


def test_results_json_schema(runs):
    assert isinstance(runs, list) and runs
    for r in runs:
        assert KEYS <= set(r)
        assert r["start"] in ("P", "Q", "R") and r["algorithm"] in ("pinv", "extended", "adjoint")
        assert r["step"] == "adaptive" or (isinstance(r["step"], float) and r["step"] > 0)
        assert isinstance(r["converged"], bool) and isinstance(r["iterations"], int)
        assert len(r["lambda"]) == 10 and len(r["x"]) == 3
        assert len(r["error_history"]) == r["iterations"] + 1
        assert r["error_history"][-1] == r["final_error"]
        assert r["converged"] == (r["final_error"] <= tchon2002.TOL)
    # every start appears with every algorithm run in quick mode
    pairs = {(r["algorithm"], r["step"]) for r in runs}
    assert {(r["start"], r["algorithm"], r["step"]) for r in runs} == {
        (s, a, st) for s in "PQR" for a, st in pairs
    }


def test_every_pseudo_inverse_run_reaches_the_tolerance(runs):
    pinv = [r for r in runs if r["algorithm"] == "pinv"]
    assert {r["start"] for r in pinv} == {"P", "Q", "R"}
    for r in pinv:
        assert r["converged"] and r["final_error"] <= 1e-12


def test_final_errors_recomputed_independently(runs):
    """The stored (λ, x) really solve the problem: the endpoint recomputed with RK4 on a much finer grid
    (a different integrator than the planner's) is within the tolerance for every pseudo-inverse run."""
    setting = tchon2002.setting()
    fine = PlanningSetting(setting.robot, setting.basis, setting.horizon, steps=4000, method="rk4")
    pinv = [r for r in runs if r["algorithm"] == "pinv"]
    z = np.stack([np.concatenate([r["lambda"], r["x"]]) for r in pinv])
    q0 = np.stack([tchon2002.start_pose(r["start"]) for r in pinv])
    err = np.linalg.norm(np.asarray(endpoint(fine, z, q0)) - tchon2002.TARGET, axis=-1)
    assert np.all(err < 2e-12)


def test_dexterity_positive_at_visited_regular_configurations(runs):
    """d = √det 𝒟 > 0 at the start and at every converged end point, and it equals eq. (12) recomputed
    here."""
    setting = tchon2002.setting().jacobian_setting
    z0 = tchon2002.initial_configuration()
    for r in runs:
        q0 = tchon2002.start_pose(r["start"])
        assert r["dexterity_start"] == pytest.approx(dexterity(setting, z0, q0), rel=1e-12)
        assert r["dexterity_start"] > 0
        if r["converged"]:
            assert r["dexterity_end"] > 0


def test_start_pose_is_polar():
    q = tchon2002.start_pose("R")
    assert q == pytest.approx(
        [5 * math.cos(5 * math.pi / 4), 5 * math.sin(5 * math.pi / 4), 0.0, math.pi / 6]
    )


def test_figures_and_report_exist(reproduction):
    result, out = reproduction
    names = {p.name.split("_")[0] for p in result.figures}
    assert names == {f"fig{k}" for k in range(2, 8)}
    for path in result.figures:
        assert path.exists() and path.stat().st_size > 5000
    report = (out / "report.md").read_text()
    assert "conclusion" in report.lower() and "Every pseudo-inverse run reaches" in report


def test_batch_success_rate(reproduction):
    """plan_batch on the reproduction's compiled kernel: all pinv problems solved, no Δθ = 0.1 adjoint one."""
    setting = tchon2002.setting()
    z0 = tchon2002.initial_configuration()
    q0 = np.stack([tchon2002.start_pose(n) for n in tchon2002.STARTS])
    solved = plan_batch(
        setting, z0, q0, tchon2002.TARGET, tchon2002.options("pinv", 1.0, tchon2002.QUICK_CAP)
    )
    assert solved.success_rate == 1.0 and np.all(solved.final_errors <= tchon2002.TOL)
    slow = plan_batch(
        setting, z0, q0, tchon2002.TARGET, tchon2002.options("adjoint", 0.1, tchon2002.QUICK_CAP)
    )
    assert slow.success_rate == 0.0 and slow.status == ["max_iterations"] * 3
    assert np.all(slow.final_errors > 1e-3)
