"""Configurations outside the joint limits (mobman.cli.limits.outside_limits): the names per configuration,
one warning line per offending configuration ending with the note, and with ``strict`` one InputError
naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.cli.limits import outside_limits
from mobman.errors import InputError
from mobman.model.arm import Arm, Joint
from mobman.model.platforms import DifferentialDrive
from mobman.model.robot import MobileManipulator


@pytest.fixture(scope="module")
def robot() -> MobileManipulator:
    """Differential base + shoulder in [−1, 1] rad and slide in [0, 0.5] m: q = (x, y, θ, shoulder, slide)."""
    arm = Arm(
        (
            Joint("revolute", name="shoulder", lower=-1.0, upper=1.0),
            Joint("prismatic", (1.0, 0.0, 0.0), name="slide", lower=0.0, upper=0.5),
        )
    )
    return MobileManipulator(DifferentialDrive(), (arm,))


def test_configurations_inside_the_limits_give_no_names_and_no_warning(robot, capsys):
    q = np.array([[1e6, -1e6, 40.0, 0.0, 0.25], [0.0, 0.0, 0.0, -1.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.5]])
    assert outside_limits(robot, q, "--q", strict=False) == [[], [], []]  # the bounds themselves are inside
    assert capsys.readouterr().err == ""


def test_the_names_of_each_configuration_outside_its_limits(robot, capsys):
    q = np.array(
        [
            [0.0, 0.0, 0.0, 1.5, 0.1],  # shoulder above
            [0.0, 0.0, 0.0, 0.0, 0.2],  # inside
            [0.0, 0.0, 0.0, -2.0, 0.75],  # both
            [0.0, 0.0, 0.0, 0.0, -0.01],  # slide below
        ]
    )
    assert outside_limits(robot, q, "--q-file q.csv", strict=False) == [
        ["shoulder"],
        [],
        ["shoulder", "slide"],
        ["slide"],
    ]
    assert capsys.readouterr().err.splitlines() == [
        "warning: --q-file q.csv, configuration 1: shoulder = 1.5 outside [-1, 1] "
        "(the robot's joint limits); analysed as given",
        "warning: --q-file q.csv, configuration 3: shoulder = -2 outside [-1, 1], "
        "slide = 0.75 outside [0, 0.5] (the robot's joint limits); analysed as given",
        "warning: --q-file q.csv, configuration 4: slide = -0.01 outside [0, 0.5] "
        "(the robot's joint limits); analysed as given",
    ]


def test_a_single_configuration_is_labelled_by_the_field_alone(robot, capsys):
    out = outside_limits(
        robot, np.array([[0.0, 0.0, 0.0, 0.0, 0.6]]), "--q", False, note="simulated as given"
    )
    assert out == [["slide"]]
    assert capsys.readouterr().err.splitlines() == [
        "warning: --q: slide = 0.6 outside [0, 0.5] (the robot's joint limits); simulated as given"
    ]


def test_strict_raises_one_line_naming_the_field_and_the_limits(robot, capsys):
    q = np.array([[0.0, 0.0, 0.0, 0.0, 0.1], [0.0, 0.0, 0.0, 3.0, 0.1]])
    with pytest.raises(InputError) as info:
        outside_limits(robot, q, "--q-file q.csv", strict=True)
    assert str(info.value) == (
        "--q-file q.csv, configuration 2: shoulder = 3 outside [-1, 1] (the robot's joint limits)"
    )
    assert capsys.readouterr().err == ""


def test_strict_accepts_configurations_inside_the_limits(robot):
    assert outside_limits(robot, np.array([[0.0, 0.0, 0.0, 0.5, 0.5]]), "--q", strict=True) == [[]]


def test_only_the_selected_coordinates_are_checked(robot, capsys):
    q = np.array([[0.0, 0.0, 0.0, 5.0, 0.9]])
    assert outside_limits(robot, q, "--q", False, coordinates=slice(4, None)) == [["slide"]]
    assert "shoulder" not in capsys.readouterr().err
    assert outside_limits(robot, q, "--q", True, coordinates=slice(0, 3)) == [[]]  # the platform: unbounded
