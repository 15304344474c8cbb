"""mobman.viz.timeseries: one panel per series, and a clear error for a bad shape."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import viz
from mobman.errors import InputError


def test_plot_timeseries_panels_and_bad_shape():
    t = np.linspace(0.0, 1.0, 11)
    fig = viz.plot_timeseries(
        t,
        {"w": {"w_a5": t, "w5": t**2}, "v (m/s)": {"v": np.sin(t)}},
        hlines={"w": [0.9]},
        events={"graining": [0.5]},
    )
    assert len(fig.axes) == 2
    np.testing.assert_allclose(fig.axes[0].lines[1].get_ydata(), t**2)
    with pytest.raises(InputError, match="w_a5"):
        viz.plot_timeseries(t, {"w": {"w_a5": t[:5]}})
