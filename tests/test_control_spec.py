"""mobman.control.spec: a simulation's specification (the planar angle's sequence)."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import InputError, kinematics
from mobman.model import robots
from mobman.model.tasks import PlanarAngle

PLANAR_ANGLE_SPEC = {
    "duration": 0.2,
    "dt": 0.02,
    "q0": [0.0, 0.0, 0.0, 0.2, 0.5, 0.9],
    "robot": {"name": "bayle-rrp"},
    "task": {"kind": "planar_angle"},
    "reference": {"kind": "line", "start": [0.2], "end": [0.3], "duration": 0.2},
    "law": {"kind": "bayle"},
    "gains": {"W": 2.0},
}


def test_spec_planar_angle_sequence():
    """``sequence = "ZXY"``: Bayle's ξ4 = q3 + q4 (§5.2) through the vertical arm and past it; the default
    ZYX heading of the x axis turns by π past the vertical (the arm's x axis points backwards)."""
    from mobman.control import spec

    robot = robots.bayle_rrp()
    zxy = spec.parse(dict(PLANAR_ANGLE_SPEC, task={"kind": "planar_angle", "sequence": "ZXY"})).task
    zyx = spec.parse(PLANAR_ANGLE_SPEC).task
    assert zxy == PlanarAngle(sequence="ZXY") and zyx == PlanarAngle(sequence="ZYX")
    for q5 in (0.3, np.pi / 2, 2.0):
        q = np.array([0.1, -0.2, 0.3, 0.4, q5, 0.9])
        np.testing.assert_allclose(np.asarray(kinematics.forward(robot, q, zxy)), [0.7], atol=1e-12)
    q = np.array([0.1, -0.2, 0.3, 0.4, 2.0, 0.9])
    np.testing.assert_allclose(np.asarray(kinematics.forward(robot, q, zyx)), [0.7 - np.pi], atol=1e-12)


@pytest.mark.parametrize(
    "sequence, message",
    [
        ("zxy", "task.sequence: 'zxy' not one of ZYX, ZXY (did you mean 'ZXY'?)"),
        ("ZYZ", "(did you mean 'ZYX'?)"),
        ("XYZ", "task.sequence: 'XYZ' not one of ZYX, ZXY"),
        (3, "task.sequence: must be a string"),
    ],
)
def test_spec_planar_angle_sequence_errors(sequence, message):
    from mobman.control import spec

    with pytest.raises(InputError) as exc:
        spec.parse(dict(PLANAR_ANGLE_SPEC, task={"kind": "planar_angle", "sequence": sequence}))
    assert message in str(exc.value)
