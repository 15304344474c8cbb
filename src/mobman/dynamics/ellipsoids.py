"""Task-space ellipsoids of mobile manipulators, kinematic and dynamic (Yamamoto & Yun §3, eq. 23–38).

Both ellipsoids live in actuator space: the platform's quasi-velocities η = (v, ω) of a differential drive (or
a skid-steer) are replaced by the wheel speeds u_p = (θ̇_r, θ̇_l) (η_p = T_p u_p, ``platform.actuator_matrix``),
because the maxima of Table 2 are per wheel, and the torques τ = (τ_r, τ_l, τ_joints…) act on exactly these
coordinates. The arms' coordinates are their joint rates. x = u in the paper's notation (eq. 39).

**Kinematic** (eq. 23–26). Normalised actuator rates ū = Y u, Y = diag(1/u_max) (eq. 23), Ĵ = J Y⁻¹ (eq. 24)
with J the reduced Jacobian of the task in actuator coordinates. The ellipsoid is the set of task velocities
reachable with |ū| ≤ 1 (eq. 25). Without a held object it is {Ĵ ū}; with one, the end-effector velocities must
be rigid-body velocities of the object, Ĵ ū = Wᵀ v_o (eq. 20), and the set is

    {v_o : v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o ≤ 1}      (Ĵ of full row rank)

which is eq. 26 once its typos are removed (the printed form multiplies Ĵ⁺ by Y once too often, and has a
stray transpose). It is computed as the image of the unit ball under K = (W Wᵀ)⁻¹ W Ĵ Π, Π the orthogonal
projector onto the normalised rates that respect the grasp, which also holds when Ĵ loses rank.

**Dynamic** (eq. 27–38). Reduced equations P u̇ = ξ + Q τ − Jᵀ h (eq. 16, here P = Tᵀ SᵀMS T, Q = Tᵀ SᵀE,
ξ = −Tᵀ × reduced bias), the closure a = J u̇ + J̇ u = Wᵀ a_o + Ẇᵀ v_o (eq. 21, 27, 29) and the object
M_o a_o + c_o + g_o = W h (eq. 22). Two ellipsoids:

- ``method="paper"`` (eq. 31–38): u̇ = J⁺(Wᵀ a_o + Ẇᵀ v_o − J̇ u) and h = W⁺(M_o a_o + c_o + g_o) — minimum-norm
  choices — give τ = Λ_o a_o + μ_o with Λ_o = Q⁻¹(P J⁺ Wᵀ + Jᵀ W⁺ M_o) (eq. 34) and
  μ_o = Q⁻¹(−ξ + P J⁺(Ẇᵀ v_o − J̇ u) + Jᵀ W⁺(c_o + g_o)) (eq. 35 prints +Q⁻¹ξ and omits the velocity terms).
  With Z = diag(1/τ_max) (eq. 36) the ellipsoid is {a_o : |Z Λ_o a_o + Z μ_o| ≤ 1} (eq. 38): centre
  −Λ̄⁺μ̄, shape Λ̄⁺ scaled by ρ = √(1 − |μ̄ − Λ̄Λ̄⁺μ̄|²) (empty when the part of μ̄ outside range Λ̄ exceeds 1).
- ``method="exact"``: the image of the whole torque ball |Z τ| ≤ 1 through the closed-chain forward dynamics
  (u̇, h, a_o solved from the three equations above), i.e. every acceleration some admissible torque produces,
  whatever the self-motion and internal forces. It contains the paper's ellipsoid; both agree when Λ̄ is the
  minimum-norm inverse (e.g. a non-redundant arm without object).

**Grasp.** ``grasp="rigid"`` (default): each hand holds the object rigidly, wrenches (f, n) and the object's
(x_o, y_o, angle_o). ``grasp="point"``: the hands hold the object at its centre of mass through pivots (all tool
points within 1 mm of one point, as in the paper's case study), forces only: W = [I₂ I₂ …], v_i = v_o, M_o = m I₂, task
(x_o, y_o) — the paper's 2-D ellipses with m = 2.

``interaction=False`` drops the inertial coupling between platform and arms in P (the paper's §4.3
simplification). Results are :class:`Ellipsoid` objects: centre, shape matrix, principal axes and directions,
volume, sections and projections.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Literal, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import kinematics
from mobman.dynamics.grasp import HeldObject, grasp_matrix_one, grasp_matrix_rate_one
from mobman.errors import InputError, ModelError, SingularConfigurationError
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import PlanarAngle, Position, Task, stack

if TYPE_CHECKING:
    from mobman.dynamics.inertia import DynamicModel

Method = Literal["paper", "exact"]
Grasp = Literal["rigid", "point"]
GRASPS: tuple[Grasp, ...] = ("rigid", "point")


# --- the ellipsoid as a result ---------------------------------------------------------------------


@dataclass(frozen=True)
class Ellipsoid:
    """E = {center + matrix · s : |s| ≤ 1}, batched over leading dimensions.

    center (..., m); matrix (..., m, k); names: the m task coordinates; feasible (...): False where the set is
    empty (a dynamic ellipsoid whose offset μ̄ alone exceeds the torque limits); singular (...): True where the
    equations that define it are singular and it is their minimum-norm (degenerate) answer
    (:func:`closed_chain_matrices`).
    """

    center: np.ndarray
    matrix: np.ndarray
    names: tuple[str, ...]
    feasible: np.ndarray
    singular: np.ndarray | bool = False

    def __post_init__(self) -> None:
        for name in ("center", "matrix"):
            if not np.isfinite(getattr(self, name)).all():
                raise InputError(f"Ellipsoid: {name} must be finite (NaN or infinite entries)")

    @property
    def shape_matrix(self) -> np.ndarray:
        """Σ = K Kᵀ: E = {x : (x − c)ᵀ Σ⁻¹ (x − c) ≤ 1} when Σ is invertible."""
        return self.matrix @ np.swapaxes(self.matrix, -1, -2)

    @property
    def axes(self) -> np.ndarray:
        """Principal semi-axis lengths, major first, shape (..., m) (zeros for flat directions)."""
        s = np.linalg.eigvalsh(self.shape_matrix)[..., ::-1]
        return np.sqrt(np.clip(s, 0.0, None))

    @property
    def directions(self) -> np.ndarray:
        """Unit principal directions, columns in the order of :attr:`axes`, shape (..., m, m)."""
        _, vecs = np.linalg.eigh(self.shape_matrix)
        vecs = vecs[..., ::-1]
        # a deterministic sign: the largest component of each direction is positive
        idx = np.argmax(np.abs(vecs), axis=-2)[..., None, :]
        sign = np.sign(np.take_along_axis(vecs, idx, axis=-2))
        return vecs * np.where(sign == 0, 1.0, sign)

    @property
    def volume(self) -> np.ndarray:
        """Volume (area for m = 2): the unit ball's times the product of the semi-axes."""
        m = self.center.shape[-1]
        return math.pi ** (m / 2) / math.gamma(m / 2 + 1) * np.prod(self.axes, axis=-1)

    def projection(self, keep: Sequence[int]) -> "Ellipsoid":
        """The shadow of E on the coordinates ``keep`` (the others free)."""
        keep = list(keep)
        return Ellipsoid(
            self.center[..., keep],
            self.matrix[..., keep, :],
            tuple(self.names[i] for i in keep),
            self.feasible,
            self.singular,
        )

    def section(self, keep: Sequence[int], at: Sequence[float] | None = None) -> "Ellipsoid":
        """The slice of E where the other coordinates equal ``at`` (zero by default), on the coordinates ``keep``.

        With Σ = K Kᵀ split into kept (t) and fixed (s) blocks and d = at − c_s: centre c_t + Σ_ts Σ_ss⁻¹ d,
        shape Σ_tt − Σ_ts Σ_ss⁻¹ Σ_st scaled by ρ² = 1 − dᵀ Σ_ss⁻¹ d (empty when ρ² < 0). Needs Σ_ss invertible.
        """
        keep = list(keep)
        fixed = [i for i in range(self.center.shape[-1]) if i not in keep]
        values = np.zeros(len(fixed)) if at is None else np.asarray(at, dtype=float)
        sigma = self.shape_matrix
        s_tt = sigma[..., keep, :][..., :, keep]
        s_ts = sigma[..., keep, :][..., :, fixed]
        s_ss = sigma[..., fixed, :][..., :, fixed]
        d = values - self.center[..., fixed]
        flat = "Ellipsoid.section: the block Σ_ss of the fixed coordinates is singular (a flat ellipsoid)"
        gain = np.swapaxes(_solve(s_ss, np.swapaxes(s_ts, -1, -2), flat), -1, -2)  # Σ_ts Σ_ss⁻¹
        center = self.center[..., keep] + np.einsum("...ij,...j->...i", gain, d)
        rho2 = 1.0 - np.einsum("...i,...i->...", d, _solve(s_ss, d[..., None], flat)[..., 0])
        cond = s_tt - gain @ np.swapaxes(s_ts, -1, -2)
        vals, vecs = np.linalg.eigh((cond + np.swapaxes(cond, -1, -2)) / 2)
        root = vecs * np.sqrt(np.clip(vals, 0.0, None))[..., None, :] @ np.swapaxes(vecs, -1, -2)
        scale = np.sqrt(np.clip(rho2, 0.0, None))[..., None, None]
        return Ellipsoid(
            center, root * scale, tuple(self.names[i] for i in keep), np.logical_and(self.feasible, rho2 >= 0)
        )

    def contains(self, x: npt.ArrayLike, tol: float = 1e-9) -> np.ndarray:
        """Whether points x (..., m) lie in E (Σ invertible), up to ``tol`` on the quadratic form."""
        d = np.asarray(x, dtype=float) - self.center
        flat = "Ellipsoid.contains: the shape matrix Σ is singular (a flat ellipsoid)"
        form = np.einsum("...i,...i->...", d, _solve(self.shape_matrix, d[..., None], flat)[..., 0])
        return np.logical_and(self.feasible, form <= 1.0 + tol)

    def boundary(self, n: int = 100, keep: Sequence[int] = (0, 1)) -> np.ndarray:
        """Points of the outline of the 2-D projection on ``keep`` (one ellipse per batch entry), (..., n, 2)."""
        proj = self.projection(keep)
        t = np.linspace(0.0, 2.0 * np.pi, n)
        sig = proj.shape_matrix
        vals, vecs = np.linalg.eigh(sig)
        root = vecs * np.sqrt(np.clip(vals, 0.0, None))[..., None, :]
        circle = np.stack([np.cos(t), np.sin(t)], axis=-1)
        return proj.center[..., None, :] + np.einsum("...ij,nj->...ni", root, circle)


