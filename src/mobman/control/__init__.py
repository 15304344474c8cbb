"""Operational motion control of mobile manipulators: references ξ*(t), criteria P(q), control laws with
redundancy resolution (Bayle eq. 5–7, Nait-Chabane eq. 30, Korayem eq. 30, and Bayle's law as a quadratic
program within the velocity, wheel-speed and joint limits), closed-loop simulation and metrics.

```python
from mobman.control import references, criteria, laws, simulate, metrics
from mobman.model import robots
robot = robots.bayle_planar()
task = Position("xy")
law = laws.BaylePseudoInverse(W=2.0, k=1.0, criterion=criteria.Manipulability("eccentricity", "system"))
ref = references.Ellipse(center=(1.5, 0.0), semi_axes=(1.0, 0.5), period=20.0)
result = simulate(robot, task, law, ref, q0, duration=20.0, dt=0.01, measures=("arm_w5", "system_w5"))
metrics.summarize(result, robot, transient=2.0)
```

Notes for code written against ``docs/control_api`` (the contract):
- criteria are called as ``criterion(robot, q, task=None, xi_star=None)`` (``task``: the operational task the
  measure refers to; ``xi_star``: used by ``Blend``'s α(ξ*)); the laws pass the simulated task.
- ``references.Ellipse`` has an extra ``rotation`` (rad) of the ellipse; ``angle`` appends a constant
  orientation component, a 3-value ``center`` a constant z.
- laws: options ``damping`` (λ_max), ``damping_threshold`` (ε), ``normalized``, ``saturate`` are keyword-only.
- ``simulate(..., integrator="auto"|"lie"|"rk4", progress=None)``; ``law`` may be a list of laws (batch
  over gains), ``q0`` a (B, n_q) array (batch over initial configurations).
- ``simulate_pieces(...)``: the same run as consecutive pieces of ``chunk`` samples, one in memory at a time;
  ``metrics.RunningSummary`` takes them one after the other and gives ``summarize``'s metrics.
- ``result.info``: ``damping`` (λ²), ``sigma_min``, ``limit_ratio``, ``P`` (with a criterion), ``det``
  (AugmentedJacobian: |det [G; J; J_z]|), ``speed_limited``, ``joint_limited``, ``residual`` (WholeBodyQP),
  ``q_mid`` (lie integrator).
- ``metrics.summarize`` returns also ``final_error``, ``saturated_steps``, ``damped_steps``, the joint-limit
  report (``joint_limit_violations``, ``joint_limit_worst``, ``joint_limit_worst_joint``), the largest
  velocity and wheel-speed ratios (``velocity_limit_ratio``, ``wheel_speed_ratio``), ``NAME_steps`` per
  boolean info entry and, per recorded measure NAME, ``NAME_min``, ``NAME_max``, ``NAME_final``;
  ``metrics.first_significant(v, threshold)``.
"""

from mobman.control import criteria, laws, metrics, references
from mobman.control.simulation import (
    SimulationResult,
    compute_measures,
    simulate,
    simulate_pieces,
)

__all__ = [
    "SimulationResult",
    "compute_measures",
    "criteria",
    "laws",
    "metrics",
    "references",
    "simulate",
    "simulate_pieces",
]
