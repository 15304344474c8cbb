"""The dynamic model the dynamics tests share: a yaw joint and two lifting joints (a vertical 2-link arm on a
turret, full inertia tensors) on a differential drive, with a platform body, wheels and a payload."""

from __future__ import annotations

import math
from functools import cache

import numpy as np

import mobman
from mobman import dynamics as dyn
from mobman import kinematics
from mobman.model import spatial

R, B = 0.1, 0.25
WHEEL = dyn.Wheel(5.0, 0.01, 0.135)


def turret_arm() -> mobman.Arm:
    """A yaw joint and two lifting joints (a vertical 2-link arm on a turret), full inertia tensors."""
    lift = (0.0, -1.0, 0.0)
    return mobman.Arm(
        (
            mobman.Joint(
                "revolute",
                (0.0, 0.0, 1.0),
                name="yaw",
                inertial=mobman.LinkInertial(
                    4.0, (0.0, 0.02, 0.05), (0.03, 0.0, 0.0, 0.0, 0.04, 0.0, 0.0, 0.0, 0.02)
                ),
            ),
            mobman.Joint(
                "revolute",
                lift,
                spatial.transform(None, (0.0, 0.0, 0.1)),
                name="shoulder",
                inertial=mobman.LinkInertial(
                    3.0, (0.2, 0.0, 0.01), (0.01, 0.001, 0.0, 0.001, 0.05, 0.0, 0.0, 0.0, 0.05)
                ),
            ),
            mobman.Joint(
                "revolute",
                lift,
                spatial.transform(None, (0.4, 0.0, 0.0)),
                name="elbow",
                inertial=mobman.LinkInertial(
                    2.0, (0.15, 0.01, 0.0), (0.005, 0.0, 0.0, 0.0, 0.02, 0.0, 0.0, 0.0, 0.02)
                ),
            ),
        ),
        tool=spatial.transform(None, (0.35, 0.0, 0.0)),
    )


def turret_model(wheel=WHEEL, gravity=(0.0, 0.0, -9.81)) -> dyn.DynamicModel:
    robot = mobman.MobileManipulator(
        mobman.DifferentialDrive(R, B), (turret_arm(),), (mobman.Mount(0.2, 0.05, 0.3),)
    )
    body = dyn.PlatformBody(30.0, 1.5, com=(-0.05, 0.01, 0.15))
    payload = dyn.Payload(1.5, (0.002, 0.002, 0.002), com=(0.05, 0.0, 0.0))
    return dyn.DynamicModel(robot, body, wheel, payload, gravity)


MODEL = turret_model()
N = 6


@cache
def random_states() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(q, q̇ = S η, η, η̇) at N random states, q over the whole range [−π, π]."""
    rng = np.random.default_rng(7)
    q = rng.uniform(-math.pi, math.pi, (N, 6))
    eta = rng.normal(size=(N, 5))
    eta_dot = rng.normal(size=(N, 5))
    q_dot = np.asarray(kinematics.S(MODEL.robot, q) @ eta[..., None])[..., 0]
    return q, q_dot, eta, eta_dot
