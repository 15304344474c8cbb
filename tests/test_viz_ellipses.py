"""mobman.viz.ellipses: the drawn ellipses are the images of the unit ball under the Jacobian."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import viz
from mobman.errors import InputError


def test_ellipse_outline_satisfies_ellipse_equation():
    rng = np.random.default_rng(0)
    j = rng.normal(size=(4, 2, 3))
    pts = viz.ellipse_outline(j, scale=1.0)
    assert pts.shape == (4, 73, 2)
    m = np.linalg.inv(j @ np.swapaxes(j, -1, -2))  # boundary of {J u : |u| ≤ 1}: pᵀ (J Jᵀ)⁻¹ p = 1
    np.testing.assert_allclose(np.einsum("kni,kij,knj->kn", pts, m, pts), 1.0, rtol=1e-12)


def test_ellipse_axes_and_singular_jacobian():
    pts = viz.ellipse_outline(np.array([[2.0, 0.0], [0.0, 0.5]]), scale=0.1)
    assert np.max(np.abs(pts[:, 0])) == pytest.approx(0.2)
    assert np.max(np.abs(pts[:, 1])) == pytest.approx(0.05)
    flat = viz.ellipse_outline(np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0]]))  # rank 1: a segment along (1, 2)
    assert np.all(np.isfinite(flat))
    np.testing.assert_allclose(flat[:, 0] * 2.0 - flat[:, 1], 0.0, atol=1e-12)
    with pytest.raises(InputError, match="shape"):
        viz.ellipse_outline(np.ones((3, 3)))
