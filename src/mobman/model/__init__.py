"""What a robot is: platforms, arms, mounts, the whole mobile manipulator, tasks and the papers' robots."""

from mobman.model.arm import Arm, Joint, LinkInertial
from mobman.model.platforms import (
    CarLike,
    DifferentialDrive,
    Fixed,
    Omnidirectional,
    Platform,
    SkidSteer,
    platform_class,
    platform_kinds,
)
from mobman.model.robot import Frames, MobileManipulator, Mount
from mobman.model.tasks import (
    ElbowAngle,
    Elevation,
    EulerAngles,
    FunctionTask,
    MountPosition,
    PlanarAngle,
    Pose,
    Position,
    Stack,
    Task,
    stack,
    task_class,
    task_kinds,
)

__all__ = [
    "Arm",
    "CarLike",
    "DifferentialDrive",
    "ElbowAngle",
    "Elevation",
    "EulerAngles",
    "Fixed",
    "Frames",
    "FunctionTask",
    "Joint",
    "LinkInertial",
    "MobileManipulator",
    "Mount",
    "MountPosition",
    "Omnidirectional",
    "PlanarAngle",
    "Platform",
    "Pose",
    "Position",
    "SkidSteer",
    "Stack",
    "Task",
    "platform_class",
    "platform_kinds",
    "stack",
    "task_class",
    "task_kinds",
]
