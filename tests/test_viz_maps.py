"""mobman.viz.maps: the best score along a line of sight, and the map's views."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.errors import InputError
from mobman.viz.maps import best_along, plot_reachability


def test_the_best_score_along_an_axis_skips_cells_not_reached():
    score = np.array([[[0.1, 0.9], [0.5, 0.2]], [[np.nan, np.nan], [0.3, 0.8]]])
    reached = np.array([[[True, False], [True, True]], [[False, False], [True, True]]])
    np.testing.assert_array_equal(best_along(score, reached, 2), [[0.1, 0.5], [np.nan, 0.8]])


def test_a_spatial_map_has_a_top_and_a_side_view_and_a_planar_one_a_top_view():
    axes = (np.linspace(0, 1, 3), np.linspace(0, 1, 4), np.linspace(0, 1, 2))
    score = np.random.default_rng(0).uniform(size=(3, 4, 2))
    reached = score > 0.3
    fig = plot_reachability(axes, score, reached, "yoshikawa", "title")
    images = [ax for ax in fig.axes if ax.collections and ax.get_label() != "<colorbar>"]
    assert [ax.get_xlabel() + ax.get_ylabel() for ax in images] == ["x (m)y (m)", "x (m)z (m)"]
    top = images[0].collections[0].get_array().reshape(4, 3)
    np.testing.assert_array_equal(np.ma.filled(top, np.nan), best_along(score, reached, 2).T)
    flat = plot_reachability((axes[0], axes[1], axes[2][:1]), score[:, :, :1], reached[:, :, :1])
    assert len([ax for ax in flat.axes if ax.get_label() != "<colorbar>"]) == 1


def test_arrays_of_another_shape_are_refused():
    axes = (np.zeros(2), np.zeros(3), np.zeros(1))
    with pytest.raises(InputError, match="score and reached must have shape"):
        plot_reachability(axes, np.zeros((2, 3)), np.zeros((2, 3), bool))
