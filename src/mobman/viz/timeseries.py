"""Measures, coordinates and velocities versus time, one panel per group."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import numpy.typing as npt
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from mobman.errors import InputError


def plot_timeseries(
    t: npt.ArrayLike,
    panels: Mapping[str, Mapping[str, np.ndarray]],
    hlines: Mapping[str, Sequence[float] | np.ndarray] | None = None,
    title: str | None = None,
    events: Mapping[str, Sequence[float] | np.ndarray] | None = None,
) -> Figure:
    """Stacked panels sharing the time axis.

    t: times (N,). panels: panel y-label → {curve label → values (N,)}. hlines: panel y-label → levels
    drawn dashed (e.g. the 0.9 threshold of w_a5). events: label → times marked by vertical lines on every
    panel (e.g. the platform's graining points).
    """
    fig = Figure(figsize=(6.4, 1.2 + 1.9 * len(panels)))
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for k, (ax, (ylabel, curves)) in enumerate(zip(axes, panels.items())):
        draw_curves(
            ax,
            t,
            curves,
            (hlines or {}).get(ylabel, ()),
            events if k == 0 else None,
            (events or {}) if k else None,
        )
        ax.set_ylabel(ylabel)
    axes[-1].set_xlabel("t (s)")
    if title:
        axes[0].set_title(title)
    fig.tight_layout()
    return fig


def draw_curves(
    ax: Axes,
    t: npt.ArrayLike,
    curves: Mapping[str, np.ndarray],
    hlines: Sequence[float] | np.ndarray = (),
    events: Mapping[str, Sequence[float] | np.ndarray] | None = None,
    unlabelled_events: Mapping[str, Sequence[float] | np.ndarray] | None = None,
) -> None:
    """Curves (label → values (N,)) against t on one axes, dashed horizontal levels, and event times as
    labelled vertical lines (``unlabelled_events``: the same lines without legend entries)."""
    t = np.asarray(t, dtype=float)
    for label, values in curves.items():
        values = np.asarray(values, dtype=float)
        if values.shape != t.shape:
            raise InputError(f"plot_timeseries: curve {label!r} has shape {values.shape}, time has {t.shape}")
        ax.plot(t, values, lw=1.3, label=label)
    for level in hlines:
        ax.axhline(level, color="k", ls="--", lw=0.8)
    for labelled, group in ((True, events), (False, unlabelled_events)):
        for k, (name, times) in enumerate((group or {}).items()):
            for j, te in enumerate(times):
                ax.axvline(te, color=f"C{k + 3}", ls=":", lw=1, label=name if labelled and j == 0 else None)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
