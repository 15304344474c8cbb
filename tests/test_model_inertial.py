"""mobman.model.inertial: PlatformBody, Wheel and Payload — stored values, validation (ModelError naming the
class and the field) and Payload.scaled against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman.errors import ModelError
from mobman.model.inertial import Payload, PlatformBody, Wheel


def test_platform_body_stores_floats_and_defaults_the_com_to_the_origin():
    body = PlatformBody(30, 2)
    assert body == PlatformBody(30.0, 2.0, (0.0, 0.0, 0.0))
    assert type(body.mass) is float and type(body.inertia_z) is float
    assert PlatformBody(1.0, 0.0, np.array([0.1, -0.2, 0.3])).com == (0.1, -0.2, 0.3)
    assert hash(body) == hash(PlatformBody(30.0, 2.0))


@pytest.mark.parametrize(
    "kwargs, field, allowed",
    [
        ({"mass": 0.0, "inertia_z": 1.0}, "mass", "> 0"),
        ({"mass": -1.0, "inertia_z": 1.0}, "mass", "> 0"),
        ({"mass": math.nan, "inertia_z": 1.0}, "mass", "finite"),
        ({"mass": "heavy", "inertia_z": 1.0}, "mass", "a number"),
        ({"mass": True, "inertia_z": 1.0}, "mass", "a number"),
        ({"mass": 1.0, "inertia_z": -0.1}, "inertia_z", "≥ 0"),
        ({"mass": 1.0, "inertia_z": math.inf}, "inertia_z", "finite"),
        ({"mass": 1.0, "inertia_z": 0.0, "com": (0.0, 0.0)}, "com", "3 numbers"),
        ({"mass": 1.0, "inertia_z": 0.0, "com": (0.0, math.nan, 0.0)}, "com\\[1\\]", "finite"),
    ],
)
def test_platform_body_rejects_bad_values(kwargs, field, allowed):
    with pytest.raises(ModelError, match=f"^PlatformBody: {field} must be .*{allowed}"):
        PlatformBody(**kwargs)


def test_wheel_allows_zero_values():
    wheel = Wheel(0, 0, 0)
    assert (wheel.mass, wheel.I_w, wheel.I_m) == (0.0, 0.0, 0.0)
    assert Wheel(0.5, 0.01, 0.005) == Wheel(mass=0.5, I_w=0.01, I_m=0.005)


@pytest.mark.parametrize("field", ["mass", "I_w", "I_m"])
@pytest.mark.parametrize("value, allowed", [(-1e-9, "≥ 0"), (math.nan, "finite"), (None, "a number")])
def test_wheel_rejects_bad_values(field, value, allowed):
    kwargs = {"mass": 1.0, "I_w": 0.1, "I_m": 0.1, field: value}
    with pytest.raises(ModelError, match=f"^Wheel: {field} must be .*{allowed}"):
        Wheel(**kwargs)


def test_payload_reads_a_diagonal_or_a_full_inertia():
    diagonal = Payload(2.0, (0.1, 0.2, 0.3), (0.0, 0.0, 0.05))
    assert diagonal.inertia == (0.1, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.3)
    full = Payload(2.0, np.array([[0.1, 0.01, 0.0], [0.01, 0.2, 0.0], [0.0, 0.0, 0.3]]))
    assert full.inertia == (0.1, 0.01, 0.0, 0.01, 0.2, 0.0, 0.0, 0.0, 0.3)
    assert full.com == (0.0, 0.0, 0.0) and full.arm == 0
    assert Payload(0.0).inertia == (0.0,) * 9
    assert Payload(1.0, arm=np.int64(1)).arm == 1 and type(Payload(1.0, arm=np.int64(1)).arm) is int


@pytest.mark.parametrize(
    "kwargs, field, allowed",
    [
        ({"mass": -0.5}, "mass", "≥ 0"),
        ({"mass": math.inf}, "mass", "finite"),
        ({"mass": 1.0, "inertia": (1.0, 2.0)}, "inertia", "9 finite numbers"),
        ({"mass": 1.0, "inertia": (0.1, 0.0, math.nan)}, "inertia", "9 finite numbers"),
        ({"mass": 1.0, "inertia": (1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)}, "inertia", "symmetric"),
        ({"mass": 1.0, "inertia": (1.0, -1.0, 1.0)}, "inertia", "positive semi-definite"),
        ({"mass": 1.0, "inertia": "abc"}, "inertia", "9 numbers"),
        ({"mass": 1.0, "com": (1.0, 2.0, 3.0, 4.0)}, "com", "3 numbers"),
        ({"mass": 1.0, "arm": -1}, "arm", "arm index ≥ 0"),
        ({"mass": 1.0, "arm": 1.5}, "arm", "arm index ≥ 0"),
    ],
)
def test_payload_rejects_bad_values(kwargs, field, allowed):
    with pytest.raises(ModelError, match=f"^Payload: {field} must be .*{allowed}"):
        Payload(**kwargs)


def test_payload_scaled_keeps_the_inertia_per_kilogram():
    load = Payload(2.0, (0.4, 0.1, 0.0, 0.1, 0.6, 0.0, 0.0, 0.0, 0.8), (0.0, 0.1, 0.2), arm=1)
    heavier = load.scaled(5.0)
    assert heavier.mass == 5.0
    np.testing.assert_allclose(heavier.inertia, (1.0, 0.25, 0.0, 0.25, 1.5, 0.0, 0.0, 0.0, 2.0), rtol=1e-15)
    assert heavier.com == load.com and heavier.arm == 1
    assert load.scaled(2.0) == load
    unloaded = load.scaled(0.0)
    assert unloaded.mass == 0.0 and unloaded.inertia == (0.0,) * 9


def test_payload_of_zero_mass_scaled_keeps_a_zero_inertia():
    empty = Payload(0.0, (0.0, 0.0, 0.0))
    scaled = empty.scaled(3.0)
    assert scaled.mass == 3.0 and scaled.inertia == (0.0,) * 9


def test_payload_scaled_validates_the_new_mass():
    with pytest.raises(ModelError, match="^Payload: mass must be"):
        Payload(1.0).scaled(-2.0)
