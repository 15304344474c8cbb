"""Rigid-body dynamics of mobile manipulators with nonholonomic reduction.

Contract (see the module docstrings for the equations):

    from mobman import dynamics as dyn
    dyn.PlatformBody(mass, inertia_z, com=(0, 0, 0))     # inertia_z about the vertical through the com
    dyn.Wheel(mass, I_w, I_m)                            # required for a platform with driven wheels
    dyn.Payload(mass, inertia=(0,)*9, com=(0, 0, 0), arm=0)
    model = dyn.DynamicModel(robot, body, wheel, payload=None, gravity=(0, 0, -9.81))
    model = dyn.DynamicModel.from_urdf(mobman.io.urdf.read_urdf(path, tip=...), gravity=(0, 0, -9.81))
    dyn.mass_matrix(model, q), dyn.bias(model, q, q_dot)                 # full coordinates q = (x, y, θ, q_a…)
    dyn.reduced_mass_matrix(model, q), dyn.reduced_bias(model, q, eta), dyn.input_matrix(model, q)
    dyn.inverse_dynamics(model, q, eta, eta_dot) -> tau, dyn.forward_dynamics(model, q, eta, tau) -> eta_dot
    dyn.simulate(model, q0, eta0, torque_fn, duration, dt) -> SimulationResult(t, q, eta, tau)

Extensions of the contract: ``coriolis_matrix``, ``generalized_force`` (M q̈ + c + g by Newton–Euler),
``gravity_vector``, ``potential_energy``, ``actuation_matrix``
(E, full coordinates), ``energy``, ``constraint_forces``, ``wheel_angle_rates`` (Yamamoto's wheel-angle
coordinates), ``yamamoto_model()``; actuators (``TorqueBox``, ``DCMotor``) and ``max_load`` in
:mod:`mobman.dynamics.actuators` / :mod:`mobman.dynamics.load_capacity`.
Actuator order τ = (τ_platform…, τ_joints…) (``model.actuator_names``): the right and left wheels (or wheel
sides of a skid-steer) of a platform with driven wheels; other platforms are actuated directly on their
quasi-velocities (one generalized force per η_p).
"""

from mobman.dynamics.actuators import DCMotor, TorqueBox
from mobman.dynamics.equations import (
    actuation_matrix,
    bias,
    coriolis_matrix,
    generalized_force,
    gravity_vector,
    mass_matrix,
    potential_energy,
    wheel_angle_rates,
)
from mobman.dynamics.inertia import DynamicModel, yamamoto_platform
from mobman.dynamics.load_capacity import InfeasibleMotionError, LoadCapacity, load_torques, max_load
from mobman.dynamics.reduced import (
    constraint_forces,
    energy,
    forward_dynamics,
    input_matrix,
    inverse_dynamics,
    reduced_bias,
    reduced_mass_matrix,
)
from mobman.dynamics.simulation import SimulationResult, simulate, zero_torque
from mobman.model.inertial import Payload, PlatformBody, Wheel  # plain data, re-exported here


def yamamoto_model(
    payload: Payload | None = None, gravity: tuple[float, float, float] = (0.0, 0.0, 0.0)
) -> DynamicModel:
    """Yamamoto & Yun's two-arm mobile manipulator with Table 1–2 inertials (horizontal motion: no gravity)."""
    from mobman.model.robots import yamamoto_dual_arm

    body, wheel = yamamoto_platform()
    return DynamicModel(yamamoto_dual_arm(), body, wheel, payload, gravity)


__all__ = [
    "DynamicModel",
    "Payload",
    "PlatformBody",
    "Wheel",
    "actuation_matrix",
    "bias",
    "constraint_forces",
    "coriolis_matrix",
    "energy",
    "forward_dynamics",
    "generalized_force",
    "gravity_vector",
    "input_matrix",
    "inverse_dynamics",
    "mass_matrix",
    "potential_energy",
    "reduced_bias",
    "reduced_mass_matrix",
    "SimulationResult",
    "simulate",
    "wheel_angle_rates",
    "yamamoto_model",
    "yamamoto_platform",
    "zero_torque",
    "DCMotor",
    "InfeasibleMotionError",
    "LoadCapacity",
    "TorqueBox",
    "load_torques",
    "max_load",
]
