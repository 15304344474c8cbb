"""The model's identities as properties over the whole configuration space (hypothesis), for every platform
and every built-in robot (the papers' robots, the Panda, and the real robots when mobman[robots] is there):

- every platform: G(q_p) S(q_p) = 0 with rank S = δ_p and rank G = n_p − δ_p (S spans the admissible
  velocities, Bayle §4.1, Tchoń eq. 31), and a world rotation maps admissible velocities to admissible ones;
- every robot: G(q) S(q) = 0 and J̄ = J S (Bayle eq. 2: ``kinematics.reduced_jacobian_one`` against
  ``jacobian_one`` @ ``robot.S``) for its own task and a ZYX Euler-angle task, on the finite rows only where
  the task flags a representation singularity (``task.representation_singular``; the public batched
  functions against these: tests/test_task_range.py);
- frame invariance: a rigid motion of the platform in the world (θ → θ + α, (x, y) rotated by α and
  translated) leaves the flags, the Euler task's J̄ and the manipulability measures w, w2, w5 (Nait-Chabane
  eq. 17–19; arm, system, normalised system; restricted to the rank of J̄ where it is below m) unchanged;
- the velocity ellipsoid {J̄_N η : ‖η‖ ≤ 1} (Nait-Chabane §3.1): semi-axes = singular values (NumPy's SVD),
  directions = eigenvectors of J̄_N J̄_Nᵀ;
- dynamic models: the reduced mass matrix H = Sᵀ M S (Yamamoto & Yun) symmetric positive definite and
  invariant to the platform's rigid motion (kinetic energy does not depend on where the robot stands).

Autodiff = closed form = central finite differences for every task's Jacobian over the whole range is
tests/test_task_range.py. Each angle is drawn from 0, ±π/2, ±π mixed with floats over its whole range (a
joint's limits where it has them, both ends included); each hypothesis example is a batch of configurations of
one fixed shape, so each robot's kinematics compile once.
"""

from __future__ import annotations

import functools
import math

import jax
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mobman.io  # noqa: F401  (registers the real robots when mobman[robots] is installed)
from mobman import dynamics as dyn
from mobman import kinematics as K
from mobman import manipulability as mp
from mobman.model import CarLike, DifferentialDrive, EulerAngles, Platform, SkidSteer, robots
from mobman.model.platforms import platform_class, platform_kinds

SPECIAL = (0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi)
BATCH = 4  # configurations per example: one shape, one compilation per robot and function
# twice 6 for the dynamics: the 12 configurations whose H test_urdf_pinocchio.py compiles for TIAGo and Stretch
DYNAMIC_BATCH = 6
WIDTH = 24  # columns the measures see (more than any built-in robot has quasi-velocities)
SETTINGS = settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ANGLES = st.sampled_from(SPECIAL) | st.floats(-math.pi, math.pi)
POSITIONS = st.sampled_from((0.0,)) | st.floats(-3.0, 3.0)

PLATFORMS = [platform_class(kind)() for kind in platform_kinds()] + [
    DifferentialDrive(wheel_radius=0.075, half_track=0.171),
    CarLike(length=0.4),
    SkidSteer(x_icr=0.1, track_factor=1.6),
]
"""Every registered platform kind with its default parameters (a new kind is covered without an edit here),
and a few other parameters."""


def _concrete(cls: type) -> set[type]:
    """The subclasses of ``cls`` that mobman defines (not those a test file adds)."""
    found = set()
    for sub in cls.__subclasses__():
        found |= ({sub} if sub.__module__.startswith("mobman.") else set()) | _concrete(sub)
    return found


def _coordinate(kind: str, lower: float, upper: float) -> st.SearchStrategy[float]:
    """The whole range of one coordinate: [lower, upper] with both ends where the joint has limits, a full
    turn for an unbounded revolute joint (as `redundancy.sample_configurations` spans the others)."""
    span = math.pi if kind == "revolute" else 1.0
    lo = lower if math.isfinite(lower) else (upper - span if math.isfinite(upper) else -span)
    hi = upper if math.isfinite(upper) else lo + (span if math.isfinite(lower) else 2 * span)
    special = [v for v in SPECIAL if lo <= v <= hi] if kind == "revolute" else [0.0] if lo <= 0 <= hi else []
    return st.sampled_from(sorted({lo, hi, *special})) | st.floats(lo, hi)


def _configuration(robot) -> st.SearchStrategy[list[float]]:
    """One configuration: platform position anywhere, heading (and steering) over the whole turn, each arm
    joint over its whole range."""
    kinds = [j.kind for a in robot.arms for j in a.joints]
    arm = [_coordinate(k, lo, hi) for k, (lo, hi) in zip(kinds, robot.position_limits[robot.platform.n_q :])]
    return st.tuples(POSITIONS, POSITIONS, *([ANGLES] * (robot.platform.n_q - 2)), *arm).map(list)


