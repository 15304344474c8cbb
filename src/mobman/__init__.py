"""mobman: nonholonomic wheeled mobile manipulators.

Importing mobman enables float64 in JAX: every kinematic quantity is computed in double precision.
"""

from __future__ import annotations

import jax

jax.config.update("jax_enable_x64", True)

# The real robots (TIAGo, TIAGo dual, Stretch) join the built-in robots; their URDF files are read when first built.
import mobman.io.real_robots  # noqa: E402,F401
from mobman.errors import (  # noqa: E402
    ConvergenceError,
    InfeasibleTaskError,
    InputError,
    MobmanError,
    ModelError,
    SingularConfigurationError,
)
from mobman.model import (  # noqa: E402
    Arm,
    CarLike,
    DifferentialDrive,
    Fixed,
    Joint,
    LinkInertial,
    MobileManipulator,
    Mount,
    Omnidirectional,
    SkidSteer,
)

__version__ = "0.1.0"

__all__ = [
    "Arm",
    "CarLike",
    "ConvergenceError",
    "DifferentialDrive",
    "Fixed",
    "InfeasibleTaskError",
    "InputError",
    "Joint",
    "LinkInertial",
    "MobileManipulator",
    "MobmanError",
    "ModelError",
    "Mount",
    "Omnidirectional",
    "SingularConfigurationError",
    "SkidSteer",
    "__version__",
]
