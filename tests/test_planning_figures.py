"""The planned-motion figures of mobman.planning.figures: plot_paths draws the platform and end-effector paths
of a configuration (checked against a straight drive in closed form) and plot_convergence one log10 error
line per run with the tolerance; both write a PNG, creating the folder."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest

from mobman.model.robots import tchon_car_rtr
from mobman.planning import figures
from mobman.planning.basis import Fourier
from mobman.planning.endpoint import PlanningSetting

PNG = b"\x89PNG\r\n\x1a\n"
L2, L3 = 0.6, 0.4
STEPS = 10


@pytest.fixture
def drawn(monkeypatch):
    """The figures passed to the saving function, in order (they stay readable after being closed)."""
    seen = []
    real = figures.save_figure

    def keep(fig, path, **kwargs):
        seen.append(fig)
        return real(fig, path, **kwargs)

    monkeypatch.setattr(figures, "save_figure", keep)
    return seen


@pytest.fixture(scope="module")
def straight():
    """Car + RTR arm with constant controls (one Fourier term): u1 = V, u2 = 0 drives straight along x."""
    return PlanningSetting(
        tchon_car_rtr(l2=L2, l3=L3), Fourier(0), horizon=1.0, steps=STEPS, jacobian_steps=STEPS
    )


def _lines(fig):
    (ax,) = fig.axes
    return {line.get_label(): line for line in ax.get_lines()}


def test_backend_is_agg():
    assert matplotlib.get_backend().lower() == "agg"


def test_plot_paths_draws_the_platform_and_end_effector_paths(straight, drawn, tmp_path):
    speed, x1, x2, x3 = 0.8, 0.3, 0.5, 0.2
    z = np.array([speed, 0.0, x1, x2, x3])
    q0 = np.array([1.0, -2.0, 0.0, 0.0])
    path = figures.plot_paths(
        straight, z, q0, (0.5, -1.5, 0.0), "straight drive", tmp_path / "figs" / "paths.png"
    )
    assert path == tmp_path / "figs" / "paths.png"
    assert path.read_bytes()[:8] == PNG

    (fig,) = drawn
    assert fig.axes[0].get_title() == "straight drive"
    lines = _lines(fig)
    t = np.linspace(0.0, 1.0, STEPS + 1)
    platform_x, platform_y = 1.0 + speed * t, np.full_like(t, -2.0)
    platform = lines["platform (q1, q2)"]
    np.testing.assert_allclose(platform.get_xdata(), platform_x, atol=1e-12)
    np.testing.assert_allclose(platform.get_ydata(), platform_y, atol=1e-12)
    # the RTR arm on the rear axle: horizontal reach l2 + l3 cos x3 at heading θ + x1 = x1
    reach = L2 + L3 * math.cos(x3)
    tool = lines["end effector (y1, y2)"]
    np.testing.assert_allclose(tool.get_xdata(), platform_x + reach * math.cos(x1), atol=1e-12)
    np.testing.assert_allclose(tool.get_ydata(), platform_y + reach * math.sin(x1), atol=1e-12)
    assert tool.get_linestyle() == "--"

    np.testing.assert_allclose(lines["platform start"].get_xydata(), [[1.0, -2.0]], atol=1e-12)
    start = [[1.0 + reach * math.cos(x1), -2.0 + reach * math.sin(x1)]]
    np.testing.assert_allclose(lines["end effector start"].get_xydata(), start, atol=1e-12)
    np.testing.assert_array_equal(lines["target y_d"].get_xydata(), [[0.5, -1.5]])
    assert lines["target y_d"].get_marker() == "*"


def test_plot_convergence_draws_log10_of_each_history(drawn, tmp_path):
    histories = {
        "pinv, step 1": [1.0, 1e-2, 1e-5, 1e-13],
        "adjoint, step 0.1": np.array([2.0, 1.5, 1.0, 0.5, 0.25, 0.125]),
    }
    path = figures.plot_convergence(histories, 1e-12, "convergence", tmp_path / "out" / "convergence.png")
    assert path.read_bytes()[:8] == PNG

    (fig,) = drawn
    ax = fig.axes[0]
    assert ax.get_title() == "convergence" and ax.get_xlabel() == "iteration"
    assert ax.get_xscale() == "symlog"
    lines = _lines(fig)
    pinv = lines["pinv, step 1"]
    np.testing.assert_array_equal(pinv.get_xdata(), [0, 1, 2, 3])
    np.testing.assert_allclose(pinv.get_ydata(), [0.0, -2.0, -5.0, -13.0], atol=1e-12)
    adjoint = lines["adjoint, step 0.1"]
    np.testing.assert_array_equal(adjoint.get_xdata(), np.arange(6))
    np.testing.assert_allclose(
        adjoint.get_ydata(), np.log2([2.0, 1.5, 1.0, 0.5, 0.25, 0.125]) / math.log2(10)
    )
    tolerance = lines["tolerance 1e-12"]
    np.testing.assert_allclose(tolerance.get_ydata(), [-12.0, -12.0], atol=1e-12)
    assert [label for label in lines] == ["pinv, step 1", "adjoint, step 0.1", "tolerance 1e-12"]


def test_plot_convergence_keeps_an_exact_zero_error_finite(drawn, tmp_path):
    figures.plot_convergence({"exact": [1.0, 0.0]}, 1e-10, "zero", tmp_path / "zero.png")
    ydata = _lines(drawn[0])["exact"].get_ydata()
    assert np.all(np.isfinite(ydata))
    assert ydata[0] == 0.0 and ydata[1] <= -300.0


def test_the_figures_are_closed_after_saving(straight, tmp_path):
    import matplotlib.pyplot as plt

    before = len(plt.get_fignums())
    figures.plot_convergence({"run": [1.0, 0.1]}, 1e-3, "closed", tmp_path / "c.png")
    figures.plot_paths(straight, np.zeros(5), np.zeros(4), (0.0, 0.0), "closed", tmp_path / "p.png")
    assert len(plt.get_fignums()) == before
