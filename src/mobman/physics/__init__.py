"""The robot as a MuJoCo model, for running mobman's motions on a physics engine.

:func:`to_mjspec` builds the model with MuJoCo's ``MjSpec`` editing API: the platform as a free body resting
on a floor plane on real wheels, the arms with mobman's inertials, joint limits and velocity-commanded
actuators with mobman's motor limits (:mod:`mobman.physics.mjcf`); :mod:`mobman.physics.state` maps mobman's
configuration q to MuJoCo's state and back; :func:`run_on_physics` closes a control law on the simulated
state (:mod:`mobman.physics.loop`). MuJoCo is imported only in this package, from the ``physics``
extra (``pip install -e ".[physics]"``).
"""

from mobman.physics.loop import PhysicsRun, run_on_physics
from mobman.physics.mjcf import dynamic_model, mjcf_text, to_mjspec
from mobman.physics.state import measured_q, set_configuration

__all__ = [
    "PhysicsRun",
    "dynamic_model",
    "measured_q",
    "mjcf_text",
    "run_on_physics",
    "set_configuration",
    "to_mjspec",
]
