"""What a run on physics measures beyond q: each wheel's slip and contact force, each actuator's torque.

:func:`wheel_probe` is a probe of :func:`mobman.physics.run_on_physics` for a model of
:func:`mobman.physics.to_mjspec`. At each control instant it reads off MuJoCo's state:

- ``slip_longitudinal`` (per wheel, m/s): the velocity of the wheel's contact point, the lowest point of its
  rim, along its rolling direction d = a × ẑ (a the axle in world axes): v_c · d with
  v_c = v_o + ω × (−r ẑ) (v_o, ω the wheel body's linear and angular velocity, r its radius). Rolling without
  slipping is v_c = 0 (Campion et al.'s rolling condition; the lateral part v_c · a is the nonholonomic
  constraint, which the run records for the whole platform as G(q_p) q̇_p);
- ``contact_normal``, ``contact_tangential`` (per wheel, N): the normal force of the floor (and of obstacles)
  on the wheel and the magnitude of the friction force (``mj_contactForce``, summed over its contacts);
- ``torque`` (per actuator, N·m or N): the force each servo applies (``actuator_force``) plus the run's
  feed-forward on the actuator's joint (``qfrc_applied``, 0 without one), and ``at_limit`` whether it is held at
  its torque limit (the ``forcerange`` the model was built with).

The wheels are the bodies with a ``<name>_contact`` sphere (the export's wheels; casters are not wheels).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from mobman.physics.mjcf import mujoco_module

AT_LIMIT = 1.0 - 1e-9
"""A servo whose |force| reaches this fraction of its limit counts as saturated."""


def wheel_probe(model: Any) -> Callable[[Any], dict[str, np.ndarray]]:
    """The function of ``MjData`` giving the wheel slips, contact forces and actuator torques of ``model``
    (see the module docstring)."""
    mj = mujoco_module()
    names = [model.geom(g).name for g in range(model.ngeom)]
    contacts = [g for g, name in enumerate(names) if name.endswith("_contact")]
    bodies = np.array([model.geom_bodyid[g] for g in contacts], dtype=int)
    radii = np.array([model.geom_size[g, 0] for g in contacts])
    wheel_of = {g: i for i, g in enumerate(contacts)}
    limited = model.actuator_forcelimited.astype(bool)
    limits = np.where(limited, np.abs(model.actuator_forcerange[:, 1]), np.inf)
    on_joint = model.actuator_trntype == int(mj.mjtTrn.mjTRN_JOINT)
    dofs = model.jnt_dofadr[np.where(on_joint, model.actuator_trnid[:, 0], 0)]
    z = np.array([0.0, 0.0, 1.0])
    velocity, force = np.zeros(6), np.zeros(6)

    def sample(data: Any) -> dict[str, np.ndarray]:
        slip = np.zeros(len(contacts))
        for i, (body, radius) in enumerate(zip(bodies, radii)):
            mj.mj_objectVelocity(model, data, mj.mjtObj.mjOBJ_BODY, body, velocity, 0)
            rim = velocity[3:] + np.cross(velocity[:3], -radius * z)
            axle = data.xmat[body].reshape(3, 3)[:, 1]  # the hinge axis: the body's y axis
            rolling = np.cross(axle, z)
            slip[i] = rim @ rolling / np.linalg.norm(rolling)
        normal, tangential = np.zeros(len(contacts)), np.zeros(len(contacts))
        for c in range(data.ncon):
            contact = data.contact[c]
            wheel = wheel_of.get(contact.geom1, wheel_of.get(contact.geom2))
            if wheel is not None:
                mj.mj_contactForce(model, data, c, force)
                normal[wheel] += force[0]
                tangential[wheel] += np.hypot(force[1], force[2])
        torque = data.actuator_force + np.where(on_joint, data.qfrc_applied[dofs], 0.0)
        return {
            "slip_longitudinal": slip,
            "contact_normal": normal,
            "contact_tangential": tangential,
            "torque": torque,
            "at_limit": np.abs(torque) >= AT_LIMIT * limits,
        }

    return sample


def wheel_names(model: Any) -> list[str]:
    """The wheels' body names, in the order of :func:`wheel_probe`'s per-wheel series."""
    geoms = (model.geom(g) for g in range(model.ngeom))
    return [model.body(g.bodyid[0]).name for g in geoms if g.name.endswith("_contact")]


__all__ = ["AT_LIMIT", "wheel_names", "wheel_probe"]