def _batch(robot, size: int = BATCH) -> st.SearchStrategy[np.ndarray]:
    return st.lists(_configuration(robot), min_size=size, max_size=size).map(np.array)


MOTIONS = st.tuples(ANGLES, POSITIONS, POSITIONS)


def _moved(q: np.ndarray, motion: tuple[float, float, float]) -> np.ndarray:
    """The same configurations with the platform moved rigidly: rotated by α about the world z axis, then
    translated by (dx, dy); the heading wrapped to [−π, π)."""
    alpha, dx, dy = motion
    c, s = math.cos(alpha), math.sin(alpha)
    out = q.copy()
    out[:, 0] = c * q[:, 0] - s * q[:, 1] + dx
    out[:, 1] = s * q[:, 0] + c * q[:, 1] + dy
    out[:, 2] = (q[:, 2] + alpha + math.pi) % (2 * math.pi) - math.pi
    return out


def _rotation(n: int, alpha: float) -> np.ndarray:
    """R_p acting on q̇: (ẋ, ẏ) rotated by α, every other coordinate rate unchanged."""
    r = np.eye(n)
    r[:2, :2] = [[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]]
    return r


# --- platforms -------------------------------------------------------------------------------------


def test_every_platform_is_covered():
    assert _concrete(Platform) <= {type(p) for p in PLATFORMS}  # every subclass is registered by a kind


@pytest.mark.parametrize("platform", PLATFORMS, ids=repr)
@SETTINGS
@given(data=st.data())
def test_platform_S_spans_the_admissible_velocities(platform, data):
    n, d = platform.n_q, platform.n_eta
    q = np.array(
        data.draw(st.lists(st.tuples(POSITIONS, POSITIONS, *[ANGLES] * (n - 2)), min_size=1, max_size=8))
    )
    alpha = data.draw(ANGLES)
    for q_p in q:
        s, g = np.asarray(platform.S(q_p)), np.asarray(platform.constraints(q_p))
        assert s.shape == (n, d) and g.shape == (n - d, n)
        np.testing.assert_allclose(g @ s, 0.0, atol=1e-14)
        assert np.linalg.matrix_rank(s) == d
        assert np.linalg.matrix_rank(g) == n - d if n > d else g.size == 0
        moved = _moved(q_p[None], (alpha, 0.0, 0.0))[0]  # rotated admissible velocities stay admissible
        np.testing.assert_allclose(
            np.asarray(platform.constraints(moved)) @ _rotation(n, alpha) @ s, 0, atol=1e-14
        )


# --- robots: G S = 0, J̄ = J S, frame invariance, the velocity ellipsoid --------------------------------


@pytest.fixture(scope="module", params=list(robots.ROBOTS))
def robot(request):
    return robots.build(request.param)


def _tasks(robot) -> list:
    return [robot.task, EulerAngles("ZYX", arm=len(robot.arms) - 1)]


@functools.lru_cache(maxsize=None)
def _compiled(robot):
    """G, S and, for each task, J, J̄ and the representation flags of a batch: one program per robot."""
    tasks = _tasks(robot)

    def one(q):
        out = [robot.constraints(q), robot.S(q)]
        for task in tasks:
            frames = robot.frames(q)
            out += [K.jacobian_one(robot, task, q), K.reduced_jacobian_one(robot, task, q)]
            out.append(task.representation_singular(robot, q, frames))
        return out

    return jax.jit(jax.vmap(one))


def test_identities_of_every_robot(robot):
    @SETTINGS
    @given(q=_batch(robot), motion=MOTIONS)
    def check(q, motion):
        both = np.concatenate([q, _moved(q, motion)])
        g, s, *per_task = (np.asarray(a) for a in _compiled(robot)(both))
        np.testing.assert_allclose(g @ s, 0.0, atol=1e-14)
        for k, task in enumerate(_tasks(robot)):
            jac, jbar, flags = per_task[3 * k : 3 * k + 3]
            np.testing.assert_array_equal(flags[:BATCH], flags[BATCH:])  # a property of the robot's shape
            assert np.isfinite(jac[~flags]).all() and np.isfinite(jbar[~flags]).all(), task
            rows = np.isfinite(jac).all(axis=-1)  # where flagged: the finite rows
            scale = np.abs(np.where(rows[..., None], jac, 0.0)).max() + 1.0
            np.testing.assert_allclose(
                np.where(rows[..., None], jbar, 0.0),
                np.where(rows[..., None], jac @ s, 0.0),
                atol=1e-13 * scale,
            )
            if isinstance(task, EulerAngles):  # ZYX: a world yaw adds α to the first angle, J̄ unchanged
                regular = ~flags[:BATCH]
                np.testing.assert_allclose(jbar[BATCH:][regular], jbar[:BATCH][regular], atol=1e-9 * scale)
        jac, jbar, flags = per_task[:3]
        scale = np.abs(jac).max() + 1.0
        if not flags.any():
            _check_measures(robot, jac, jbar)

    check()


