"""mobman.dynamics.inertia: invalid inertial data names the field."""

from __future__ import annotations

import math

import pytest

import mobman
from mobman import dynamics as dyn
from mobman.model import robots

from dynamics_model import MODEL, WHEEL


@pytest.mark.parametrize(
    "build, field",
    [
        (lambda: dyn.PlatformBody(-1.0, 1.0), "mass"),
        (lambda: dyn.PlatformBody(1.0, math.nan), "inertia_z"),
        (lambda: dyn.Wheel(1.0, -0.1, 0.1), "I_w"),
        (lambda: dyn.Payload(1.0, (1, 2, 0, 0, 1, 0, 0, 0, 1)), "symmetric"),
        (lambda: dyn.Payload(1.0, (1.0, -1.0, 1.0)), "positive semi-definite"),
        (lambda: dyn.DynamicModel(robots.bayle_planar(), dyn.PlatformBody(1.0, 1.0), WHEEL), "inertial"),
        (lambda: dyn.DynamicModel(robots.yamamoto_dual_arm(), dyn.PlatformBody(1.0, 1.0), None), "wheel"),
        (lambda: dyn.DynamicModel(MODEL.robot, MODEL.body, WHEEL, dyn.Payload(1.0, arm=3)), "payload.arm"),
    ],
)
def test_invalid_inertial_data_names_the_field(build, field):
    with pytest.raises(mobman.ModelError, match=field):
        build()
