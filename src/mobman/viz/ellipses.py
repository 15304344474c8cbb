"""Manipulability ellipses along a path.

For a 2 × k Jacobian J (planar rows of an arm Jacobian J_a, of the reduced Jacobian J̄ or of the normalised
J̄_N), the image of the unit ball {J u : ‖u‖ ≤ 1} is the ellipse with semi-axes σ1 ≥ σ2 along the left
singular vectors u1, u2 of J = U Σ Vᵀ (Yoshikawa; Nait-Chabane eq. 15–16): its boundary is
U diag(σ) (cos t, sin t). A singular J gives a flat ellipse (a segment).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from mobman.errors import InputError
from mobman.viz.paths import figure_of, finish_plane


def ellipse_outline(jacobian: npt.ArrayLike, scale: float = 1.0, n: int = 73) -> np.ndarray:
    """Boundary points (..., n, 2) of the velocity ellipses of 2 × k Jacobians (..., 2, k), batched.

    ``scale`` multiplies the semi-axes (a drawing scale: metres of figure per unit of velocity).
    """
    j = np.asarray(jacobian, dtype=float)
    if j.ndim < 2 or j.shape[-2] != 2:
        raise InputError(f"ellipse_outline: jacobian must have shape (..., 2, k), got {j.shape}")
    u, s, _ = np.linalg.svd(j, full_matrices=False)
    sigma = np.zeros(j.shape[:-2] + (2,))
    sigma[..., : s.shape[-1]] = s[..., :2]
    t = np.linspace(0.0, 2.0 * np.pi, n)
    circle = np.stack([np.cos(t), np.sin(t)], axis=-1)  # (n, 2)
    if u.shape[-1] < 2:  # k = 1: complete the basis (the second axis has length 0 anyway)
        u = np.concatenate([u, np.stack([-u[..., 1, :], u[..., 0, :]], axis=-2)], axis=-1)
    return scale * np.einsum("...ij,...j,nj->...ni", u[..., :2], sigma, circle)


def plot_ellipses(
    centers: npt.ArrayLike,
    jacobians: npt.ArrayLike,
    scale: float = 1.0,
    path: npt.ArrayLike | None = None,
    labels: str = "ellipse",
    title: str | None = None,
    ax: Axes | None = None,
    color: str = "tab:purple",
) -> Figure:
    """Draw the ellipses of ``jacobians`` (N, 2, k) centred at ``centers`` (N, 2), over an optional path (M, 2).
    Returns a new Figure, or the figure holding ``ax`` when one is given."""
    centers = np.asarray(centers, dtype=float)
    outlines = ellipse_outline(jacobians, scale) + centers[:, None, :]
    fig = Figure(figsize=(6.4, 5.2)) if ax is None else figure_of(ax)
    ax = fig.add_subplot(1, 1, 1) if ax is None else ax
    if path is not None:
        path = np.asarray(path)
        ax.plot(path[:, 0], path[:, 1], color="tab:green", lw=1, label="end-effector path")
    for k, outline in enumerate(outlines):
        ax.plot(outline[:, 0], outline[:, 1], color=color, lw=1, label=labels if k == 0 else None)
        ax.plot(*centers[k], ".", color=color)
    finish_plane(ax, title)
    return fig
