"""Reachability maps (:mod:`mobman.studies.maps`) seen from above and from the side.

Each panel shows, for every column of cells across the view, the best score among its reached cells (the
highest value of the measure along the line of sight); columns with no reached cell are left blank.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from matplotlib.figure import Figure

from mobman.errors import InputError


def best_along(score: np.ndarray, reached: np.ndarray, axis: int) -> np.ndarray:
    """The best score of the reached cells along ``axis`` (NaN where none is reached)."""
    masked = np.where(reached, score, -np.inf)
    best = masked.max(axis=axis)
    return np.where(np.isfinite(best), best, np.nan)


def plot_reachability(
    axes: tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike],
    score: npt.ArrayLike,
    reached: npt.ArrayLike,
    measure: str = "score",
    title: str | None = None,
) -> Figure:
    """Top view (x–y, best over z) and, when the map has several z layers, side view (x–z, best over y) of a
    reachability map: cell centres ``axes`` (x, y, z), ``score`` and ``reached`` of shape
    (len(x), len(y), len(z))."""
    x, y, z = (np.asarray(a, dtype=float) for a in axes)
    score, reached = np.asarray(score, dtype=float), np.asarray(reached, dtype=bool)
    shape = (x.size, y.size, z.size)
    if score.shape != shape or reached.shape != shape:
        raise InputError(f"plot_reachability: score and reached must have shape {shape}, got {score.shape}")
    views = [("x", "y", x, y, best_along(score, reached, 2))]
    if z.size > 1:
        views.append(("x", "z", x, z, best_along(score, reached, 1)))
    fig = Figure(figsize=(5.2 * len(views), 4.6), layout="constrained")
    finite = [v[4][np.isfinite(v[4])] for v in views]
    values = np.concatenate(finite) if finite else np.array([])
    top = float(values.max()) if values.size else 1.0
    for k, (a, b, u, v, image) in enumerate(views):
        ax = fig.add_subplot(1, len(views), k + 1)
        mesh = ax.pcolormesh(
            _edges(u), _edges(v), image.T, shading="flat", cmap="viridis", vmin=0.0, vmax=top or 1.0
        )
        ax.plot([0.0], [0.0], marker="+", color="black", markersize=10, label="platform reference point")
        ax.set_aspect("equal")
        ax.set_xlabel(f"{a} (m)")
        ax.set_ylabel(f"{b} (m)")
        ax.set_title(f"{'top' if b == 'y' else 'side'} view: best {measure} along {'z' if b == 'y' else 'y'}")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=7)
        fig.colorbar(mesh, ax=ax, shrink=0.85, label=measure)
    if title:
        fig.suptitle(title)
    return fig


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around evenly spaced centres (a single centre gets a cell 0.1 m wide)."""
    step = float(centres[1] - centres[0]) if centres.size > 1 else 0.1
    return np.concatenate([centres - step / 2, centres[-1:] + step / 2])


__all__ = ["best_along", "plot_reachability"]
