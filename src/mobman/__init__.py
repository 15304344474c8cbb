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

It also sets one XLA option, in ``XLA_FLAGS`` before JAX is imported:

- XLA's CPU compiler turns a while loop (``lax.scan``, ``fori_loop``, ``while_loop``) whose buffers total at
  most ``xla_cpu_small_while_loop_byte_threshold`` bytes into one kernel; a larger loop runs its body's kernels
  one by one through XLA's runtime, each a task handed to a thread pool, which costs more than mobman's tiny
  kernels. XLA's default, 1 kB, leaves most of mobman's loops to the runtime; mobman raises it to
  :data:`SMALL_LOOP_BYTES` (a batch of planning problems: 2.7× faster per iteration, one problem 2.4×;
  ``benchmarks/planning.py``). It is not set where ``XLA_FLAGS`` already gives
  ``--xla_backend_extra_options`` (the user's choice stands), nor where ``MOBMAN_XLA_SMALL_LOOPS=0``. XLA reads
  ``XLA_FLAGS`` once, when its first program compiles: it has no effect where a JAX computation ran before
  mobman was imported.
"""

from __future__ import annotations

import os
import warnings

SMALL_LOOP_BYTES = 1 << 20
"""The size (bytes) up to which XLA's CPU compiler makes a while loop one kernel (module notes)."""


def _switch(name: str, default: bool, otherwise: str) -> bool:
    """The environment variable ``name`` read as a yes or no (unset: ``default``); anything else warns and
    keeps the default, ``otherwise`` saying what that means."""
    value = os.environ.get(name, "").strip().lower()
    if value in ("1", "true", "yes", "on"):
        return True
    if value in ("0", "false", "no", "off"):
        return False
    if value:
        warnings.warn(
            f"{name} must be 1/true/yes/on or 0/false/no/off, got {value!r}: {otherwise}", stacklevel=3
        )
    return default


def _async_dispatch_wanted() -> bool:
    """``MOBMAN_CPU_ASYNC_DISPATCH`` read as a yes or no (unset: no)."""
    return _switch("MOBMAN_CPU_ASYNC_DISPATCH", False, "CPU dispatch stays synchronous")


def _with_small_loops(flags: str) -> str:
    """``XLA_FLAGS`` with the small-loop threshold added, unless the flags already give XLA's backend options
    (module notes)."""
    if "xla_backend_extra_options" in flags:
        return flags
    option = f"--xla_backend_extra_options=xla_cpu_small_while_loop_byte_threshold={SMALL_LOOP_BYTES}"
    return f"{flags} {option}".strip()


if _switch("MOBMAN_XLA_SMALL_LOOPS", True, f"while loops up to {SMALL_LOOP_BYTES} bytes become one kernel"):
    os.environ["XLA_FLAGS"] = _with_small_loops(os.environ.get("XLA_FLAGS", ""))

import jax  # noqa: E402  (after XLA_FLAGS)

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
