"""M(q) and c + g against Pinocchio (CRBA and RNEA) for a planar 3-link arm and the Panda (example-robot-data).

Pinocchio has no nonholonomic platform, so the comparison uses an Omnidirectional platform (S = I, a
holonomic base): the base becomes three joints (prismatic x, prismatic y, revolute z) carrying the platform
body, and the arm is attached through the mount transform. Its coordinates are exactly q = (x, y, θ, q_a),
so the whole (3 + n) × (3 + n) mass matrix and bias vector are compared, which includes the fixed-base arm
block (rows/columns 3:) with the platform held fixed. The differential drive differs only by S(q) and the
wheel terms, tested in test_dynamics_equations.py.
"""

from __future__ import annotations

from importlib import metadata

import numpy as np
import pinocchio as pin  # test-only dependency (pyproject `test` extra): a missing install fails loudly
import pytest

import mobman
from mobman import dynamics as dyn
from mobman.model import spatial

MOUNT = mobman.Mount(0.12, -0.05, 0.3, yaw=0.4)
BODY = dyn.PlatformBody(20.0, 1.3, com=(0.05, 0.02, 0.1))


def _links_to_models(links, gravity):
    """links: (axis, origin 4 × 4, mass, com, inertia 3 × 3) → (our DynamicModel, pinocchio Model)."""
    joints = tuple(
        mobman.Joint(
            "revolute",
            axis,
            tuple(np.ravel(origin)),
            name=f"j{i}",
            inertial=mobman.LinkInertial(mass, tuple(com), tuple(np.ravel(inertia))),
        )
        for i, (axis, origin, mass, com, inertia) in enumerate(links)
    )
    robot = mobman.MobileManipulator(mobman.Omnidirectional(), (mobman.Arm(joints),), (MOUNT,))
    ours = dyn.DynamicModel(robot, BODY, None, None, gravity)

    model = pin.Model()
    model.gravity.linear = np.asarray(gravity, dtype=float)
    parent = 0
    for name, joint in (("x", pin.JointModelPX()), ("y", pin.JointModelPY()), ("theta", pin.JointModelRZ())):
        parent = model.addJoint(parent, joint, pin.SE3.Identity(), name)
    inertia_body = np.diag([0.0, 0.0, BODY.inertia_z])
    model.appendBodyToJoint(
        parent, pin.Inertia(BODY.mass, np.asarray(BODY.com), inertia_body), pin.SE3.Identity()
    )
    placement = pin.SE3(spatial.as_matrix(MOUNT.transform))
    for i, (axis, origin, mass, com, inertia) in enumerate(links):
        placement = placement * pin.SE3(np.asarray(origin)) if i == 0 else pin.SE3(np.asarray(origin))
        parent = model.addJoint(
            parent, pin.JointModelRevoluteUnaligned(np.asarray(axis, float)), placement, f"j{i}"
        )
        model.appendBodyToJoint(
            parent, pin.Inertia(mass, np.asarray(com), np.asarray(inertia)), pin.SE3.Identity()
        )
    return ours, model


def _random_inertia(rng):
    a = rng.normal(size=(3, 3))
    return 0.05 * a @ a.T + 0.01 * np.eye(3)


def _planar_three_link():
    """A 3-link arm in a vertical plane (joints about y), full random inertia tensors, with gravity."""
    rng = np.random.default_rng(3)
    links = []
    for i, length in enumerate((0.0, 0.5, 0.4)):
        origin = np.eye(4)
        origin[0, 3] = length
        links.append(((0.0, 1.0, 0.0), origin, 2.0 + i, rng.uniform(-0.1, 0.3, 3), _random_inertia(rng)))
    return links


