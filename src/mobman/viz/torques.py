"""Required actuator torques along a motion against their torque–speed envelopes (load capacity), predicted
and run on physics."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure

from mobman.viz.timeseries import plot_timeseries

if TYPE_CHECKING:
    from mobman.dynamics.load_capacity import LoadCapacity


def plot_torques(capacity: LoadCapacity, title: str | None = None) -> Figure:
    """Required torques at m = 0 and at the maximum load against the envelopes of the limited actuators,
    the limiting time marked."""
    mass = capacity.max_load if capacity.bounded else 0.0
    at_load = capacity.torques(mass)
    panels = {}
    for i, name in enumerate(capacity.names):
        if not np.all(np.isfinite(capacity.upper[:, i])) and not np.all(np.isfinite(capacity.lower[:, i])):
            continue
        panels[f"{name} (N·m)"] = {
            f"τ, m = {mass:.3f} kg": at_load[:, i],
            "τ, m = 0": capacity.tau0[:, i],
            "T⁺": capacity.upper[:, i],
            "T⁻": capacity.lower[:, i],
        }
    limit = capacity.limiting_time
    events = (
        {f"limit: {capacity.limiting_actuator}": [limit]} if capacity.bounded and limit is not None else None
    )
    return plot_timeseries(capacity.t, panels, title=title, events=events)


def plot_load_runs(runs: Sequence[Any], actuator: str, title: str | None = None) -> Figure:
    """One panel per run on physics (``runs``: :class:`mobman.physics.load.LoadRun`, a higher layer than the
    figures): the torque of ``actuator`` the servo asked
    for and the one applied, against its envelope at the measured speed."""
    i = runs[0].names.index(actuator)
    panels = {
        f"{actuator}, m = {run.mass:.3f} kg (N·m)": {
            "τ asked": run.required[:, i],
            "τ applied": run.applied[:, i],
            "T⁺": run.upper[:, i],
            "T⁻": run.lower[:, i],
        }
        for run in runs
    }
    return plot_timeseries(runs[0].t, panels, title=title)
