"""mobman's configuration q in a MuJoCo model of :func:`mobman.physics.to_mjspec`, and back.

The platform pose (x, y, θ) is the free joint's position and yaw (the ``platform`` body's frame is mobman's
platform frame; for an omnidirectional platform its slide and hinge joints, for a fixed one the body's
placement, which q cannot move), a car's steering angle φ the ``steering_right`` hinge, and each arm
coordinate the MuJoCo joint of its name. The arm servos integrate their commands from their activation, which
:func:`set_configuration` sets to q so that a robot placed at q holds it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError
from mobman.model.robot import MobileManipulator


def _joint_address(model: Any, name: str) -> int:
    return int(model.jnt_qposadr[model.joint(name).id])


def set_configuration(model: Any, data: Any, robot: MobileManipulator, q: npt.ArrayLike) -> None:
    """Place the robot of ``model`` (built from ``robot``) at configuration q (n_q,) at rest: the platform on
    the floor at (x, y, θ), the arm joints (and a car's steering) at q with their servos holding q, every
    velocity 0; then ``mj_forward``."""
    import mujoco

    q = robot.validate_q(q)
    if q.shape != (robot.n_q,):
        raise InputError(f"q: one configuration of {robot.n_q} numbers, got shape {q.shape}")
    mujoco.mj_resetData(model, data)
    x, y, theta = q[:3]
    kind = robot.platform.kind
    if kind == "omnidirectional":
        for name, value in zip(robot.platform.actuator_names, (x, y, theta)):
            data.qpos[_joint_address(model, name)] = value
    elif kind != "fixed":
        adr = _joint_address(model, "platform")
        data.qpos[adr : adr + 7] = [x, y, 0.0, np.cos(theta / 2), 0.0, 0.0, np.sin(theta / 2)]
    if kind == "car":
        for side in ("right", "left"):
            data.qpos[_joint_address(model, f"steering_{side}")] = q[3]
    for name, value in zip(robot.coordinate_names[robot.n_platform :], q[robot.n_platform :]):
        data.qpos[_joint_address(model, name)] = value
    for actuator in range(model.nu):
        if model.actuator_dyntype[actuator] == mujoco.mjtDyn.mjDYN_INTEGRATOR:
            joint = model.actuator_trnid[actuator, 0]
            data.act[model.actuator_actadr[actuator]] = data.qpos[model.jnt_qposadr[joint]]
    mujoco.mj_forward(model, data)


def measured_q(model: Any, data: Any, robot: MobileManipulator) -> np.ndarray:
    """mobman's configuration q (n_q,) of the simulated state: the platform's (x, y) and its yaw θ (the
    heading of its x axis, in (−π, π]), a car's steering angle, the arm joints (:class:`StateReader`)."""
    return StateReader(model, robot).q(data)


class StateReader:
    """:func:`measured_q` and the platform's measured rates of one model, its joints' addresses looked up
    once (a control loop reads the state at every step)."""

    def __init__(self, model: Any, robot: MobileManipulator) -> None:
        import mujoco

        self.model, self.mujoco = model, mujoco
        self.n_q, kind = robot.n_q, robot.platform.kind
        self.kind, self.n_q_p = kind, robot.platform.n_q
        self.velocity = np.zeros(6)
        names = robot.platform.actuator_names if kind == "omnidirectional" else ()
        self.platform_dofs = np.array([model.jnt_dofadr[model.joint(n).id] for n in names], dtype=int)
        self.steering_dof = model.jnt_dofadr[model.joint("steering_right").id] if kind == "car" else None
        self.arm = np.array(
            [_joint_address(model, name) for name in robot.coordinate_names[robot.n_platform :]], dtype=int
        )
        self.platform = (
            np.array([_joint_address(model, name) for name in robot.platform.actuator_names], dtype=int)
            if kind == "omnidirectional"
            else None
        )
        self.body = model.body("platform").id
        self.steering = _joint_address(model, "steering_right") if kind == "car" else None

    def q(self, data: Any) -> np.ndarray:
        """The configuration q (n_q,) of ``data`` (:func:`measured_q`)."""
        q = np.zeros(self.n_q)
        if self.platform is not None:
            q[:3] = data.qpos[self.platform]
        else:
            rotation = data.xmat[self.body]
            q[:2] = data.xpos[self.body][:2]
            q[2] = np.arctan2(rotation[3], rotation[0])  # R[1, 0], R[0, 0] of the row-major 3 × 3
        if self.steering is not None:
            q[3] = data.qpos[self.steering]
        q[self.n_q - self.arm.size :] = data.qpos[self.arm]
        return q

    def rates(self, data: Any) -> np.ndarray:
        """q̇_p measured: (ẋ, ẏ, θ̇) of the platform frame (and a car's φ̇)."""
        if self.kind == "fixed":
            return np.zeros(self.n_q_p)
        if self.kind == "omnidirectional":
            return np.array(data.qvel[self.platform_dofs])
        velocity, mj = self.velocity, self.mujoco
        mj.mj_objectVelocity(self.model, data, mj.mjtObj.mjOBJ_BODY, self.body, velocity, 0)
        rates = [velocity[3], velocity[4], velocity[2]]
        if self.steering_dof is not None:
            rates.append(data.qvel[self.steering_dof])
        return np.array(rates)