# --- coordinates and tasks -------------------------------------------------------------------------


def uses_wheels(robot: MobileManipulator, kind: str = "kinematic") -> bool:
    """Whether the platform's actuator coordinates are wheel speeds: a platform with driven wheels
    (``platform.wheel_actuated``; for the kinematic ellipsoid only when its limit is given per wheel,
    ``platform.actuator_speed_limits``)."""
    platform = robot.platform
    if not platform.wheel_actuated:
        return False
    return kind == "dynamic" or platform.actuator_speed_limits is not None


def actuator_map(robot: MobileManipulator, wheels: bool) -> np.ndarray:
    """T (n_eta × n_eta) with η = T u: the platform's ``actuator_matrix`` on its block when ``wheels``, else
    I."""
    t = np.eye(robot.n_eta)
    if wheels:
        n = robot.platform.n_eta
        t[:n, :n] = robot.platform.actuator_matrix()
    return t


def actuator_velocity_limits(robot: MobileManipulator, platform_scale: float = 1.0) -> np.ndarray:
    """u_max: wheel speed limits (or the platform's η limits), then joint rate limits; the platform part times
    ``platform_scale``. ModelError when a limit is missing."""
    wheels = uses_wheels(robot)
    if wheels:
        platform = robot.platform.actuator_speed_limits
    else:
        platform = robot.platform.velocity_limits
    arms = [a.velocity_limits for a in robot.arms]
    if platform is None or any(a is None for a in arms):
        raise ModelError(
            f"{robot.name}: the kinematic ellipsoid needs velocity limits of the platform and of every joint"
        )
    limits = np.array(tuple(platform) + tuple(v for a in arms if a is not None for v in a), dtype=float)
    limits[: robot.platform.n_eta] *= platform_scale
    return limits


