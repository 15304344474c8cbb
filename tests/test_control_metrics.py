"""mobman.control.metrics: graining points and the first significant value (the summary of a run:
tests/test_control_simulation.py)."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import InputError
from mobman.control import metrics


def test_graining_points():
    v = np.array([0.0, 0.2, 0.1, 0.0005, -0.0005, 0.05, -0.1, -0.2, 0.0, 0.3])
    assert metrics.graining_points(v, threshold=1e-3) == 2
    assert metrics.graining_points(v, threshold=0.0) == 4
    assert metrics.first_significant(-v, 1e-3) == pytest.approx(-0.2)
    with pytest.raises(InputError):
        metrics.graining_points(np.zeros((2, 2)))
