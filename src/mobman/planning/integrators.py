"""The fixed-step explicit Runge–Kutta schemes the planners offer for the endpoint map and its variational
system (``PlanningSetting.method``), tableaus of :mod:`mobman.integration`.

Explicit Runge–Kutta methods commute with linearisation: integrating
the variational system (Tchoń et al. eqs. 5–7) together with the state by the same tableau on the same grid
gives exactly the derivative of the discrete endpoint map, so the variational and the autodiff Jacobians agree
to rounding error whatever the step.

- ``"rk4"``: the classical 4-stage method of order 4 (:data:`~mobman.integration.RK4`);
- ``"dop853"``: the 12-stage method of order 8 of Dormand & Prince, with a fixed step and without its error
  estimator (:data:`~mobman.integration.DOP853`).

The planners integrate thousands of times: order 8 reaches 1e-14 with ~100 steps where RK4 needs ~8000, and
the cost of a ``lax.scan`` on a CPU is dominated by the number of steps.
"""

from __future__ import annotations

from mobman.errors import InputError
from mobman.integration import DOP853, RK4, Tableau

METHODS = {"rk4": RK4, "dop853": DOP853}


def tableau(method: str) -> Tableau:
    """The tableau of a method name (``METHODS``)."""
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    return METHODS[method]
