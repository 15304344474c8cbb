"""The load-capacity torque figure of mobman.viz.torques.plot_torques: one panel per limited actuator with the
required torques at m = 0 and at the maximum load and the envelopes T⁺, T⁻, the limiting time marked;
checked on a load capacity built from hand-made torques (τ = τ0 + m τ1) whose maximum load is known in
closed form."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.dynamics.actuators import DCMotor, TorqueBox
from mobman.dynamics.load_capacity import capacity_from_torques
from mobman.viz.torques import plot_torques

T = np.array([0.0, 0.5, 1.0])
NAMES = ("lift", "wrist", "free")
TAU0 = np.array([[2.0, 0.0, 1.0], [2.0, 0.0, 1.0], [2.0, 0.0, 1.0]])
TAU1 = np.array([[1.0, -0.5, 3.0], [2.0, 0.0, 3.0], [4.0, 0.5, 3.0]])
SPEED = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [1.0, 4.0, 0.0]])
# lift |τ| ≤ 10: bounds (10 − 2)/τ1 = 8, 4, 2 → 2 kg at t = 1; wrist DC motor T_s = 5, ω_nl = 10:
# T⁺ = 5 − ω/2 = 5, 4, 3 and T⁻ = −5 − ω/2 = −5, −6, −7 → bounds 5/0.5 = 10, none, 3/0.5 = 6; free: unlimited
ACTUATORS = {"lift": TorqueBox.symmetric(10.0), "wrist": DCMotor(5.0, 10.0), "free": None}
MAX_LOAD = 2.0


@pytest.fixture(scope="module")
def capacity():
    result = capacity_from_torques(NAMES, T, TAU0, TAU1, SPEED, ACTUATORS)
    assert result.max_load == pytest.approx(MAX_LOAD, rel=1e-12)
    assert result.limiting_actuator == "lift" and result.limiting_time == 1.0
    return result


def _curves(ax):
    return {line.get_label(): line for line in ax.get_lines() if not line.get_label().startswith("_")}


def test_one_panel_per_limited_actuator(capacity):
    fig = plot_torques(capacity, title="load capacity")
    assert [ax.get_ylabel() for ax in fig.axes] == ["lift (N·m)", "wrist (N·m)"]  # "free" has no envelope
    assert fig.axes[0].get_title() == "load capacity"
    assert fig.axes[-1].get_xlabel() == "t (s)"


def test_the_torque_curves_are_those_at_zero_and_at_the_maximum_load(capacity):
    fig = plot_torques(capacity)
    expected = {
        "lift (N·m)": ([4.0, 6.0, 10.0], [2.0, 2.0, 2.0]),  # τ0 + 2 τ1, τ0
        "wrist (N·m)": ([-1.0, 0.0, 1.0], [0.0, 0.0, 0.0]),
    }
    for ax in fig.axes:
        curves = _curves(ax)
        at_load, at_zero = expected[ax.get_ylabel()]
        np.testing.assert_allclose(curves["τ, m = 2.000 kg"].get_xdata(), T)
        np.testing.assert_allclose(curves["τ, m = 2.000 kg"].get_ydata(), at_load, atol=1e-12)
        np.testing.assert_allclose(curves["τ, m = 0"].get_ydata(), at_zero, atol=1e-12)


def test_the_envelope_lines_follow_the_actuator_speeds(capacity):
    fig = plot_torques(capacity)
    lift, wrist = (_curves(ax) for ax in fig.axes)
    np.testing.assert_allclose(lift["T⁺"].get_ydata(), [10.0, 10.0, 10.0])
    np.testing.assert_allclose(lift["T⁻"].get_ydata(), [-10.0, -10.0, -10.0])
    np.testing.assert_allclose(wrist["T⁺"].get_ydata(), [5.0, 4.0, 3.0], atol=1e-12)
    np.testing.assert_allclose(wrist["T⁻"].get_ydata(), [-5.0, -6.0, -7.0], atol=1e-12)
    np.testing.assert_allclose(wrist["T⁺"].get_ydata(), capacity.upper[:, 1])


def test_the_limiting_time_is_marked_on_every_panel(capacity):
    fig = plot_torques(capacity)
    first = _curves(fig.axes[0])["limit: lift"]
    np.testing.assert_allclose(first.get_xdata(), [1.0, 1.0])
    second = [line for line in fig.axes[1].get_lines() if list(line.get_xdata()) == [1.0, 1.0]]
    assert len(second) == 1 and second[0].get_label().startswith("_")  # marked, without a second legend entry


def test_an_unbounded_load_draws_the_torques_without_a_load_and_no_limit():
    tau1 = np.zeros_like(TAU1)
    capacity = capacity_from_torques(NAMES, T, TAU0, tau1, SPEED, ACTUATORS)
    assert not capacity.bounded
    fig = plot_torques(capacity)
    for ax in fig.axes:
        curves = _curves(ax)
        assert "τ, m = 0.000 kg" in curves
        assert not any(label.startswith("limit") for label in curves)
        assert len(ax.get_lines()) == 4
    np.testing.assert_allclose(_curves(fig.axes[0])["τ, m = 0.000 kg"].get_ydata(), [2.0, 2.0, 2.0])


def test_the_figure_saves_as_png(capacity, tmp_path):
    path = tmp_path / "torques.png"
    plot_torques(capacity).savefig(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
