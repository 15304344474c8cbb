"""mobman.planning.basis: the control bases are orthonormal, and the Fourier basis is the series of Tchoń,
Jakubiak & Muszyński (2002)."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman.planning.basis import Fourier, PiecewiseConstant


@pytest.mark.parametrize("basis", [Fourier(3), PiecewiseConstant(4)])
def test_basis_is_orthonormal(basis):
    horizon, n = 2.5, 4000
    t = (np.arange(n) + 0.5) * horizon / n
    phi = np.asarray(jax.vmap(lambda s: basis.values(s, horizon))(jnp.asarray(t)))
    gram = phi.T @ phi * horizon / n
    np.testing.assert_allclose(gram, np.eye(basis.size), atol=1e-9)


def test_fourier_matches_paper_series():
    t = 0.3
    lam = np.array([0.5, -1.0, 2.0, 0.25, 3.0])
    paper = lam[0] + math.sqrt(2) * (
        lam[1] * math.sin(2 * math.pi * t)
        + lam[2] * math.cos(2 * math.pi * t)
        + lam[3] * math.sin(4 * math.pi * t)
        + lam[4] * math.cos(4 * math.pi * t)
    )
    assert float(Fourier(2).values(jnp.asarray(t), 1.0) @ lam) == pytest.approx(paper, rel=1e-14)