def _padded(j: np.ndarray) -> np.ndarray:
    """j with zero columns up to WIDTH: the same singular values, measures and ellipsoid, and one shape for
    every robot whose task has as many rows (one compilation of the measures serves them all)."""
    return np.concatenate([j, np.zeros((*j.shape[:-1], WIDTH - j.shape[-1]))], axis=-1)


def _check_measures(robot, jac: np.ndarray, jbar: np.ndarray) -> None:
    """w, w2, w5 of J_a, J̄, J̄_N equal before and after the motion (one call, each matrix padded with zero
    columns); restricted to the rank of J̄ where that is below m (``rank="auto"``'s choice: bayle-rrp's J̄ has
    rank 4 of 5 everywhere). The ellipsoid of J̄_N (or J̄)."""
    limits = robot.velocity_limits
    jn = _padded(jbar if limits is None else jbar * np.asarray(limits))
    kinds = np.stack([_padded(jac[..., robot.arm_slice(0)]), _padded(jbar), jn])  # (J_a, J̄, J̄_N)
    m, k = jbar.shape[-2:]
    r = int(np.linalg.matrix_rank(jbar).max())
    values = mp.measures(kinds.reshape(-1, m, WIDTH), None if r == min(m, k) else r)
    sigma1 = np.linalg.svd(kinds, compute_uv=False)[..., 0].max(axis=-1)  # per kind
    # accuracy of σ_i from the Gram matrix's eigenvalues: about √eps · σ_1 absolute on a tiny σ_i; w in units
    # of σ_1^r
    unit = {"yoshikawa": sigma1[:, None, None] ** r, "inverse_condition": 1.0, "eccentricity": 1.0}
    for name, value in values.items():
        value = np.asarray(value).reshape(3, 2, BATCH) / unit[name]  # kind × (before, after) × batch
        np.testing.assert_allclose(value[:, 1], value[:, 0], rtol=1e-9, atol=1e-7, err_msg=name)
    axes, directions = (np.asarray(a) for a in mp.ellipsoid(jn))
    sigma = np.linalg.svd(jn, compute_uv=False)  # NumPy's LAPACK SVD, not mobman's eigensolver
    m = jn.shape[-2]
    expected = np.concatenate([sigma, np.zeros((len(jn), m - sigma.shape[-1]))], axis=-1)
    np.testing.assert_allclose(axes, expected, atol=1e-7 * sigma.max())
    np.testing.assert_allclose(
        np.swapaxes(directions, -1, -2) @ directions, np.broadcast_to(np.eye(m), directions.shape), atol=1e-12
    )
    gram = jn @ np.swapaxes(jn, -1, -2)
    np.testing.assert_allclose(
        gram @ directions, directions * axes[:, None, :] ** 2, atol=1e-10 * sigma.max() ** 2
    )


# --- dynamics: the reduced mass matrix ------------------------------------------------------------


def _dynamic_models() -> dict:
    models = {"yamamoto-dual-arm": dyn.yamamoto_model()}
    if "tiago" in robots.ROBOTS:
        from mobman.io.real_robots import REAL_ROBOTS, urdf_model

        models |= {name: dyn.DynamicModel.from_urdf(urdf_model(name)) for name in REAL_ROBOTS}
    return models


@pytest.mark.parametrize("name", list(_dynamic_models()))
def test_reduced_mass_matrix_is_spd_and_frame_invariant(name):
    model = _dynamic_models()[name]

    @SETTINGS
    @given(q=_batch(model.robot, DYNAMIC_BATCH), motion=MOTIONS)
    def check(q, motion):
        h = np.asarray(dyn.reduced_mass_matrix(model, np.concatenate([q, _moved(q, motion)])))
        scale = np.abs(h).max()
        np.testing.assert_allclose(h, np.swapaxes(h, -1, -2), atol=1e-13 * scale)
        eig = np.linalg.eigvalsh(h)
        assert (eig > 1e-9 * scale).all(), eig.min(axis=-1)
        np.testing.assert_allclose(h[DYNAMIC_BATCH:], h[:DYNAMIC_BATCH], atol=1e-11 * scale)

    check()
