"""mobman.control.metrics: graining points, the first significant value, the velocity and wheel-speed
ratios and the law's flags of a summary (the rest of the summary of a run: tests/test_control_simulation.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mobman import InputError
from mobman.control import metrics
from mobman.control.simulation import SimulationResult
from mobman.model import robots


def test_graining_points():
    v = np.array([0.0, 0.2, 0.1, 0.0005, -0.0005, 0.05, -0.1, -0.2, 0.0, 0.3])
    assert metrics.graining_points(v, threshold=1e-3) == 2
    assert metrics.graining_points(v, threshold=0.0) == 4
    assert metrics.first_significant(-v, 1e-3) == pytest.approx(-0.2)
    with pytest.raises(InputError):
        metrics.graining_points(np.zeros((2, 2)))


def _run(robot, eta, info):
    """A made-up run of ``robot`` with the quasi-velocities ``eta`` and the law's entries ``info``."""
    n = len(eta)
    return SimulationResult(
        t=np.arange(n) * 0.1,
        q=np.zeros((n, robot.n_q)),
        eta=eta,
        xi=np.zeros((n, 2)),
        xi_star=np.zeros((n, 2)),
        error=np.zeros((n, 2)),
        measures={},
        saturated=np.zeros(n, bool),
        damped=np.zeros(n, bool),
        info=info,
    )


def test_velocity_and_wheel_speed_ratios_and_the_law_s_flags():
    robot = robots.korayem_planar()  # wheels r = 0.1 m, half track 0.25 m, 3.5 rad/s; arm 3.5 rad/s
    rng = np.random.default_rng(3)
    eta = rng.uniform(-1.0, 1.0, (9, robot.n_eta)) * [0.4, 1.5, 3.0, 4.0]
    flags = np.array([1, 0, 1, 1, 0, 0, 0, 1, 0], bool)
    run = _run(robot, eta, {"joint_limited": flags, "residual": np.full(9, 1e-9)})
    summary = metrics.summarize(run, robot)
    right, left = (eta[:, 0] + 0.25 * eta[:, 1]) / 0.1, (eta[:, 0] - 0.25 * eta[:, 1]) / 0.1
    assert summary["wheel_speed_ratio"] == pytest.approx(np.abs([right, left]).max() / 3.5, rel=1e-12)
    limits = [0.1 * 3.5, 2 * 0.1 * 3.5 / 0.5, 3.5, 3.5]  # v and ω at the corners of the wheels' diamond
    assert summary["velocity_limit_ratio"] == pytest.approx(np.max(np.abs(eta) / limits), rel=1e-12)
    assert summary["joint_limited_steps"] == 4 and "residual_steps" not in summary
    # fed in two pieces, the same numbers
    pieces = metrics.RunningSummary(robot)
    for part in (slice(0, 4), slice(4, 9)):
        piece = _run(robot, eta[part], {"joint_limited": flags[part]})
        pieces.add(replace(piece, t=run.t[part]))
    streamed = pieces.metrics()
    for key in ("wheel_speed_ratio", "velocity_limit_ratio", "joint_limited_steps"):
        assert streamed[key] == pytest.approx(summary[key], rel=1e-14)


def test_without_limits_the_ratios_are_none():
    robot = robots.tchon_car_rtr()  # no velocity limits, no wheel limits
    summary = metrics.summarize(_run(robot, np.ones((3, robot.n_eta)), {}), robot)
    assert summary["velocity_limit_ratio"] is None and summary["wheel_speed_ratio"] is None
