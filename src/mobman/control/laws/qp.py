"""Whole-body control within the joint and wheel limits: Bayle's law (Bayle, Fourquet & Renaud 2003,
eq. 5–6) as a quadratic program over the quasi-velocities.

At each configuration the law solves

    min_η  ½ ‖J̄ η − (ξ̇* + W e)‖² + ½ μ ‖R⁻¹ (η − η_s)‖²,      η_s = −k R² Sᵀ ∇P,
    s.t.   |η_i| ≤ η_i,max                                    (the robot's velocity limits),
           |(T⁻¹ η_p)_j| ≤ u_j,max                            (each driven wheel's speed limit),
           γ (q_i,min − q_i) ≤ q̇_i ≤ γ (q_i,max − q_i)         (each joint with position limits),

with R = diag(η_max) when ``normalized`` (the identity otherwise), T the platform's actuator matrix
(η_p = T u, u the wheel speeds) and P the criterion. The wheel rows are exact where a velocity box is not: a
differential drive's per-wheel limit |v/r ± b ω/(2r)| ≤ u_max is a diamond in (v, ω), inside the box
(v_max, ω_max) through its corners that the robot's velocity limits give.

Without an active limit the solution is η = R (J̃ᵀJ̃ + μ I)⁻¹ (J̃ᵀ (ξ̇* + W e) + μ R⁻¹ η_s), J̃ = J̄ R: the
damped least-squares form of Bayle's law, which it approaches as μ → 0 (J̃ of full row rank): the minimum of
‖R⁻¹(η − η_s)‖ over J̄ η = ξ̇* + W e is η = R J̃⁺ (ξ̇* + W e) + R (I − J̃⁺J̃) R⁻¹ η_s, and
R⁻¹ η_s = −k (S R)ᵀ ∇P is Bayle's gradient in the scaled coordinates. The self-motion thus keeps Bayle's
gain k for any μ; the task is tracked to a relative O(μ / σ²) where σ is the smallest singular value of J̃.
The shared ``damping`` option adds its variable λ² (see :mod:`mobman.control.laws.base`) to μ.

The limits cut the task where a bound is active and the task velocity J̄ η falls short of the commanded
u = ξ̇* + W e by more than the program without bounds gives up (its O(μ / σ²)) plus a fraction
:data:`SHORTFALL` of the larger of ‖u‖ and Σ_i ‖J̄_i‖ |η_i| (the task velocities of the coordinates' motions,
each alone: a joint held back by its damper while the others make up for it cuts nothing) and :data:`FLOOR`.
``QPStep.saturated`` reports it, as Bayle's ``saturate`` option reports that it scaled η down: in both the
error then no longer obeys ė + W e = 0 and the tracking lags (a target out of reach is never reached).

The joint rows are a velocity damper (Faverjon & Tournassoud 1987, in its linear form): the distance
d = q_max − q obeys ḋ ≥ −γ d, so d(t) ≥ d(0) e^{−γ t} and a joint that starts within its limits never
reaches them; one outside moves back at γ times its excess (within its velocity limit). Under a zero-order
hold of step h (the ``"hold"`` integrator) the same holds exactly for the samples when γ h ≤ 1:
d_{k+1} ≥ (1 − γ h) d_k. The bounds are clipped into the velocity limits, so the program is always feasible.

With a ``scene`` (:class:`~mobman.model.scene.Scene`), the program also keeps the robot away from its
obstacles and from itself: a velocity damper ḋ ≥ −ξ (d − d_s)/(d_i − d_s) (Faverjon & Tournassoud 1987, the
holistic/NEO controller's form) on each of the ``collision_rows`` nearest pairs of the robot's collision
spheres (cover tolerance ``cover_tolerance``) closer than the influence distance d_i (``influence_distance``),
d_s the ``collision_margin`` and ξ the ``collision_gain`` (m/s); :mod:`mobman.control.avoidance` has the rows.
The velocity limits may leave no η that satisfies every damper (a start in collision, a pair pressed between
two obstacles): the damper rows share one slack s ≥ 0, ḋ + s ≥ −ξ (d − d_s)/(d_i − d_s), charged
½ :data:`SLACK_WEIGHT` s² in the objective, so the program stays feasible; ``QPStep.collision_slack`` reports s
(0 to the solver's precision whenever the dampers can be met).

The program is solved by qpax's primal–dual interior-point method (Mehrotra predictor–corrector), written in
JAX, for a fixed number of ``iterations``, in the variables η / η_max (each bound ±1) where the robot has
velocity limits. ``QPStep.residual`` is the largest entry of the final iterate's optimality conditions
(stationarity, feasibility, complementarity), in those variables: about 1e-8 and below once converged.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt
import qpax

from mobman.control import avoidance
from mobman.control._tree import pytree
from mobman.control.criteria import Criterion
from mobman.control.laws.base import Law, LawStep, apply_gain, damped_inverse, positive_gain
from mobman.errors import ModelError
from mobman.model.collision_model import CONTROL_TOLERANCE, CollisionModel
from mobman.model.scene import Scene
from mobman.model.spatial import matmul, matvec

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator
    from mobman.model.tasks import Task

ACTIVE = 1e-6
"""A constraint counts as active when its slack is under this fraction of its limit."""

SHORTFALL = 1e-2
"""The limits cut the task (``QPStep.saturated``) where they cost more than this fraction of the task's
velocities (module docstring)."""

FLOOR = 1e-6
"""The least task velocity (m/s or rad/s) the :data:`SHORTFALL` is a fraction of: at rest, the round-off of
the interior-point iterates cuts nothing."""

SLACK_WEIGHT = 1e4
"""The weight of the collision dampers' slack s in the objective (½ SLACK_WEIGHT s², s in m/s): against task
velocities of order 1, a damper gives way by 1e-4 of the task's pull only where the limits leave no choice."""

