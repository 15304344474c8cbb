"""mobman.control.references: the reference paths' derivatives against finite differences, their timings and
geometry, and their errors."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ModelError
from mobman.control import references


def fd(fn, t, h=1e-6):
    return (fn(t + h) - fn(t - h)) / (2 * h)


@pytest.mark.parametrize(
    "ref",
    [
        references.Line((0.0, 1.0), (2.0, -1.0), 3.0, "linear"),
        references.Line((0.0, 1.0, 0.5), (2.0, -1.0, 0.0), 3.0, "cubic"),
        references.Line((0.0,), (2.0,), 3.0, "quintic"),
        references.Ellipse((1.0, 0.5), (1.0, 0.4), 7.0, phase=0.3, rotation=0.4, angle=0.2),
        references.Polyline([(0, 0), (1, 0), (1, 2)], (1.0, 2.0), "quintic"),
        references.FunctionReference(lambda t: jnp.stack([jnp.sin(t), t**2])),
        references.stack(references.Line((0.0,), (1.0,), 2.0), references.Ellipse((0, 0), (1, 2), 5.0)),
    ],
)
def test_reference_derivative_matches_finite_differences(ref):
    t = np.array([0.37, 1.1, 2.45])
    xi, xi_dot = ref(t)
    assert xi.shape == xi_dot.shape == (3, ref.dim)
    assert np.allclose(xi_dot, fd(lambda tt: np.asarray(ref(tt)[0]), t), atol=1e-7)


def test_line_timings():
    line = references.Line((1.0, 0.0), (3.0, 2.0), 4.0)
    _, v = line(np.linspace(0.0, 4.0, 9))
    assert np.allclose(v, 0.5)  # constant speed
    xi, v = line(np.array([-1.0, 5.0]))
    assert np.allclose(xi, [[1, 0], [3, 2]]) and np.allclose(v, 0.0)  # holds outside [0, T]
    for timing in ("cubic", "quintic"):
        xi, v = map(np.asarray, references.Line((1.0,), (3.0,), 4.0, timing)(np.array([0.0, 2.0, 4.0])))
        assert np.allclose(xi[:, 0], [1, 2, 3]) and np.allclose(v[[0, 2]], 0.0)
    polyline = references.Polyline([(0, 0), (1, 0), (1, 2)], (1.0, 2.0))
    xi, v = polyline(np.array([0.0, 1.0, 3.0]))
    assert np.allclose(xi, [[0, 0], [1, 0], [1, 2]]) and np.allclose(v, 0.0)


def test_ellipse_geometry():
    ell = references.Ellipse((1.0, 2.0, 0.3), (2.0, 0.5), 8.0, rotation=np.pi / 2)
    xi = np.asarray(ell(np.linspace(0.0, 8.0, 50))[0])
    local = xi[:, :2] - [1.0, 2.0]
    # rotated by 90°: x-extent is the minor axis, y-extent the major one
    assert np.allclose((local[:, 1] / 2.0) ** 2 + (local[:, 0] / 0.5) ** 2, 1.0)
    assert np.allclose(xi[:, 2], 0.3)


@pytest.mark.parametrize(
    "bad",
    [
        lambda: references.Line((0, 0), (1,), 1.0),
        lambda: references.Line((0,), (1,), -1.0),
        lambda: references.Line((0,), (1,), 1.0, "septic"),
        lambda: references.Ellipse((0, 0), (1, -1), 1.0),
        lambda: references.Polyline([(0, 0)], ()),
    ],
)
def test_reference_errors(bad):
    with pytest.raises(ModelError):
        bad()


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda t: references.Ellipse((0.0, 0.0), (1.0, 0.5), period=t), "period"),
        (lambda t: references.Line((0.0, 0.0), (1.0, 0.0), duration=t), "duration"),
        (
            lambda t: references.Polyline(((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)), durations=(1.0, t)),
            "durations",
        ),
    ],
)
def test_a_reference_faster_than_a_millisecond_is_refused_naming_its_field(make, field):
    """A period or duration of 1e-300 s asked for velocities of 1e300 (and below float64's range, infinite)."""
    for t in (1e-300, 1e-4):
        with pytest.raises(ModelError, match=f"{field} must be at least 0.001 s"):
            make(t)
    velocity = make(1e-3)(0.0)[1]  # the shortest accepted: finite
    assert np.all(np.isfinite(np.asarray(velocity)))