def _panda():
    """The Panda's 7 joints with the inertials of example-robot-data (fingers locked into the hand)."""
    files = [
        p
        for p in metadata.files("example-robot-data") or ()
        if str(p).endswith("panda_description/urdf/panda.urdf")
    ]
    assert files, "example-robot-data is installed without panda_description/urdf/panda.urdf"
    full = pin.buildModelFromUrdf(str(files[0].locate()))
    locked = [full.getJointId(n) for n in ("panda_finger_joint1", "panda_finger_joint2")]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    links = []
    assert model.njoints - 1 == 7
    for j in range(1, model.njoints):
        assert model.joints[j].shortname() == "JointModelRZ"  # every Panda joint turns about its local z
        inertia = model.inertias[j]
        links.append(
            (
                (0.0, 0.0, 1.0),
                model.jointPlacements[j].homogeneous,
                inertia.mass,
                np.asarray(inertia.lever),
                np.asarray(inertia.inertia),
            )
        )
    return links


@pytest.fixture(scope="module", params=["planar3", "panda"])
def comparison(request):
    """Our M and c + g at 8 random states (the last 4 with the platform at rest), and Pinocchio's."""
    links = _planar_three_link() if request.param == "planar3" else _panda()
    ours, model = _links_to_models(links, (0.0, 0.0, -9.81))
    rng = np.random.default_rng(0)
    n_q = ours.robot.n_q
    q = rng.uniform(-np.pi, np.pi, (8, n_q))
    q[:, :2] = rng.uniform(-2, 2, (8, 2))
    q_dot = rng.normal(size=(8, n_q))
    q_dot[4:, :3] = 0.0
    q_ddot = rng.normal(size=(8, n_q))
    data = model.createData()
    m_pin, b_pin, rnea, rnea_acc = [], [], [], []
    for k in range(len(q)):
        m = pin.crba(model, data, q[k]).copy()
        m_pin.append(np.triu(m) + np.triu(m, 1).T)
        b_pin.append(pin.nonLinearEffects(model, data, q[k], q_dot[k]).copy())
        rnea.append(pin.rnea(model, data, q[k], q_dot[k], np.zeros(n_q)).copy())
        rnea_acc.append(pin.rnea(model, data, q[k], q_dot[k], q_ddot[k]).copy())
    return (
        np.asarray(dyn.mass_matrix(ours, q)),
        np.asarray(dyn.bias(ours, q, q_dot)),
        np.array(m_pin),
        np.array(b_pin),
        np.array(rnea),
        np.asarray(dyn.generalized_force(ours, q, q_dot, q_ddot)),
        np.array(rnea_acc),
    )


def test_mass_matrix_matches_pinocchio_crba(comparison):
    m_ours, _, m_pin, *_ = comparison
    assert np.abs(m_pin).max() > 1.0  # a non-trivial comparison
    assert np.max(np.abs(m_ours - m_pin)) <= 1e-9 * np.abs(m_pin).max()


def test_bias_matches_pinocchio_nonlinear_effects(comparison):
    _, b_ours, _, b_pin, *_ = comparison
    assert np.abs(b_pin).max() > 1.0
    assert np.max(np.abs(b_ours - b_pin)) <= 1e-9 * np.abs(b_pin).max()


def test_fixed_platform_arm_block_matches_pinocchio_rnea(comparison):
    """Platform at rest: the arm rows of c + g equal Pinocchio's RNEA torques with zero acceleration."""
    _, b_ours, _, _, rnea, *_ = comparison
    assert np.max(np.abs(b_ours[4:, 3:] - rnea[4:, 3:])) <= 1e-9 * np.abs(rnea[4:]).max()


def test_newton_euler_inverse_dynamics_matches_pinocchio_rnea(comparison):
    """M q̈ + c + g by Newton–Euler (``generalized_force``) against Pinocchio's RNEA with an acceleration."""
    *_, ours, rnea_acc = comparison
    assert np.abs(rnea_acc).max() > 1.0
    assert np.max(np.abs(ours - rnea_acc)) <= 1e-9 * np.abs(rnea_acc).max()