def grasp_task(robot: MobileManipulator, grasp: Grasp = "rigid") -> Task:
    """The rows that a held object couples, stacked over the arms: the planar pose (x, y, angle) of every tool
    frame for a rigid grasp, the tool point (x, y) for a point grasp."""
    if grasp == "point":
        return stack(*[Position("xy", arm=i, label=f"ee{i + 1}") for i in range(len(robot.arms))])
    return stack(
        *[
            stack(Position("xy", arm=i, label=f"ee{i + 1}"), PlanarAngle(arm=i))
            for i in range(len(robot.arms))
        ]
    )


OBJECT_NAMES = ("x_o", "y_o", "angle_o")
POINT_NAMES = ("x_o", "y_o")
POINT_TOLERANCE = 1e-3  # m: how far from their centroid the tool points of a point grasp may be


def point_grasp_matrix(n_arms: int) -> np.ndarray:
    """W = [I₂ I₂ …] (2 × 2k) of a point grasp: every hand holds the object at its centre of mass through a pivot,
    so it transmits a force and no moment, h_o = Σ f_i (eq. 17), and v_i = v_o (eq. 20, Ẇ = 0)."""
    return np.hstack([np.eye(2)] * n_arms)


def grasp_offsets_one(robot: MobileManipulator, q: jax.Array) -> jax.Array:
    """r_i of one configuration q (n_q,), (k, 2): each tool point (x, y) minus their centroid, the object's
    centre of mass; unvalidated, for traced code."""
    frames = robot.frames(q)
    points = jnp.stack([Position("xy", arm=i).value(robot, q, frames) for i in range(len(robot.arms))])
    return points - jnp.mean(points, axis=0, keepdims=True)


