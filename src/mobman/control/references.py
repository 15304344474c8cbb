"""Operational references ξ*(t) with their time derivatives ξ̇*(t).

Every reference is a frozen dataclass and a JAX pytree (its numbers are leaves: a new ellipse does not
recompile the simulation) with a
``dim`` and ``__call__(t) -> (xi_star, xi_star_dot)``; ``t`` is a scalar or an array of times (the outputs
then have shape ``t.shape + (dim,)``). Before t = 0 a reference holds its initial value, after its end it
holds its final value (with zero velocity), except the periodic :class:`Ellipse`.

Pose references (:class:`PoseReference`, :class:`PoseFunctionReference`) are for a
:class:`~mobman.model.tasks.Pose` task: ξ* = (p*, log R*) and ξ̇* = (ṗ*, ω*), the linear and the world-frame
angular velocity (not the derivative of the rotation vector).

Timing laws s(τ), τ ∈ [0, 1] (Biagiotti & Melchiorri, *Trajectory planning for automatic machines*, §2.1):
``linear`` s = τ (constant speed), ``cubic`` s = 3τ² − 2τ³, ``quintic`` s = 10τ³ − 15τ⁴ + 6τ⁵ (zero velocity
— and, quintic, zero acceleration — at both ends).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import checks
from mobman.control._tree import pytree
from mobman.errors import ModelError
from mobman.model import so3
from mobman.model.spatial import matmul, matvec

TIMINGS = ("linear", "cubic", "quintic")

MIN_TIME = 1e-3
"""Shortest duration or period of a reference (s): a shorter one asks for velocities no robot has (a line's
v = Δ/duration, an ellipse's 2π a/period) and, below float64's range, for infinite ones."""


def time_scale(value: float, name: str, owner: str) -> float:
    """``value`` as a duration or period of at least :data:`MIN_TIME` seconds (one-line ModelError)."""
    number = checks.positive(value, name, owner)
    if number < MIN_TIME:
        raise ModelError(f"{owner}: {name} must be at least {MIN_TIME:g} s, got {value!r}")
    return number


def _vector(value: npt.ArrayLike, name: str, owner: str, size: int | None = None) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(value, dtype=float))
    if arr.ndim != 1 or (size is not None and arr.size != size):
        raise ModelError(
            f"{owner}: {name} must be a vector of {size or 'one or more'} numbers, got {value!r}"
        )
    if not np.all(np.isfinite(arr)):
        raise ModelError(f"{owner}: {name} must be finite, got {value!r}")
    return arr


def _check_timing(timing: str, owner: str) -> None:
    if timing not in TIMINGS:
        raise ModelError(f"{owner}: timing {timing!r} not supported; allowed: {', '.join(TIMINGS)}")


def timing_law(tau: jnp.ndarray, timing: str) -> tuple[jnp.ndarray, jnp.ndarray]:
    """s(τ) and ds/dτ for τ already clipped to [0, 1]."""
    if timing == "linear":
        return tau, jnp.ones_like(tau)
    if timing == "cubic":
        return tau * tau * (3.0 - 2.0 * tau), 6.0 * tau * (1.0 - tau)
    return tau**3 * (10.0 + tau * (-15.0 + 6.0 * tau)), 30.0 * tau**2 * (1.0 - tau) ** 2


@dataclass(frozen=True, eq=False)
class Reference:
    """Base class: subclasses define ``dim`` and ``_one(t)`` for a scalar t."""

    @property
    def dim(self) -> int:
        raise NotImplementedError

    def _one(self, t: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray]:
        raise NotImplementedError

    def __call__(self, t: npt.ArrayLike) -> tuple[jnp.ndarray, jnp.ndarray]:
        """(ξ*(t), ξ̇*(t)), each of shape ``jnp.shape(t) + (dim,)``."""
        t = jnp.asarray(t, dtype=float)
        return jnp.vectorize(self._one, signature="()->(m),(m)")(t)


@pytree("start", "end", "duration")
@dataclass(frozen=True, eq=False)
class Line(Reference):
    """Straight segment from ``start`` to ``end`` in ``duration`` seconds with a timing law (any dimension)."""

    start: Sequence[float] | np.ndarray
    end: Sequence[float] | np.ndarray
    duration: float
    timing: str = "linear"

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _vector(self.start, "start", "Line"))
        object.__setattr__(self, "end", _vector(self.end, "end", "Line", len(self.start)))
        object.__setattr__(self, "duration", np.float64(time_scale(self.duration, "duration", "Line")))
        _check_timing(self.timing, "Line")

    @property
    def dim(self) -> int:
        return len(self.start)

    def _one(self, t):
        tau = jnp.clip(t / self.duration, 0.0, 1.0)
        inside = (t >= 0.0) & (t <= self.duration)
        s, ds = timing_law(tau, self.timing)
        delta = jnp.asarray(self.end) - jnp.asarray(self.start)
        return jnp.asarray(self.start) + s * delta, jnp.where(inside, ds / self.duration, 0.0) * delta


@pytree("center", "semi_axes", "period", "phase", "angle", "rotation")
@dataclass(frozen=True, eq=False)
class Ellipse(Reference):
    """Planar ellipse traversed at constant angular rate 2π/period (Bayle Fig. 5).

    x = c_x + a cos φ(t), y = c_y + b sin φ(t), φ(t) = phase + 2π t / period, then rotated by ``rotation``
    (rad) about the centre. A ``center`` with three values adds a constant third coordinate (z); ``angle``
    (rad) adds a constant orientation component (e.g. the heading ξ3 of ``bayle_planar``'s full task).
    """

    center: Sequence[float] | np.ndarray
    semi_axes: tuple[float, float]
    period: float
    phase: float = 0.0
    angle: float | None = None
    rotation: float = 0.0

    def __post_init__(self) -> None:
        center = _vector(self.center, "center", "Ellipse")
        if len(center) not in (2, 3):
            raise ModelError(f"Ellipse: center needs 2 (x, y) or 3 (x, y, z) values, got {len(center)}")
        object.__setattr__(self, "center", center)
        axes = _vector(self.semi_axes, "semi_axes", "Ellipse", 2)
        if min(axes) <= 0:
            raise ModelError(f"Ellipse: semi_axes must be > 0 m, got {axes}")
        object.__setattr__(self, "semi_axes", axes)
        object.__setattr__(self, "period", np.float64(time_scale(self.period, "period", "Ellipse")))
        object.__setattr__(self, "phase", _vector(self.phase, "phase", "Ellipse", 1)[0])
        object.__setattr__(self, "rotation", _vector(self.rotation, "rotation", "Ellipse", 1)[0])
        if self.angle is not None:
            object.__setattr__(self, "angle", _vector(self.angle, "angle", "Ellipse", 1)[0])

    @property
    def dim(self) -> int:
        return len(self.center) + (self.angle is not None)

    def _one(self, t):
        rate = 2.0 * jnp.pi / self.period
        phi = self.phase + rate * t
        a, b = self.semi_axes
        c, s = jnp.cos(self.rotation), jnp.sin(self.rotation)
        rot = jnp.stack([jnp.stack([c, -s]), jnp.stack([s, c])])
        # products as broadcast sums (spatial.matvec): XLA fuses them, a 2 × 2 matmul is a kernel of its own
        xy = jnp.asarray(self.center[:2]) + matvec(rot, jnp.stack([a * jnp.cos(phi), b * jnp.sin(phi)]))
        vxy = matvec(rot, jnp.stack([-a * rate * jnp.sin(phi), b * rate * jnp.cos(phi)]))
        extra = jnp.concatenate(
            [
                jnp.asarray(self.center)[2:],
                jnp.reshape(jnp.asarray([] if self.angle is None else self.angle, dtype=xy.dtype), (-1,)),
            ]
        )
        return jnp.concatenate([xy, extra]), jnp.concatenate([vxy, jnp.zeros_like(extra)])


@pytree("points", "durations")
@dataclass(frozen=True, eq=False)
class Polyline(Reference):
    """Through ``points`` (k × m), segment i lasting ``durations[i]``, each with the timing law.

    With ``cubic`` or ``quintic`` timing the reference stops at every vertex (C¹ / C² everywhere);
    ``linear`` timing has constant speed on each segment and a velocity jump at the vertices.
    """

    points: tuple[tuple[float, ...], ...]
    durations: tuple[float, ...]
    timing: str = "quintic"

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[0] < 2:
            raise ModelError(f"Polyline: points must be a k × m array with k ≥ 2, got shape {pts.shape}")
        if not np.all(np.isfinite(pts)):
            raise ModelError("Polyline: points must be finite")
        durations = _vector(self.durations, "durations", "Polyline", pts.shape[0] - 1)
        for d in durations:
            time_scale(d, "durations", "Polyline")
        _check_timing(self.timing, "Polyline")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "durations", durations)

    @property
    def dim(self) -> int:
        return len(self.points[0])

    @property
    def duration(self) -> float:
        return float(np.sum(self.durations))

    def _one(self, t):
        pts = jnp.asarray(self.points)
        ends = jnp.cumsum(jnp.asarray(self.durations))
        starts = ends - jnp.asarray(self.durations)
        i = jnp.clip(jnp.searchsorted(ends, t, side="left"), 0, len(self.durations) - 1)
        d = jnp.asarray(self.durations)[i]
        tau = jnp.clip((t - starts[i]) / d, 0.0, 1.0)
        inside = (t >= 0.0) & (t <= ends[-1])
        s, ds = timing_law(tau, self.timing)
        delta = pts[i + 1] - pts[i]
        return pts[i] + s * delta, jnp.where(inside, ds / d, 0.0) * delta


@pytree()
@dataclass(frozen=True, eq=False)
class FunctionReference(Reference):
    """A user function ξ*(t) of a scalar t written with ``jax.numpy``; ξ̇* by forward-mode autodiff."""

    fn: Callable[[jnp.ndarray], jnp.ndarray]
    size: int | None = None

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise ModelError("FunctionReference: fn must be a callable of t")
        if self.size is None:
            out = jax.eval_shape(lambda t: jnp.atleast_1d(self.fn(t)), jnp.zeros(()))
            object.__setattr__(self, "size", int(out.shape[0]))

    @property
    def dim(self) -> int:
        assert self.size is not None  # set in __post_init__
        return self.size

    def _one(self, t):
        fn = lambda tt: jnp.atleast_1d(jnp.asarray(self.fn(tt), dtype=float))  # noqa: E731
        return jax.jvp(fn, (t,), (jnp.ones_like(t),))


def _orientation(value: npt.ArrayLike, name: str, owner: str) -> np.ndarray:
    """A rotation matrix from a rotation vector (3 numbers) or a rotation matrix (3 × 3, orthonormal)."""
    arr = np.asarray(value, dtype=float)
    if arr.shape == (3,) and np.all(np.isfinite(arr)):
        return np.asarray(so3.exp(arr))
    if arr.shape == (3, 3) and np.all(np.isfinite(arr)):
        if np.abs(arr @ arr.T - np.eye(3)).max() > 1e-9 or np.linalg.det(arr) < 0:
            raise ModelError(f"{owner}: {name} is not a rotation matrix (R Rᵀ = I, det R = 1)")
        return arr
    raise ModelError(
        f"{owner}: {name} must be a finite rotation vector (3 numbers) or rotation matrix (3 × 3), "
        f"got {value!r}"
    )


def _pose_sample(p, r, p_dot, omega):
    """(ξ*, ξ̇*) of a pose sample: ((p, log R), (ṗ, ω))."""
    return jnp.concatenate([p, so3.log(r)]), jnp.concatenate([p_dot, omega])


@pytree("start", "end", "rotation_step", "duration")
@dataclass(frozen=True, eq=False)
class PoseReference(Reference):
    """A pose path for a :class:`~mobman.model.tasks.Pose` task: the position on the straight segment from
    p₀ to p₁ and the orientation on the geodesic (slerp) from R₀ to R₁, both at the same timing law
    s(t/duration):

        p*(t) = p₀ + s (p₁ − p₀),    R*(t) = exp(s φ) R₀,  φ = log(R₁ R₀ᵀ),
        ṗ*(t) = ṡ (p₁ − p₀),         ω*(t) = ṡ φ

    (R* turns about the fixed world axis of φ: the shortest rotation from R₀ to R₁, angle ≤ π; at exactly
    π the two directions are equally short and one is taken). ``start`` = (p₀, R₀) and ``end`` = (p₁, R₁),
    each orientation a rotation vector (3 numbers) or a rotation matrix (3 × 3); they are kept as
    (position, rotation matrix). ξ* = (p*, log R*), ξ̇* = (ṗ*, ω*).
    """

    start: tuple
    end: tuple
    duration: float
    timing: str = "quintic"
    rotation_step: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        owner = "PoseReference"
        for name in ("start", "end"):
            pose = getattr(self, name)
            if not isinstance(pose, (tuple, list)) or len(pose) != 2:
                raise ModelError(f"{owner}: {name} must be a pair (position, orientation), got {pose!r}")
            position = _vector(pose[0], f"{name} position", owner, 3)
            object.__setattr__(self, name, (position, _orientation(pose[1], f"{name} orientation", owner)))
        step = so3.log(self.end[1] @ self.start[1].T)
        object.__setattr__(self, "rotation_step", np.asarray(step))
        object.__setattr__(self, "duration", np.float64(time_scale(self.duration, "duration", owner)))
        _check_timing(self.timing, owner)

    @property
    def dim(self) -> int:
        return 6

    def _one(self, t):
        tau = jnp.clip(t / self.duration, 0.0, 1.0)
        inside = (t >= 0.0) & (t <= self.duration)
        s, ds = timing_law(tau, self.timing)
        rate = jnp.where(inside, ds / self.duration, 0.0)
        p0, phi = jnp.asarray(self.start[0]), jnp.asarray(self.rotation_step)
        delta = jnp.asarray(self.end[0]) - p0
        r = matmul(so3.exp(s * phi), jnp.asarray(self.start[1]))
        return _pose_sample(p0 + s * delta, r, rate * delta, rate * phi)


@pytree()
@dataclass(frozen=True, eq=False)
class PoseFunctionReference(Reference):
    """A user pose path t ↦ (p(t), R(t)) of a scalar t written with ``jax.numpy`` (R a 3 × 3 rotation
    matrix), for a :class:`~mobman.model.tasks.Pose` task. The velocity comes from forward-mode autodiff:
    ṗ, and ω = vee(Ṙ Rᵀ), the world-frame angular velocity."""

    fn: Callable[[jnp.ndarray], tuple[jnp.ndarray, jnp.ndarray]]

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise ModelError("PoseFunctionReference: fn must be a callable of t returning (p, R)")
        try:
            out = jax.eval_shape(self.fn, jnp.zeros(()))
            shapes = tuple(tuple(o.shape) for o in out)
        except (TypeError, ValueError) as exc:
            raise ModelError(f"PoseFunctionReference: fn(t) must return (p, R): {exc}") from None
        if shapes != ((3,), (3, 3)):
            raise ModelError(
                f"PoseFunctionReference: fn(t) must return p (3,) and R (3, 3), got shapes {shapes}"
            )

    @property
    def dim(self) -> int:
        return 6

    def _one(self, t):
        fn = lambda tt: tuple(jnp.asarray(x, dtype=float) for x in self.fn(tt))  # noqa: E731
        (p, r), (p_dot, r_dot) = jax.jvp(fn, (t,), (jnp.ones_like(t),))
        return _pose_sample(p, r, p_dot, so3.vee(matmul(r_dot, r.T)))


@pytree("parts")
@dataclass(frozen=True, eq=False)
class Stack(Reference):
    """References concatenated component-wise, e.g. Korayem's (x_e, y_e) line with a (α, β) line."""

    parts: tuple[Reference, ...]

    def __post_init__(self) -> None:
        parts = tuple(self.parts)
        if not parts or not all(isinstance(p, Reference) for p in parts):
            raise ModelError("Stack: give one or more references")
        object.__setattr__(self, "parts", parts)

    @property
    def dim(self) -> int:
        return sum(p.dim for p in self.parts)

    def _one(self, t):
        outs = [p._one(t) for p in self.parts]
        return jnp.concatenate([o[0] for o in outs]), jnp.concatenate([o[1] for o in outs])


def stack(*parts: Reference) -> Stack:
    """Concatenate references component-wise."""
    return Stack(tuple(parts))


__all__ = [
    "Ellipse",
    "FunctionReference",
    "Line",
    "MIN_TIME",
    "Polyline",
    "PoseFunctionReference",
    "PoseReference",
    "Reference",
    "Stack",
    "TIMINGS",
    "stack",
    "time_scale",
    "timing_law",
]