MIN_REGULARIZATION = 1e-7
"""The least μ: the interior-point iterates keep their slacks and multipliers above √eps ≈ 1.5e-8, a force
that a smaller μ lets move the self-motion (tested: μ ≥ 1e-7 gives the closed form to 1e-9)."""


@pytree(
    "eta",
    "damping",
    "sigma_min",
    "limit_ratio",
    "saturated",
    "damped",
    "P",
    "speed_limited",
    "joint_limited",
    "residual",
    "collision_limited",
    "collision_slack",
    "min_distance",
    "closest_pair",
)
@dataclass(frozen=True)
class QPStep(LawStep):
    """A :class:`~mobman.control.laws.base.LawStep` of the QP law. ``speed_limited``: a velocity or
    wheel-speed limit is active; ``joint_limited``: a joint's position bound (its damper) is active;
    ``residual``: the largest entry of the optimality conditions at the solution returned; ``P``: the
    criterion's value (None without one). ``saturated``: a bound is active and it cuts the task velocity
    J̄ η short of ξ̇* + W e (module docstring); η is the program's optimum, never scaled afterwards. With a
    scene: ``collision_limited`` (a collision damper is active), ``collision_slack`` (its slack s, m/s),
    ``min_distance`` (m) and ``closest_pair`` (its index in :func:`mobman.collision.pair_names`) of the nearest
    pair; None without a scene."""

    P: jnp.ndarray | None = None
    speed_limited: jnp.ndarray | None = None
    joint_limited: jnp.ndarray | None = None
    residual: jnp.ndarray | None = None
    collision_limited: jnp.ndarray | None = None
    collision_slack: jnp.ndarray | None = None
    min_distance: jnp.ndarray | None = None
    closest_pair: jnp.ndarray | None = None


class Bounds(NamedTuple):
    """The robot's limits in the program's variables x = η / scale (NumPy arrays, fixed for a robot):
    ``scale`` (the velocity limits, or ones), ``box`` (|x_i| ≤ box_i, inf where none), ``wheels`` (rows with
    |wheels x| ≤ 1, one per wheel-speed limit) and the position limits of each η's coordinate, ``lower`` and
    ``upper`` (±inf for the platform's quasi-velocities and unbounded joints)."""

    scale: np.ndarray
    box: np.ndarray
    wheels: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


