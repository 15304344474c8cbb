"""Actuator models (mobman.dynamics.actuators): the DC motor's torque–speed envelope, torque boxes, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman.dynamics.actuators import DCMotor, TorqueBox, actuator_list, envelope_coefficients
from mobman.errors import InputError, ModelError


def test_dc_motor_envelope_is_korayem_eq_34():
    motor = DCMotor(63.22, 3.5)
    assert motor.k2 == pytest.approx(63.22 / 3.5)
    speed = np.array([-1.0, 0.0, 1.0, 3.5, 5.0])
    lower, upper = motor.limits(speed)
    np.testing.assert_allclose(upper, 63.22 - 63.22 / 3.5 * speed, rtol=1e-15)
    np.testing.assert_allclose(lower, -63.22 - 63.22 / 3.5 * speed, rtol=1e-15)
    assert upper[3] == pytest.approx(0.0, abs=1e-12)  # no torque left to drive at the no-load speed


def test_torque_box_and_coefficients():
    box = TorqueBox(-2.0, 5.0)
    np.testing.assert_array_equal(box.limits([0.0, 10.0]), ([-2.0, -2.0], [5.0, 5.0]))
    assert TorqueBox.symmetric(3.0) == TorqueBox(-3.0, 3.0)
    coeffs = envelope_coefficients(actuator_list(("a", "b", "c"), {"a": box, "c": DCMotor(2.0, 4.0)}))
    np.testing.assert_array_equal(
        coeffs, [[-2.0, -math.inf, -2.0], [0.0, 0.0, -0.5], [5.0, math.inf, 2.0], [0.0, 0.0, -0.5]]
    )


@pytest.mark.parametrize(
    ("factory", "field"),
    [
        (lambda: DCMotor(0.0, 3.5), "stall_torque"),
        (lambda: DCMotor(63.22, -1.0), "no_load_speed"),
        (lambda: DCMotor(math.inf, 3.5), "stall_torque"),
        (lambda: DCMotor(1.0, "fast"), "no_load_speed"),
        (lambda: TorqueBox(1.0, -1.0), "lower must be < upper"),
        (lambda: TorqueBox(math.nan, 1.0), "lower"),
        (lambda: TorqueBox.symmetric(-2.0), "limit"),
    ],
)
def test_actuator_validation_names_the_field(factory, field):
    with pytest.raises(ModelError, match=field):
        factory()


def test_actuator_list_errors():
    with pytest.raises(InputError, match="unknown actuator 'elbow'"):
        actuator_list(("a", "b"), {"elbow": TorqueBox(-1, 1)})
    with pytest.raises(InputError, match="expected 2 entries"):
        actuator_list(("a", "b"), [TorqueBox(-1, 1)])
    with pytest.raises(InputError, match="TorqueBox, a DCMotor or None"):
        actuator_list(("a",), [3.0])