def grasp_offsets(robot: MobileManipulator, q: npt.ArrayLike) -> jnp.ndarray:
    """r_i: each tool point minus the object's centre of mass (the centroid of the tool points), (..., k, 2)."""
    return jnp.vectorize(partial(grasp_offsets_one, robot), signature="(n)->(k,c)")(
        kinematics.validated_q(robot, q)
    )


def _check_held(robot: MobileManipulator, grasp: str, q: npt.ArrayLike) -> None:
    if len(robot.arms) < 2:
        raise ModelError(
            f"{robot.name}: a held object needs two or more arms, the robot has {len(robot.arms)}"
        )
    if grasp not in GRASPS:
        raise InputError(f"grasp must be one of {', '.join(GRASPS)}, got {grasp!r}")
    if grasp == "point":
        spread = float(np.max(np.abs(np.asarray(grasp_offsets(robot, q)))))
        if spread > POINT_TOLERANCE:
            raise InputError(
                f"grasp='point' needs all tool points at one point (the object's centre of mass); "
                f"they are up to {spread:.3g} m from their centroid"
            )


def _scale(value: float | npt.ArrayLike, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise InputError(f"{name} must be finite and ≥ 0, got {value!r}")
    return arr


# --- kinematic ellipsoid ---------------------------------------------------------------------------


@partial(jax.jit, static_argnums=(0, 1, 2))
def _kinematic(
    robot: MobileManipulator, task: Task, held: str | None, q: jax.Array, u_max: jax.Array
) -> tuple[jax.Array, jax.Array]:
    t = actuator_map(robot, uses_wheels(robot))

    def one(q, u_max):
        jhat = kinematics.reduced_jacobian_one(robot, task, q) @ t * u_max  # Ĵ = J T Y⁻¹ (eq. 24)
        if held is None:
            return jnp.zeros(jhat.shape[0]), jhat
        if held == "point":
            w = jnp.asarray(point_grasp_matrix(len(robot.arms)))
        else:
            w = grasp_matrix_one(grasp_offsets_one(robot, q))
        w_left = jnp.linalg.solve(w @ w.T, w)  # (W Wᵀ)⁻¹ W: v_o from rigid end-effector velocities
        internal = jnp.eye(w.shape[1]) - w.T @ w_left  # projector onto internal (non-rigid) velocities
        cj = internal @ jhat
        admissible = jnp.eye(jhat.shape[1]) - jnp.linalg.pinv(cj) @ cj
        return jnp.zeros(w.shape[0]), w_left @ jhat @ admissible

    return jnp.vectorize(one, signature="(n),(k)->(m),(m,k)")(q, u_max)


def kinematic_ellipsoid(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    *,
    held: bool = False,
    platform_scale: float | npt.ArrayLike = 1.0,
    task: Task | None = None,
    grasp: Grasp = "rigid",
) -> Ellipsoid:
    """Kinematic task-space ellipsoid (eq. 23–26), batched over q (and over ``platform_scale``).

    ``held=False``: velocities of ``task`` (default: the robot's) reachable with |Y u| ≤ 1.
    ``held=True``: velocities (ẋ_o, ẏ_o, ω_o) of an object rigidly held by all arms (planar robots), centre of
    mass at the centroid of the tool points; with ``grasp="point"`` the hands hold the object's centre of mass
    through pivots (all tool points within 1 mm of one point) and the ellipsoid is that of (ẋ_o, ẏ_o).
    ``platform_scale`` multiplies the platform's maximum velocities.
    """
    q = robot.validate_q(q)
    if held:
        _check_held(robot, grasp, q)
        task = grasp_task(robot, grasp)
    task = robot.task if task is None else task
    task.check(robot)
    scale = _scale(platform_scale, "platform_scale")
    is_platform = np.arange(robot.n_eta) < robot.platform.n_eta
    u_max = actuator_velocity_limits(robot) * np.where(is_platform, scale[..., None], 1.0)
    center, matrix = _kinematic(robot, task, grasp if held else None, q, u_max)
    matrix = _finite_matrix(np.asarray(matrix), "kinematic ellipsoid")
    names = (POINT_NAMES if grasp == "point" else OBJECT_NAMES) if held else task.names
    return Ellipsoid(np.asarray(center), np.asarray(matrix), names, np.ones(center.shape[:-1], dtype=bool))


# --- dynamic ellipsoid -----------------------------------------------------------------------------


@dataclass(frozen=True)
class _Terms:
    """The ingredients of eq. 16, 21, 22 in actuator coordinates for a batch of configurations (NumPy)."""

    p: np.ndarray  # P = Tᵀ SᵀMS T (..., n, n)
    q: np.ndarray  # Q = Tᵀ SᵀE (..., n, n)
    b: np.ndarray  # −ξ = Tᵀ × reduced bias (..., n)
    j: np.ndarray  # J = J̄ T (..., r, n): end-effector (or task) rows
    drift: np.ndarray  # J̇ u − Ẇᵀ v_o (..., r): the velocity part of the closure a = Wᵀ a_o + Ẇᵀ v_o
    w: np.ndarray  # grasp matrix (..., m, r) (identity without object)
    m_o: np.ndarray  # object inertia (..., m, m) (zero without object)
    bias_o: np.ndarray  # c_o + g_o (..., m)


@partial(jax.jit, static_argnums=(0, 1, 2, 3, 4, 5))
def _dynamic_terms(
    model: DynamicModel,
    task: Task,
    obj: HeldObject | None,
    grasp: str,
    wheels: bool,
    at_rest: bool,
    q: jax.Array,
    eta: jax.Array,
) -> tuple[jax.Array, ...]:
    from mobman.dynamics import equations, reduced

    robot = model.robot
    t = actuator_map(robot, wheels)

    def jbar(q):
        return kinematics.reduced_jacobian_one(robot, task, q)

    def one(q, eta):
        s = robot.S(q)
        j = jbar(q)
        if at_rest:  # η = 0: the reduced bias is Sᵀ g(q) and there is no velocity term
            bias = s.T @ equations.gravity_one(model, q)
            drift = jnp.zeros(j.shape[0])
        else:
            bias = reduced.reduced_bias_one(model, q, eta)
            drift = jax.jvp(jbar, (q,), (s @ eta,))[1] @ eta  # J̇ u = J̄̇ η
        if obj is None:
            m = j.shape[0]
            w, m_o, bias_o = jnp.eye(m), jnp.zeros((m, m)), jnp.zeros(m)
        elif grasp == "point":  # forces only at the centre of mass: W constant, M_o = m I₂
            w = jnp.asarray(point_grasp_matrix(len(robot.arms)))
            m_o = obj.mass * jnp.eye(2)
            bias_o = obj.bias(jnp.zeros(3), gravity=model.gravity)[:2]
        else:
            r = grasp_offsets_one(robot, q)
            w = grasp_matrix_one(r)
            v_o = jnp.linalg.solve(w @ w.T, w @ (j @ eta))
            drift = drift - grasp_matrix_rate_one(r, v_o[2]).T @ v_o
            m_o = jnp.asarray(obj.mass_matrix(planar=True))
            bias_o = obj.bias(v_o, gravity=model.gravity)
        p = t.T @ reduced.reduced_mass_matrix_one(model, q) @ t
        return p, t.T @ reduced.input_matrix_one(model, q), t.T @ bias, j @ t, drift, w, m_o, bias_o

    return jnp.vectorize(one, signature="(n),(k)->(k,k),(k,k),(k),(r,k),(r),(m,r),(m,m),(m)")(q, eta)


def _interaction_mask(robot: MobileManipulator) -> np.ndarray:
    """1 on the platform block and on each arm's block of P, 0 on the platform–arm coupling blocks."""
    n_p = robot.platform.n_eta
    mask = np.zeros((robot.n_eta, robot.n_eta))
    mask[:n_p, :n_p] = 1.0
    for i in range(len(robot.arms)):
        s = robot.arm_eta_slice(i)
        mask[s, s] = 1.0
    return mask


def _solve(a: np.ndarray, b: np.ndarray, what: str) -> np.ndarray:
    """np.linalg.solve(a, b), batched; SingularConfigurationError with the message ``what`` (what is singular
    and why) and the first configuration where a is singular or not finite."""
    finite = np.isfinite(a).all(axis=(-2, -1)) & np.isfinite(b).all(axis=(-2, -1))
    if finite.all():
        try:
            return np.linalg.solve(a, b)
        except np.linalg.LinAlgError:
            pass
    singular = ~finite | ~np.isfinite(np.linalg.cond(np.where(finite[..., None, None], a, 0.0)))
    index = tuple(int(i) for i in np.argwhere(singular)[0]) if singular.any() else ()
    where = f" at configuration {index}" if index else ""
    raise SingularConfigurationError(f"{what}{where}")


def _finite_matrix(matrix: np.ndarray, what: str) -> np.ndarray:
    """The ellipsoid's matrix, or SingularConfigurationError where it is not finite."""
    bad = ~np.isfinite(matrix).all(axis=(-2, -1))
    if bad.any():
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        where = f" at configuration {index}" if index else ""
        raise SingularConfigurationError(
            f"{what}: the task's Jacobian is not finite{where} (its coordinates are singular as a representation "
            "there, see mobman.kinematics.representation_singular)"
        )
    return matrix


def _mv(a: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.einsum("...ij,...j->...i", a, v)


def _t(a: np.ndarray) -> np.ndarray:
    return np.swapaxes(a, -1, -2)


def _paper(terms: _Terms, tau_max: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 31–38: τ = Λ_o a_o + μ_o with u̇ = J⁺(Wᵀ a_o − drift), h = W⁺(M_o a_o + c_o + g_o) (pseudo-inverses:
    never flagged singular)."""
    j_plus, w_plus = np.linalg.pinv(terms.j), np.linalg.pinv(terms.w)
    lam = _solve(
        terms.q,
        terms.p @ j_plus @ _t(terms.w) + _t(terms.j) @ w_plus @ terms.m_o,
        "dynamic ellipsoid: the input matrix Q is singular",
    )  # eq. 34
    mu_rhs = terms.b - _mv(terms.p @ j_plus, terms.drift) + _mv(_t(terms.j) @ w_plus, terms.bias_o)
    mu = _solve(terms.q, mu_rhs[..., None], "dynamic ellipsoid: the input matrix Q is singular")[
        ..., 0
    ]  # eq. 35, corrected
    lam_bar, mu_bar = lam / tau_max[..., :, None], mu / tau_max  # eq. 36
    lam_pinv = np.linalg.pinv(lam_bar)
    outside = mu_bar - _mv(lam_bar @ lam_pinv, mu_bar)
    rho2 = 1.0 - np.sum(outside**2, axis=-1)
    matrix = np.sqrt(np.clip(rho2, 0.0, None))[..., None, None] * lam_pinv
    return -_mv(lam_pinv, mu_bar), matrix, rho2 >= 0.0, np.zeros(rho2.shape, dtype=bool)


CLOSED_CHAIN_SINGULAR = (
    "the closed-chain equations (mass matrix, task Jacobian, grasp matrix) are singular: an arm's Jacobian "
    "loses rank there (stretched or folded) and its hand forces are undetermined; the ellipsoid is that of their "
    "minimum-norm solution"
)
"""What a dynamic ellipsoid flagged ``singular`` is (:func:`closed_chain_matrices`)."""


def closed_chain_matrices(terms: _Terms) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward map of the closed chain: a_o = G τ + g₀, from P u̇ + Jᵀ h = Q τ − b, M_o a_o − W h = −(c_o + g_o),
    J u̇ − Wᵀ a_o = −drift (unknowns u̇, h, a_o). Returns (G, g₀, singular).

    Where the system is singular (an arm stretched or folded: its hand forces are undetermined) G and g₀ come
    from its minimum-norm least-squares solution (the pseudo-inverse), and ``singular`` (...) is True there:
    a valid configuration gets its degenerate answer, flagged, instead of a refusal."""
    n, r, m = terms.p.shape[-1], terms.j.shape[-2], terms.w.shape[-2]
    batch = terms.p.shape[:-2]
    a = np.zeros(batch + (n + r + m,) * 2)
    a[..., :n, :n], a[..., :n, n : n + r] = terms.p, _t(terms.j)
    a[..., n : n + m, n : n + r], a[..., n : n + m, n + r :] = -terms.w, terms.m_o
    a[..., n + m :, :n], a[..., n + m :, n + r :] = terms.j, -_t(terms.w)
    rhs = np.zeros(batch + (n + r + m, n + 1))
    rhs[..., :n, :n] = terms.q
    rhs[..., :, n] = np.concatenate([-terms.b, -terms.bias_o, -terms.drift], axis=-1)
    if not (np.isfinite(a).all() and np.isfinite(rhs).all()):
        raise SingularConfigurationError("dynamic ellipsoid: the closed-chain equations are not finite")
    size = n + r + m
    singular = np.asarray(np.linalg.cond(a) > 1 / (size * np.finfo(float).eps))
    flag = singular[..., None, None]
    regular = np.linalg.solve(np.where(flag, np.eye(size), a), rhs)  # the identity where singular
    sol = np.where(flag, np.linalg.pinv(a) @ rhs, regular)[..., -m:, :]
    return sol[..., :n], sol[..., n], singular


def _exact(terms: _Terms, tau_max: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The image of the torque ball |Z τ| ≤ 1 through the closed-chain forward map (and where it is singular)."""
    g, g0, singular = closed_chain_matrices(terms)
    matrix = g * tau_max[..., None, :]
    feasible = np.ones(matrix.shape[:-2], dtype=bool)
    return np.broadcast_to(g0, matrix.shape[:-1]), matrix, feasible, np.broadcast_to(singular, feasible.shape)


def dynamic_terms(
    model: DynamicModel,
    q: npt.ArrayLike,
    *,
    eta: npt.ArrayLike | None = None,
    obj: HeldObject | None = None,
    task: Task | None = None,
    interaction: bool = True,
    platform_fixed: bool = False,
    grasp: Grasp = "rigid",
) -> _Terms:
    """The matrices of eq. 16, 21, 22 in actuator coordinates (wheels, joints), batched over q and η.

    ``interaction=False`` zeroes the platform–arm blocks of P; ``platform_fixed=True`` keeps only the arms'
    coordinates (the platform braked); ``grasp``: how ``obj`` is held (see :func:`dynamic_ellipsoid`).
    """
    robot = model.robot
    q = robot.validate_q(q)
    if obj is not None:
        _check_held(robot, grasp, q)
        task = grasp_task(robot, grasp)
    task = robot.task if task is None else task
    task.check(robot)
    at_rest = eta is None
    eta = np.zeros(robot.n_eta) if eta is None else np.asarray(eta, dtype=float)
    if eta.shape[-1] != robot.n_eta or not np.all(np.isfinite(eta)):
        raise InputError(f"eta: expected {robot.n_eta} finite quasi-velocities, got shape {eta.shape}")
    raw = _dynamic_terms(model, task, obj, grasp, uses_wheels(robot, "dynamic"), at_rest, q, eta)
    terms = _Terms(*(np.asarray(x) for x in raw))
    _finite_matrix(terms.j, "dynamic ellipsoid")
    for name, value in (("reduced mass matrix P", terms.p), ("velocity and gravity terms", terms.b)):
        if not np.isfinite(value).all():
            raise SingularConfigurationError(
                f"dynamic ellipsoid: the {name} is not finite (check the inertials)"
            )
    p = terms.p if interaction else terms.p * _interaction_mask(robot)
    keep = np.arange(robot.platform.n_eta if platform_fixed else 0, robot.n_eta)
    return _Terms(
        p[..., keep[:, None], keep],
        terms.q[..., keep[:, None], keep],
        terms.b[..., keep],
        terms.j[..., keep],
        terms.drift,
        terms.w,
        terms.m_o,
        terms.bias_o,
    )


def dynamic_ellipsoid(
    model: DynamicModel,
    q: npt.ArrayLike,
    torque_limits: Sequence[float] | np.ndarray,
    *,
    eta: npt.ArrayLike | None = None,
    obj: HeldObject | None = None,
    platform_scale: float | npt.ArrayLike = 1.0,
    method: Method = "paper",
    interaction: bool = True,
    platform_fixed: bool = False,
    task: Task | None = None,
    grasp: Grasp = "rigid",
) -> Ellipsoid:
    """Dynamic task-space ellipsoid of accelerations (eq. 27–38), batched over q, η and ``platform_scale``.

    ``model``: a :class:`mobman.dynamics.DynamicModel`; ``torque_limits``: τ_max of every actuator
    (wheels right, left, then joints), N·m; ``platform_scale`` multiplies the wheel limits. ``eta``: the current
    quasi-velocities (None: at rest, eq. 27–30); velocity, Coriolis and gravity terms shift the ellipsoid (μ_o).
    ``obj``: a held object (planar robots, all arms grasp it; task (x_o, y_o, angle_o)); otherwise ``task``
    (default: the robot's). ``grasp="point"``: the hands hold the object's centre of mass through pivots (all
    tool points within 1 mm of one point), forces only, W = [I₂ I₂ …], task (x_o, y_o).
    ``method``: "paper" (eq. 31–38) or "exact" (image of the torque ball).
    ``interaction=False`` drops the platform–arm inertial coupling (the paper's §4.3 simplification).
    ``platform_fixed=True``: the platform braked (its wheel torques removed): the fixed-base multi-arm system.
    """
    robot = model.robot
    if method not in ("paper", "exact"):
        raise InputError(f"method must be 'paper' or 'exact', got {method!r}")
    limits = np.asarray(torque_limits, dtype=float)
    if limits.shape != (robot.n_eta,) or not np.all(np.isfinite(limits)) or np.any(limits <= 0):
        raise InputError(
            f"torque_limits: expected {robot.n_eta} finite values > 0 N·m (wheels, then joints), got {torque_limits!r}"
        )
    scale = _scale(platform_scale, "platform_scale")
    if np.any(scale <= 0):
        raise InputError("platform_scale must be > 0 for the dynamic ellipsoid")
    terms = dynamic_terms(
        model,
        q,
        eta=eta,
        obj=obj,
        task=task,
        interaction=interaction,
        platform_fixed=platform_fixed,
        grasp=grasp,
    )
    is_platform = np.arange(robot.n_eta) < robot.platform.n_eta
    tau_max = limits * np.where(is_platform, scale[..., None], 1.0)
    if platform_fixed:
        tau_max = tau_max[..., ~is_platform]
    center, matrix, feasible, singular = (_paper if method == "paper" else _exact)(terms, tau_max)
    names: tuple[str, ...]
    if obj is not None:
        names = POINT_NAMES if grasp == "point" else OBJECT_NAMES
    else:
        names = (robot.task if task is None else task).names
    return Ellipsoid(center, matrix, names, feasible, singular)
