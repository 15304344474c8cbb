"""mobman.model.visual: a shape fixed in a robot frame, its sizes per kind, its checks, and visuals kept out of
the kinematics (two robots that differ only in their looks are equal and share compiled functions)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.spatial import IDENTITY
from mobman.model.visual import Visual


def test_values_are_normalised_to_floats():
    shift = np.eye(4)
    shift[:3, 3] = (0.1, 0.0, 0.2)
    box = Visual("box", tuple(shift.ravel()), (1, 2, 3), rgba=(0, 0.5, 1, 1), name="shell")
    assert box.size == (1.0, 2.0, 3.0) and all(isinstance(v, float) for v in box.size)
    assert box.origin == tuple(float(v) for v in shift.ravel())
    assert box.rgba == (0.0, 0.5, 1.0, 1.0)
    assert Visual("sphere", size=(0.2,)).origin == IDENTITY


@pytest.mark.parametrize(
    ("kwargs", "phrase"),
    [
        ({"kind": "cone", "size": (1.0,)}, "kind must be one of box, cylinder, sphere, mesh"),
        ({"kind": "box", "size": (1.0, 2.0)}, "a box needs 3 positive size values"),
        ({"kind": "cylinder", "size": (0.1, -1.0)}, "a cylinder needs 2 positive size values"),
        ({"kind": "sphere", "size": (float("nan"),)}, "a sphere needs 1 positive size values"),
        ({"kind": "mesh"}, "a mesh needs a filename"),
        ({"kind": "sphere", "size": (1.0,), "origin": (0.0,) * 15}, "origin must be a finite 4 × 4"),
        ({"kind": "sphere", "size": (1.0,), "origin": (float("inf"),) * 16}, "origin must be a finite 4 × 4"),
        ({"kind": "sphere", "size": (1.0,), "rgba": (1.0, 0.0, 0.0)}, "rgba must be 4 numbers in [0, 1]"),
        (
            {"kind": "sphere", "size": (1.0,), "rgba": (1.5, 0.0, 0.0, 1.0)},
            "rgba must be 4 numbers in [0, 1]",
        ),
    ],
)
def test_bad_shapes_are_model_errors_naming_the_visual(kwargs, phrase):
    with pytest.raises(ModelError, match="Visual 'part'") as info:
        Visual(name="part", **kwargs)
    assert phrase in str(info.value) and "\n" not in str(info.value)


def test_visuals_stay_out_of_equality_and_hashing():
    robot = robots.bayle_planar()
    drawn = dataclasses.replace(robot, platform_visuals=(Visual("box", size=(1, 1, 1)),))
    assert drawn.platform_visuals != robot.platform_visuals
    assert drawn == robot and hash(drawn) == hash(robot)
