"""Figures of planned motions (Tchoń et al. figs. 2–7): matplotlib figures without pyplot's state, as in
:mod:`mobman.viz`."""

from __future__ import annotations

from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
import numpy.typing as npt
from matplotlib.figure import Figure

from mobman.io.output import save_figure
from mobman.planning.endpoint import PlanningSetting, trajectory


def plot_paths(
    setting: PlanningSetting,
    z: npt.ArrayLike,
    q0: npt.ArrayLike,
    y_d: Sequence[float] | np.ndarray,
    title: str,
    path: Path,
) -> Path:
    """Platform path (q1, q2) and end-effector path (y1, y2) in the plane for the configuration z (figs.
    2–4)."""
    _, q_p, y = trajectory(setting, z, q0)
    fig = Figure(figsize=(5.5, 5))
    ax = fig.subplots()
    ax.plot(q_p[:, 0], q_p[:, 1], "-", color="tab:blue", label="platform (q1, q2)")
    ax.plot(y[:, 0], y[:, 1], "--", color="tab:red", label="end effector (y1, y2)")
    ax.plot(q_p[0, 0], q_p[0, 1], "o", color="tab:blue", label="platform start")
    ax.plot(y[0, 0], y[0, 1], "s", color="tab:red", mfc="none", label="end effector start")
    ax.plot(y_d[0], y_d[1], "*", color="k", ms=12, label="target y_d")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def plot_convergence(
    histories: Mapping[str, Sequence[float] | np.ndarray], tol: float, title: str, path: Path
) -> Path:
    """log10 ‖e‖ versus iteration, one line per labelled run (figs. 5–7)."""
    fig = Figure(figsize=(6.5, 4))
    ax = fig.subplots()
    for label, history in histories.items():
        errors = np.asarray(history, float)
        ax.plot(np.arange(errors.size), np.log10(np.maximum(errors, 1e-300)), label=label, lw=1.2)
    ax.axhline(np.log10(tol), color="k", ls=":", lw=1, label=f"tolerance {tol:g}")
    ax.set_xscale("symlog", linthresh=10)
    ax.set_xlim(left=0)
    ax.set_xlabel("iteration")
    ax.set_ylabel("log10 ‖K − y_d‖")
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def _save(fig: Figure, path: Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    return path
