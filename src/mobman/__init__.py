"""mobman: nonholonomic wheeled mobile manipulators.

Importing mobman sets two JAX options:

- float64 (``jax_enable_x64``): every kinematic quantity is computed in double precision;
- synchronous CPU dispatch (``jax_cpu_enable_async_dispatch`` off): a compiled CPU program runs on the
  calling thread. Asynchronous dispatch hands a program to a worker thread and the caller waits for it: for
  mobman's one-configuration programs (tens of microseconds) that hand-over costs more than the program
  itself (TIAGo's J̄ and measures: 70 against 24 µs a call with each result waited for,
  ``benchmarks/real_robots.py``), and a batch is one long call either way. Set the environment variable
  ``MOBMAN_CPU_ASYNC_DISPATCH=1`` to keep JAX's asynchronous default. JAX reads the option when it creates
  its CPU backend, so it has no effect where a JAX computation ran before mobman was imported.
"""

from __future__ import annotations

import os
import warnings

import jax


def _async_dispatch_wanted() -> bool:
    """``MOBMAN_CPU_ASYNC_DISPATCH`` read as a yes or no (unset: no)."""
    value = os.environ.get("MOBMAN_CPU_ASYNC_DISPATCH", "").strip().lower()
    if value in ("1", "true", "yes", "on"):
        return True
    if value not in ("", "0", "false", "no", "off"):
        warnings.warn(
            f"MOBMAN_CPU_ASYNC_DISPATCH must be 1/true/yes/on or 0/false/no/off, got {value!r}: "
            "CPU dispatch stays synchronous",
            stacklevel=2,
        )
    return False


jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", _async_dispatch_wanted())

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
