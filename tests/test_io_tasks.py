"""Tasks from file tables (mobman.io.tasks): every built-in kind from its table equals the task built in Python,
and each kind of mistake is one InputError naming the field."""

from __future__ import annotations

import pytest

from mobman.errors import InputError
from mobman.io.tasks import task
from mobman.model.tasks import (
    ElbowAngle,
    Elevation,
    EulerAngles,
    MountPosition,
    PlanarAngle,
    Pose,
    Position,
    stack,
)


@pytest.mark.parametrize(
    "table, expected",
    [
        ({"kind": "position"}, Position()),
        (
            {
                "kind": "position",
                "components": "xz",
                "arm": 1,
                "link": 2,
                "point": [0, 0.1, 0.2],
                "label": "t",
            },
            Position("xz", 1, 2, (0.0, 0.1, 0.2), "t"),
        ),
        ({"kind": "mount_position", "components": "y"}, MountPosition("y")),
        ({"kind": "planar_angle", "sequence": "ZXY", "link": 1}, PlanarAngle("ZXY", link=1)),
        ({"kind": "elevation", "arm": 1}, Elevation(arm=1)),
        ({"kind": "euler_angles", "sequence": "ZYX", "select": [2, 0]}, EulerAngles("ZYX", (2, 0))),
        ({"kind": "pose", "label": "flange"}, Pose(label="flange")),
        ({"kind": "elbow_angle"}, ElbowAngle()),
        (
            {
                "kind": "stack",
                "tasks": [{"kind": "stack", "tasks": [{"kind": "position"}]}, {"kind": "elevation"}],
            },
            stack(Position(), Elevation()),
        ),
    ],
)
def test_every_kind_from_its_table(table, expected):
    built = task(table, "task")
    assert built == expected and type(built) is type(expected)


@pytest.mark.parametrize(
    "table, message",
    [
        ("position", "task: must be a task table"),
        ({"kind": "positon"}, "task.kind: 'positon' not one of"),
        ({"kind": "position", "componets": "xy"}, "task.componets: unknown key; did you mean 'components'?"),
        ({"kind": "position", "components": "xq"}, "task: task components 'xq'"),
        ({"kind": "position", "arm": 0.5}, "task.arm: must be an integer"),
        ({"kind": "position", "point": [0, 0]}, "task.point: 3 values, got 2"),
        ({"kind": "position", "point": [0, "a", 0]}, "task.point[1]: must be a finite number"),
        (
            {"kind": "euler_angles", "sequence": "ZZZ"},
            "task.sequence: 'ZZZ' not one of ZYZ, ZYX, XYZ, ZXZ, ZXY",
        ),
        ({"kind": "euler_angles", "select": [0, 0]}, "task: EulerAngles: select must be distinct"),
        ({"kind": "elbow_angle", "labels": ["b"]}, "task.labels: unknown key; allowed: kind"),
        ({"kind": "stack", "tasks": {"kind": "position"}}, "task.tasks: must be an array"),
        ({"kind": "stack", "tasks": []}, "task: Stack: give one or more tasks"),
        (
            {"kind": "stack", "tasks": [{"kind": "position"}, {"kind": "pose", "arm": "a"}]},
            "task.tasks[1].arm",
        ),
    ],
)
def test_mistakes_name_the_field(table, message):
    with pytest.raises(InputError) as exc:
        task(table, "task")
    assert message in str(exc.value)