def bounds(robot: MobileManipulator) -> Bounds:
    """The limits of ``robot`` that the QP law enforces (see the module docstring)."""
    n_p = robot.platform.n_eta
    limits = robot.velocity_limits
    scale = np.ones(robot.n_eta) if limits is None else np.asarray(limits, dtype=float)
    box = np.full(robot.n_eta, np.inf) if limits is None else np.ones(robot.n_eta)
    wheel_limits = robot.platform.actuator_speed_limits
    wheels = np.zeros((0, robot.n_eta))
    if wheel_limits is not None:
        wheels = np.zeros((len(wheel_limits), robot.n_eta))
        per_wheel = np.linalg.inv(robot.platform.actuator_matrix()) * scale[:n_p]
        wheels[:, :n_p] = per_wheel / np.asarray(wheel_limits, dtype=float)[:, None]
    unbounded = np.full((n_p, 2), [-np.inf, np.inf])
    position = np.concatenate([unbounded, np.asarray(robot.position_limits, dtype=float)[robot.n_platform :]])
    return Bounds(scale, box, wheels, position[:, 0], position[:, 1])


@pytree("W", "k", "criterion", "damping", "damping_threshold", "regularization", "limit_gain")
@dataclass(frozen=True, eq=False)
class WholeBodyQP(Law):
    """Bayle's law as a quadratic program with the robot's velocity, wheel-speed and joint limits as
    constraints (module docstring).

    ``W``: m-order positive-definite error gain (1/s); ``k`` ≥ 0 the self-motion gain of ``criterion``
    (None: no self-motion); ``regularization`` μ ≥ 1e-7; ``limit_gain`` γ > 0 (1/s) of the joints' velocity
    damper; ``iterations``: the interior-point iterations (20 solve TIAGo's programs to about 1e-10 in η).
    ``scene``: the obstacles to avoid (None: none, and no self-collision rows either); ``collision_margin``
    d_s ≥ 0 (m), ``influence_distance`` d_i > d_s (m), ``collision_gain`` ξ > 0 (m/s), ``collision_rows``
    the number of nearest pairs given a damper, ``cover_tolerance`` the sphere cover's τ (m).
    """

    kind = "qp"
    gains = ("W", "k")

    W: npt.ArrayLike = 1.0
    k: npt.ArrayLike = 0.0
    criterion: Criterion | None = None
    regularization: float = field(default=1e-4, kw_only=True)
    limit_gain: float = field(default=5.0, kw_only=True)
    iterations: int = field(default=20, kw_only=True)
    scene: Scene | None = field(default=None, kw_only=True)
    collision_margin: float = field(default=0.05, kw_only=True)
    influence_distance: float = field(default=0.3, kw_only=True)
    collision_gain: float = field(default=0.5, kw_only=True)
    collision_rows: int = field(default=32, kw_only=True)
    cover_tolerance: float = field(default=CONTROL_TOLERANCE, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "W", positive_gain(self.W, "W", "WholeBodyQP"))
        k = positive_gain(self.k, "k", "WholeBodyQP", allow_zero=True)
        if k.ndim:
            raise ModelError(f"WholeBodyQP: k must be a scalar ≥ 0, got {self.k!r}")
        object.__setattr__(self, "k", k)
        checks = {
            "regularization": (MIN_REGULARIZATION, "≥ 1e-7"),
            "limit_gain": (np.nextafter(0.0, 1.0), "> 0"),
            "collision_margin": (0.0, "≥ 0 m"),
            "influence_distance": (np.nextafter(0.0, 1.0), "> 0 m"),
            "collision_gain": (np.nextafter(0.0, 1.0), "> 0 m/s"),
            "cover_tolerance": (1e-3, "≥ 0.001 m"),
        }
        for name, (least, allowed) in checks.items():
            value = getattr(self, name)
            number = np.ndim(value) == 0 and np.asarray(value).dtype.kind in "iuf"
            if not (number and np.isfinite(value) and value >= least):
                raise ModelError(f"WholeBodyQP: {name} must be a finite number {allowed}, got {value!r}")
            object.__setattr__(self, name, np.float64(value))
        if self.influence_distance <= self.collision_margin:
            raise ModelError(
                f"WholeBodyQP: influence_distance must be > collision_margin ({self.collision_margin:g} m), "
                f"got {self.influence_distance:g}"
            )
        if not (isinstance(self.iterations, int) and 1 <= self.iterations <= 1000):
            raise ModelError(
                f"WholeBodyQP: iterations must be an integer in 1..1000, got {self.iterations!r}"
            )
        if not (isinstance(self.collision_rows, int) and 1 <= self.collision_rows <= 256):
            raise ModelError(
                f"WholeBodyQP: collision_rows must be an integer in 1..256, got {self.collision_rows!r}"
            )
        if self.scene is not None and not isinstance(self.scene, Scene):
            raise ModelError(f"WholeBodyQP: scene must be a Scene, got {type(self.scene).__name__}")
        if self.saturate:
            raise ModelError("WholeBodyQP: saturate does not apply, the program keeps η within the limits")
        self.check_options("WholeBodyQP")

    def collision_model(self, robot: MobileManipulator) -> CollisionModel:
        """The spheres and self pairs whose dampers the law adds (:func:`mobman.control.avoidance.control_model`
        at ``cover_tolerance`` and ``collision_margin``)."""
        return avoidance.control_model(robot, float(self.cover_tolerance), float(self.collision_margin))

    def __call__(
        self,
        robot: MobileManipulator,
        task: Task | None,
        q: jax.Array,
        t: jax.Array,
        xi_star: jax.Array,
        xi_star_dot: jax.Array,
    ) -> QPStep:
        task = robot.task if task is None else task
        limits = bounds(robot)
        frames = robot.frames(q)
        xi = task.value(robot, q, frames)
        weight = self.scale(robot)  # R
        jbar = task.reduced_jacobian(robot, q, frames)
        _, lam2, sigma_min = damped_inverse(jbar * weight, self.damping, self.damping_threshold)
        rhs = xi_star_dot + apply_gain(self.W, task.error(xi_star, xi), "W")
        eta_s = jnp.zeros(robot.n_eta, dtype=jbar.dtype)
        value = None
        criterion = self.criterion
        if criterion is not None:
            value, grad = jax.value_and_grad(lambda qq: criterion(robot, qq, task, xi_star))(q)
            eta_s = -jnp.asarray(self.k) * weight**2 * matvec(robot.S(q).T, grad)

        # the program in x = η / scale: ½ xᵀ H x + cᵀ x, G x ≤ h
        a = jbar * limits.scale
        metric = (limits.scale / weight) ** 2
        mu = self.regularization + lam2
        hessian = matmul(a.T, a) + mu * jnp.diag(metric)
        linear = -matvec(a.T, rhs) - mu * metric * eta_s / limits.scale
        # the joints' velocity damper, clipped into the velocity box
        q_eta = jnp.concatenate([jnp.zeros(robot.platform.n_eta, q.dtype), q[robot.n_platform :]])
        gain = self.limit_gain / limits.scale
        upper = jnp.clip(gain * (limits.upper - q_eta), -limits.box, limits.box)
        lower = jnp.clip(gain * (limits.lower - q_eta), -limits.box, limits.box)
        has_upper = np.isfinite(limits.box) | np.isfinite(limits.upper)
        has_lower = np.isfinite(limits.box) | np.isfinite(limits.lower)
        eye = np.eye(robot.n_eta)
        ones = np.ones(len(limits.wheels))
        g = jnp.asarray(np.concatenate([eye[has_upper], -eye[has_lower], limits.wheels, -limits.wheels]))
        h = jnp.concatenate([upper[has_upper], -lower[has_lower], ones, ones])
        n_limits = len(h)
        collisions = None
        if self.scene is not None:
            # the dampers −rows (scale x) − s ≤ −bound, s ≥ 0, over (x, s), s charged ½ SLACK_WEIGHT s²
            with jax.ensure_compile_time_eval():  # the cover is NumPy work on constants, even when traced
                model = self.collision_model(robot)
            collisions = avoidance.dampers(
                model,
                self.scene,
                q,
                self.collision_margin,
                self.influence_distance,
                self.collision_gain,
                self.collision_rows,
            )
            n_rows = len(collisions.bound)
            g = jnp.block(
                [
                    [g, jnp.zeros((n_limits, 1), g.dtype)],
                    [-collisions.rows * limits.scale, -jnp.ones((n_rows, 1), g.dtype)],
                    [jnp.zeros((1, robot.n_eta), g.dtype), -jnp.ones((1, 1), g.dtype)],
                ]
            )
            h = jnp.concatenate([h, -collisions.bound, jnp.zeros(1, h.dtype)])
            hessian = jnp.block(
                [
                    [hessian, jnp.zeros((robot.n_eta, 1), hessian.dtype)],
                    [jnp.zeros((1, robot.n_eta), hessian.dtype), jnp.full((1, 1), SLACK_WEIGHT)],
                ]
            )
            linear = jnp.concatenate([linear, jnp.zeros(1, linear.dtype)])
        solution, _, z, _, _, _ = qpax.solve_qp(
            hessian,
            linear,
            jnp.zeros((0, hessian.shape[0]), dtype=jbar.dtype),
            jnp.zeros(0, dtype=jbar.dtype),
            g,
            h,
            solver_tol=0.0,  # never met: the iterations are fixed (qpax floors its slacks near √eps)
            max_iter=self.iterations,
        )
        slack = h - matvec(g, solution)
        residual = jnp.max(
            jnp.concatenate(
                [
                    jnp.abs(matvec(hessian, solution) + linear + matvec(g.T, z)),
                    jnp.maximum(-slack, 0.0),
                    jnp.abs(z * slack),
                ]
            )
        )
        x = solution[: robot.n_eta]
        active_all = slack < ACTIVE * jnp.maximum(jnp.abs(h), 1.0)
        active = active_all[:n_limits]
        if collisions is not None:
            damping_rows = active_all[n_limits:-1] & collisions.active
            hessian, linear = hessian[: robot.n_eta, : robot.n_eta], linear[: robot.n_eta]
        # which bounds are the joints' dampers (tighter than the velocity box) rather than speed limits
        damper = jnp.concatenate(
            [(upper < limits.box)[has_upper], (lower > -limits.box)[has_lower], np.zeros(2 * len(ones), bool)]
        )
        # the task velocity the bounds give up: beyond that of the program without them
        free = jnp.linalg.solve(hessian, -linear)
        cut = jnp.linalg.norm(matvec(a, x) - rhs) - jnp.linalg.norm(matvec(a, free) - rhs)
        size = jnp.maximum(jnp.linalg.norm(rhs), jnp.sum(jnp.linalg.norm(a, axis=0) * jnp.abs(x)))
        eta = x * limits.scale
        ratio = jnp.zeros((), eta.dtype) if robot.velocity_limits is None else jnp.max(jnp.abs(x))
        bounded = jnp.any(active) if collisions is None else jnp.any(active) | jnp.any(damping_rows)
        return QPStep(
            eta,
            lam2,
            sigma_min,
            ratio,
            bounded & (cut > SHORTFALL * jnp.maximum(size, FLOOR)),
            lam2 > 0,
            P=value,
            speed_limited=jnp.any(active & ~damper),
            joint_limited=jnp.any(active & damper),
            residual=residual,
            **(
                {}
                if collisions is None
                else dict(
                    collision_limited=jnp.any(damping_rows),
                    collision_slack=solution[-1],
                    min_distance=collisions.distance,
                    closest_pair=collisions.pair,
                )
            ),
        )


__all__ = [
    "ACTIVE",
    "FLOOR",
    "MIN_REGULARIZATION",
    "SHORTFALL",
    "SLACK_WEIGHT",
    "Bounds",
    "QPStep",
    "WholeBodyQP",
    "bounds",
]
