"""Operational tasks ξ = f(q) (Bayle §2), one module per kind; :mod:`mobman.model.tasks.base` has the
:class:`Task` interface and the registry.

Every module of this package is imported here, so a new file with a :class:`Task` subclass that sets ``kind``
is found by :func:`task_class` (robot and specification files name tasks by kind) without any other edit.
"""

from mobman.model.kinds import import_package
from mobman.model.tasks.base import REPRESENTATION_TOL, Task, task_class, task_kinds
from mobman.model.tasks.elevation import Elevation
from mobman.model.tasks.euler_angles import EulerAngles
from mobman.model.tasks.function import ElbowAngle, FunctionTask, elbow_angle
from mobman.model.tasks.mount_position import MountPosition
from mobman.model.tasks.orientation import OrientationTask
from mobman.model.tasks.planar_angle import HEADING_SEQUENCES, PlanarAngle
from mobman.model.tasks.pose import Pose
from mobman.model.tasks.position import Position
from mobman.model.tasks.stack import Stack, stack

import_package(__name__, __path__)

__all__ = [
    "HEADING_SEQUENCES",
    "REPRESENTATION_TOL",
    "ElbowAngle",
    "Elevation",
    "EulerAngles",
    "FunctionTask",
    "MountPosition",
    "OrientationTask",
    "PlanarAngle",
    "Pose",
    "Position",
    "Stack",
    "Task",
    "elbow_angle",
    "stack",
    "task_class",
    "task_kinds",
]
