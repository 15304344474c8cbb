"""Closed-loop simulation of q̇ = S(q) η, η = law(q, t, ξ*(t), ξ̇*(t)): one compiled ``lax.scan``.

Integrators (``integrator=``):

``"lie"`` (default for a platform with a constant body twist, S(q_p) = R(θ) B: a differential drive, a
    skid-steer, a fixed base) — the commutator-free Lie-group Runge–Kutta method of
    order 4 of Celledoni, Marthinsen & Owren (*Future Gener. Comput. Syst.* 19, 2003;
    :data:`mobman.integration.CF4`) on SE(2) × Rⁿ, with the quasi-velocities η = (η_p, q̇_a) as body twists
    B η_p of the platform ((v, 0, ω) for a differential drive):
        X1 = η(q, t),               Y2 = q ∘ exp(h X1/2),           X2 = η(Y2, t + h/2),
        Y3 = q ∘ exp(h X2/2),       X3 = η(Y3, t + h/2),
        Y4 = Y2 ∘ exp(h (X3 − X1/2)), X4 = η(Y4, t + h),
        q_mid = q ∘ exp(h (3X1 + 2X2 + 2X3 − X4)/12),  q_next = q_mid ∘ exp(h (−X1 + 2X2 + 2X3 + 3X4)/12).
    exp of a body twist (v, 0, ω) is an exact arc of a circle (a line if ω = 0), so every step is the
    composition of two arcs driven at zero lateral velocity: the discrete platform path itself rolls without
    slipping — not only the velocities q̇ = S(q) η at the samples. ``result.info["q_mid"]`` holds the junction
    of the two arcs so that this can be checked. On the joints (an abelian group) the method is classical RK4.
``"rk4"`` — classical Runge–Kutta on q̇ = S(q) η, for any platform. Each stage velocity satisfies the
    constraints, but a step's chord does not exactly (the defect is O(h⁵) per step).
``"hold"`` — a digital controller with sample time h: η = law(q_k, t_k) is held constant over the step (zero-order
    hold) and the robot moves exactly under it — an arc of a circle for a differential drive (q_{k+1} =
    q_k ∘ exp(h η)), one RK4 step of q̇ = S(q) η at fixed η for other platforms. One law evaluation per step
    (the others take four); first order in h as an approximation of the continuous-time loop.

The law is evaluated at the sampled configuration and at the stages; the η recorded at t_k is the one of the
first stage (the control applied at t_k), and ξ(t_k) is recorded from the same evaluation. Measures are
computed after the run, batched over all samples.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import partial
from typing import Callable, Iterator, Sequence, cast

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import integration
from mobman.control.laws import Law
from mobman.control.references import Reference
from mobman.engine import runge_kutta
from mobman.engine.batched import across_cores
from mobman.errors import InputError, ModelError, SingularConfigurationError
from mobman.model.robot import MobileManipulator
from mobman.model.spatial import matvec
from mobman.model.tasks import Task

INTEGRATORS = ("auto", "lie", "rk4", "hold")
_MEASURE_SUFFIX = {"w": "yoshikawa", "w2": "inverse_condition", "w5": "eccentricity"}
_MEASURE_WHICH = ("system_normalized", "system", "arm")


@dataclass
class SimulationResult:
    """Samples at t_k = k dt, k = 0 … N − 1 (a leading batch axis first when batched).

    ``error`` = the controlled task's error e(ξ*, ξ) (ξ* − ξ for vector tasks, position difference and
    rotation vector log(R* Rᵀ) for a :class:`~mobman.model.tasks.Pose`) over the controlled task
    (``law.controlled_task(task)``: the task stacked with the extra rows for
    :class:`~mobman.control.laws.AugmentedJacobian`); ``measures`` name → values; ``info`` the fields of the
    law's :class:`~mobman.control.laws.LawStep` per step but η, ``saturated`` and ``damped`` (``damping`` λ²,
    ``sigma_min``, ``limit_ratio``, ``P``, ``det``, …); ``law`` the law of an unbatched run (None for a batch
    of laws).
    """

    t: np.ndarray
    q: np.ndarray
    eta: np.ndarray
    xi: np.ndarray
    xi_star: np.ndarray
    error: np.ndarray
    measures: dict[str, np.ndarray]
    saturated: np.ndarray
    damped: np.ndarray
    info: dict[str, np.ndarray] = field(default_factory=dict)
    robot: MobileManipulator | None = None
    task: Task | None = None
    law: Law | None = None

    @property
    def dt(self) -> float:
        return float(self.t[1] - self.t[0])

    @property
    def batched(self) -> bool:
        return self.q.ndim == 3

    def run(self, index: int) -> "SimulationResult":
        """The ``index``-th run of a batched result (an unbatched result)."""
        if not self.batched:
            raise InputError("run(index): this result is not batched")

        def pick(x):
            return {k: pick(v) for k, v in x.items()} if isinstance(x, dict) else np.asarray(x)[index]

        batched = ("q", "eta", "xi", "xi_star", "error", "measures", "saturated", "damped", "info")
        return replace(self, **{name: pick(getattr(self, name)) for name in batched})


def _unicycle_exp(robot: MobileManipulator, q: jnp.ndarray, u: jnp.ndarray) -> jnp.ndarray:
    """q ∘ exp(u) for the increment u = h X = (h η_p, Δq_a): an exact arc of a platform with a constant body
    twist (``platform.displace``), the joints moved by Δq_a."""
    n_p, n_e = robot.n_platform, robot.platform.n_eta
    return jnp.concatenate([robot.platform.displace(q[:n_p], u[:n_e]), q[n_p:] + u[n_e:]])


def _step(robot, integrator, control, q, t, h):
    """One integration step: (q_next, q_mid or None, η at t, the law's info at t). ``"lie"``: the
    commutator-free method :data:`~mobman.integration.CF4` with the slopes k_i = η_i in the Lie algebra and
    the exact arcs of the platform as exponential; ``"rk4"``: :data:`~mobman.integration.RK4` on
    q̇ = S(q) η."""
    lie = integrator == "lie"

    def f(s, y):
        eta, info = control(y, s)
        return (eta if lie else matvec(robot.S(y), eta)), (eta, info)

    tab, exp = (integration.CF4, partial(_unicycle_exp, robot)) if lie else (integration.RK4, None)
    q_next, junctions, (eta, info) = runge_kutta.step_path(tab, f, q, t, h, exp=exp, has_aux=True)
    first = jax.tree.map(lambda a: a[0], (eta, info))
    return (q_next, junctions[0] if lie else None, *first)


def _hold(robot, q, eta, h):
    """q after h seconds at constant η (zero-order hold): exact for a platform with a constant body twist
    (``platform.constant_body_twist``: differential drive, skid-steer, fixed base), RK4 otherwise."""
    if robot.platform.constant_body_twist:
        return _unicycle_exp(robot, q, h * eta)
    return integration.step(integration.RK4, lambda t, y: matvec(robot.S(y), eta), q, 0.0, h)


def _trajectory(robot, task, integrator, n, dt, reference, law, q0, k0):
    """n samples from q0 at t = k0 dt (one configuration, one law)."""

    ctask = law.controlled_task(task)

    def control(q, t):
        xs, xsd = reference._one(t)
        result = law(robot, task, q, t, xs, xsd)
        # (ξ*, ξ) as one entry: ξ as the law computes it (XLA evaluates it once), recorded here rather than
        # recomputed after the run, without one more output buffer per step (see _block_steps)
        xi_pair = jnp.stack([xs, ctask.value(robot, q, robot.frames(q))])
        return result.eta, dict(result.recorded(), xi_pair=xi_pair)

    def step(q, k):
        if integrator == "hold":
            eta, info = control(q, k * dt)
            q_next, q_mid = _hold(robot, q, eta, dt), None
        else:
            q_next, q_mid, eta, info = _step(robot, integrator, control, q, k * dt, dt)
        pair = info.pop("xi_pair")
        if q_mid is not None:
            info["q_mid"] = q_mid
        return q_next, {"q": q, "eta": eta, "xi_pair": pair, "info": info}

    steps = _block_steps(robot, reference) if jax.default_backend() == "cpu" else n
    blocks = -(-n // steps)

    def block(q, k):
        return jax.lax.scan(step, q, k + jnp.arange(steps, dtype=float))

    q_end, out = jax.lax.scan(block, q0, k0 + steps * jnp.arange(blocks, dtype=float))
    out = jax.tree.map(lambda a: a.reshape((blocks * steps,) + a.shape[2:]), out)
    if n % steps:  # the last block ran past sample n − 1: the state after n steps is its sample n
        q_end = out["q"][n]
    return q_end, jax.tree.map(lambda a: a[:n], out)


def _block_steps(robot: MobileManipulator, reference: Reference) -> int:
    """Steps per inner scan. XLA's CPU runtime runs a loop body's kernels one after the other on the calling
    thread only when every buffer they touch is at most 512 bytes or there are at most 8 of them; otherwise
    it schedules them as a task graph over a thread pool, which costs more than these tiny kernels. The
    recorded samples of a block (q, η and the pair (ξ*, ξ): at most max(n_q, 2m) numbers a step each) are
    kept under that size, and so is the block's slice of the step indices; the outer scan over blocks writes
    them into the whole run's arrays. (On a GPU the run is one block: there the nested loop only added
    launches, 10 % on an H200.)"""
    return max(1, 64 // max(robot.n_q, 2 * reference.dim))


@partial(jax.jit, static_argnums=(0, 1, 2, 3, 8, 9))
def _run(robot, task, integrator, n, dt, reference, law, q0, batch_law, batch_q, k0):
    fn = partial(_trajectory, robot, task, integrator, n, dt, reference)
    if batch_law or batch_q:
        fn = jax.vmap(fn, in_axes=(0 if batch_law else None, 0 if batch_q else None, None))
    return fn(law, q0, k0)


_run_shared = across_cores({7: 1}, min_share=4)(_run)
""":func:`_run` for a batch of initial configurations (one law): the runs shared between the CPU cores."""


def _stack_laws(laws: Sequence) -> object:
    try:
        return jax.tree.map(lambda *xs: jnp.stack([jnp.asarray(x, dtype=float) for x in xs]), *laws)
    except (ValueError, TypeError) as exc:
        raise ModelError(f"laws in a batch must differ only in their gains and damping: {exc}") from None


def parse_measure_names(names: Sequence[str]) -> list[tuple[str, str, str]]:
    """``<which>_<w|w2|w5>`` measure names as (name, which, measure key); an InputError names a bad one."""
    parsed = []
    for name in names:
        which, _, suffix = name.rpartition("_")
        if which not in _MEASURE_WHICH or suffix not in _MEASURE_SUFFIX:
            raise InputError(
                f"measures: {name!r} is not <which>_<measure> with which in {', '.join(_MEASURE_WHICH)} "
                f"and measure in {', '.join(_MEASURE_SUFFIX)} (e.g. system_w5)"
            )
        parsed.append((name, which, _MEASURE_SUFFIX[suffix]))
    return parsed


_MEASURE_CHUNK = 1024
"""Configurations per compiled call of :func:`compute_measures` (the last chunk is padded): one compilation
serves every run length and batch size."""


@partial(jax.jit, static_argnums=(0, 1, 2))
def _measure_chunk(robot, task, which, q):
    from mobman import manipulability as mp
    from mobman.control.criteria import measure_jacobian

    return jax.vmap(lambda qq: mp.measures_one(measure_jacobian(robot, qq, task, which)))(q)


def compute_measures(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task, names: Sequence[str]
) -> dict[str, np.ndarray]:
    """Manipulability measures named ``<which>_<w|w2|w5>`` along a (batched) path of configurations."""
    parsed = parse_measure_names(names)
    q = np.asarray(q, dtype=float)
    flat = q.reshape(-1, q.shape[-1])
    if not len(flat):
        raise InputError(f"measures: q holds no configuration (shape {q.shape})")
    pad = -len(flat) % _MEASURE_CHUNK
    chunks = np.concatenate([flat, np.repeat(flat[-1:], pad, axis=0)]).reshape(
        -1, _MEASURE_CHUNK, q.shape[-1]
    )
    out: dict[str, np.ndarray] = {}
    cache: dict[str, dict] = {}
    for name, which, measure in parsed:
        if which == "system_normalized" and robot.velocity_limits is None:
            raise ModelError(f"measures: {name} needs velocity limits, {robot.name} has none")
        if which not in cache:
            parts = [_measure_chunk(robot, task, which, c) for c in chunks]
            cache[which] = {k: np.concatenate([np.asarray(p[k]) for p in parts]) for k in parts[0]}
        out[name] = cache[which][measure][: len(flat)].reshape(q.shape[:-1])
    return out


@dataclass(frozen=True)
class _Setup:
    """A validated request of :func:`simulate`: what every compiled piece of the run takes."""

    robot: MobileManipulator
    task: Task
    ctask: Task
    integrator: str
    n: int
    dt: float
    reference: Reference
    law: object
    q0: jnp.ndarray
    batch_law: bool
    batch_q: bool
    measures: tuple[str, ...]

    @property
    def axis(self) -> int:
        """The time axis of the recorded arrays (1 after a batch axis)."""
        return 1 if (self.batch_law or self.batch_q) else 0

    @property
    def laws(self) -> int:
        """The number of laws of a batch of laws (1 for one law)."""
        return int(jax.tree.leaves(self.law)[0].shape[0]) if self.batch_law else 1


def _setup(
    robot: MobileManipulator,
    task: Task | None,
    law: Law | Sequence[Law],
    reference: Reference,
    q0: npt.ArrayLike,
    duration: float,
    dt: float,
    measures: Sequence[str],
    integrator: str,
) -> _Setup:
    task = robot.task if task is None else task
    task.check(robot)
    if integrator not in INTEGRATORS:
        raise InputError(f"integrator {integrator!r} not one of {', '.join(INTEGRATORS)}")
    if integrator == "auto":
        integrator = "lie" if robot.platform.constant_body_twist else "rk4"
    if integrator == "lie" and not robot.platform.constant_body_twist:
        raise InputError(
            f"integrator 'lie' needs a platform with a constant body twist (S = R(θ) B: differential, "
            f"skid_steer, fixed), {robot.name} has a {type(robot.platform).__name__}"
        )
    for name, value in (("duration", duration), ("dt", dt)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0 s, got {value!r}")
    n = int(round(duration / dt)) + 1
    batch_law = isinstance(law, (list, tuple))
    laws = list(law) if isinstance(law, (list, tuple)) else [cast(Law, law)]
    if not laws:
        raise InputError("law: give one law or a non-empty list of laws")
    if not all(isinstance(one, Law) for one in laws):
        raise InputError("law: a control law (mobman.control.laws) or a list of them")
    if not isinstance(reference, Reference):
        raise InputError(
            f"reference: a reference (mobman.control.references), got {type(reference).__name__}"
        )
    ctask = laws[0].controlled_task(task)
    if reference.dim != ctask.dim:
        raise ModelError(
            f"reference has {reference.dim} components, the controlled task {ctask.names} has {ctask.dim}"
        )
    q0 = robot.validate_q(q0)
    if q0.ndim > 2:
        raise InputError(f"q0: one configuration (n_q,) or a batch (B, n_q), got shape {q0.shape}")
    batch_q = q0.ndim == 2
    if batch_law and batch_q and len(laws) != q0.shape[0]:
        raise InputError(f"q0 batch ({q0.shape[0]}) and law batch ({len(laws)}) must have the same size")
    law_arg = _stack_laws(laws) if batch_law else law
    parse_measure_names(measures)
    return _Setup(
        robot,
        task,
        ctask,
        integrator,
        n,
        float(dt),
        reference,
        law_arg,
        jnp.asarray(q0),
        batch_law,
        batch_q,
        tuple(measures),
    )


SCAN_SAMPLES = 1024
MIN_SCAN_STEPS = 16
"""Most samples (steps times the runs of a batch, at least one step) of one compiled call. A compiled loop runs
to its end before Python sees a signal, so a run is computed in calls of this size and Ctrl-C stops it within
one call: TIAGo's QP law takes about 1.5 ms a step, 0.4 s a call (the cost of the calls on a cheap law:
``benchmarks/control.py``)."""


def _scan_steps(setup: _Setup, chunk: int) -> int:
    """Steps of each compiled call computing pieces of ``chunk`` samples: the fewest calls of at most
    :data:`SCAN_SAMPLES` samples each, of equal length (the last call runs past the piece by fewer steps than
    there are calls)."""
    runs = max(int(np.prod(setup.q0.shape[:-1])) if setup.batch_q else 1, setup.laws)
    most = max(MIN_SCAN_STEPS, SCAN_SAMPLES // runs)
    return -(-chunk // -(-chunk // most))


def _pieces(setup: _Setup, chunk: int) -> Iterator[tuple[int, dict]]:
    """The run as consecutive pieces (k0, recorded arrays of samples k0 … k0 + chunk − 1, NumPy). Each piece
    is joined from calls of the same compiled scan (:func:`_scan_steps`), each continuing from the state the
    previous one ended in (the law and the reference are functions of (q, t) only, so a call computes the
    whole run's samples); between calls Python answers a signal (Ctrl-C). The last piece is cut at sample
    n − 1."""
    run = _run_shared if setup.batch_q and not setup.batch_law else _run
    steps = _scan_steps(setup, chunk)
    axis = setup.axis
    q, k, k0 = setup.q0, 0, 0
    if setup.batch_law and not setup.batch_q:  # a batch of laws from one q0: one state per law from the start
        q = jnp.broadcast_to(jnp.asarray(q), (setup.laws, *np.shape(q)))
    held: list[dict] = []
    while k0 < setup.n:
        wanted = min(chunk, setup.n - k0)
        while sum(part["q"].shape[axis] for part in held) < wanted:
            q, out = run(
                setup.robot,
                setup.task,
                setup.integrator,
                steps,
                setup.dt,
                setup.reference,
                setup.law,
                q,
                setup.batch_law,
                setup.batch_q or setup.batch_law,
                float(k),
            )
            held.append(jax.tree.map(np.asarray, out))
            k += steps
        joined = held[0] if len(held) == 1 else jax.tree.map(lambda *xs: np.concatenate(xs, axis=axis), *held)
        cut, rest = ((slice(None),) * axis + (part,) for part in (slice(0, wanted), slice(wanted, None)))
        yield k0, jax.tree.map(lambda x, cut=cut: x[cut], joined)
        held = [jax.tree.map(lambda x, rest=rest: x[rest], joined)] if k - k0 > wanted else []
        k0 += wanted


def _result(setup: _Setup, k0: int, out: dict) -> SimulationResult:
    """The samples k0, k0 + 1, … recorded in ``out`` as a result; raises SingularConfigurationError at the
    first non-finite state or control."""
    q_path = out["q"]
    finite = np.all(np.isfinite(q_path), axis=-1) & np.all(np.isfinite(out["eta"]), axis=-1)
    if not np.all(finite):
        bad = np.argwhere(~finite)[0]
        bad[-1] += k0
        raise SingularConfigurationError(
            f"simulation produced non-finite velocities at t = {bad[-1] * setup.dt:g} s (sample {tuple(int(i) for i in bad)}): "
            "the law met a singular configuration (give it damping > 0) or a non-finite reference or criterion"
        )
    xi_star, xi = out["xi_pair"][..., 0, :], out["xi_pair"][..., 1, :]
    info = dict(out["info"])
    robot, task = setup.robot, setup.task
    return SimulationResult(
        t=(k0 + np.arange(q_path.shape[setup.axis])) * setup.dt,
        q=q_path,
        eta=out["eta"],
        xi=xi,
        xi_star=xi_star,
        error=np.asarray(setup.ctask.error(xi_star, xi)),
        measures=compute_measures(robot, q_path, task, setup.measures) if setup.measures else {},
        saturated=info.pop("saturated"),
        damped=info.pop("damped"),
        info=info,
        robot=robot,
        task=task,
        law=None if setup.batch_law else cast(Law, setup.law),
    )


def simulate(
    robot: MobileManipulator,
    task: Task | None,
    law: Law | Sequence[Law],
    reference: Reference,
    q0: npt.ArrayLike,
    duration: float,
    dt: float,
    measures: Sequence[str] = (),
    integrator: str = "auto",
    progress: Callable[[float], None] | None = None,
    chunk: int = 2000,
) -> SimulationResult:
    """Simulate the closed loop from q0 during ``duration`` with step ``dt`` (one compiled scan).

    Batching: ``q0`` of shape (B, n_q) and/or ``law`` a sequence of B laws differing only in gains run as
    one vmapped call; every array of the result then has a leading axis B. ``measures``: names such as
    ``"arm_w5"``, ``"system_w"``, ``"system_normalized_w5"``. ``progress(fraction)``, if given, is called
    between chunks of ``chunk`` steps (the same compiled chunk is reused). Raises
    :class:`~mobman.SingularConfigurationError` if the run produced non-finite values (an undamped law
    at a singular configuration).
    """
    setup = _setup(robot, task, law, reference, q0, duration, dt, measures, integrator)
    chunk = setup.n if progress is None else max(1, min(chunk, setup.n))
    pieces = []
    for k0, out in _pieces(setup, chunk):
        pieces.append(out)
        if progress is not None:
            progress(min(k0 + chunk, setup.n) / setup.n)
    if len(pieces) == 1:
        return _result(setup, 0, pieces[0])
    return _result(setup, 0, jax.tree.map(lambda *xs: np.concatenate(xs, axis=setup.axis), *pieces))


def simulate_pieces(
    robot: MobileManipulator,
    task: Task | None,
    law: Law | Sequence[Law],
    reference: Reference,
    q0: npt.ArrayLike,
    duration: float,
    dt: float,
    measures: Sequence[str] = (),
    integrator: str = "auto",
    chunk: int = 100_000,
) -> Iterator[SimulationResult]:
    """The run of :func:`simulate` (same arguments) as consecutive results of ``chunk`` samples each (the
    last one shorter), computed one after the other so that only one piece is in memory at a time: for
    runs too long to hold whole. Concatenated along time they are :func:`simulate`'s result (each piece
    continues from the state the previous one ended in; its ``t`` holds the absolute times)."""
    if not (isinstance(chunk, (int, np.integer)) and chunk >= 2):
        raise InputError(f"chunk must be an integer ≥ 2 samples, got {chunk!r}")
    setup = _setup(robot, task, law, reference, q0, duration, dt, measures, integrator)
    for k0, out in _pieces(setup, min(int(chunk), setup.n)):
        yield _result(setup, k0, out)


__all__ = [
    "INTEGRATORS",
    "SimulationResult",
    "compute_measures",
    "simulate",
    "simulate_pieces",
]
