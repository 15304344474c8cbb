"""Closed forms with SymPy: ξ = f(q), J, S, J̄ = J S, augmented Jacobians and rank-drop conditions.

The forward kinematics is built symbolically from the same model data the numerical path uses (platform,
mount transforms, joint origins, axes, offsets, couplings, tool transforms) — one SymPy path mirroring
:meth:`MobileManipulator.frames` and :meth:`Arm.link_poses`, never a per-robot formula. Numbers in the model
become exact where they are simple (integers, rationals with denominator ≤ 1000, rational multiples of π,
√2/2, √3/2), SymPy floats otherwise.

**Symbolic parameters.** ``params=("l1", "l2")`` turns robot parameters into positive symbols. The model
stores numbers, so the robot is rebuilt by its factory (the built-in robot of the same name by default, or
``factory=``) with each parameter moved by +1 and +2: every model number must be affine in the parameters
(lengths in translations are), and the coefficients found give the symbolic model exactly.

**Simplification.** Every entry goes through :func:`simplify` (``trigsimp``, which folds sin/cos sums into
sin/cos of angle sums, then ``factor_terms``). An orientation angle atan2(c sin u, c cos u) (c > 0) is u
itself (Bayle's ξ4 = q3 + q4, ξ5 = q5); other atan2 forms are differentiated on the chart of Bayle §2 where
the angle's cosine is positive, so √(cos² u) = cos u there.

**Rank drop.** :func:`rank_drop_conditions` uses the generic rank r (D or D̄ of :mod:`mobman.redundancy`):
when r = m the rank drops where det(J̄ J̄ᵀ) (det J̄ when square) vanishes, factored; when r < m (J̄ square or not
and never of full rank, e.g. Bayle's RRP example) it drops where every r × r minor vanishes. The condition is
returned as a minimal disjunctive normal form of equations ``factor = 0``.
"""

from __future__ import annotations

import inspect
import itertools
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Callable, Iterable, Sequence

import numpy as np
import sympy as sp

from mobman.errors import ModelError
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Task

Pose = tuple[sp.Matrix, sp.Matrix]


# --- numbers and parameters ------------------------------------------------------------------------


def exact(x: float) -> sp.Expr:
    """A model number as an exact SymPy number when it is simple, a SymPy Float otherwise."""
    x = float(x)
    for unit in (sp.Integer(1), sp.pi, sp.sqrt(2) / 2, sp.sqrt(3) / 2):
        ratio = Fraction(x / float(unit)).limit_denominator(1000)
        if abs(float(ratio) * float(unit) - x) <= 1e-12 * max(1.0, abs(x)):
            return sp.Rational(ratio.numerator, ratio.denominator) * unit
    return sp.Float(x)


def _sites(robot: MobileManipulator) -> dict[str, float]:
    """Every number of the model that the kinematics reads, keyed by where it is."""
    sites = {f"platform.{k}": v for k, v in robot.platform.parameters().items()}
    for i, (arm, mount) in enumerate(zip(robot.arms, robot.mounts)):
        sites.update({f"mount{i}[{k}]": v for k, v in enumerate(mount.transform)})
        sites.update({f"arm{i}.tool[{k}]": v for k, v in enumerate(arm.tool)})
        for j, joint in enumerate(arm.joints):
            sites.update({f"arm{i}.joint{j}.origin[{k}]": v for k, v in enumerate(joint.origin)})
            sites[f"arm{i}.joint{j}.offset"] = joint.offset
    return sites


class _Constants:
    """Exact or symbolic values of the model numbers (affine in the symbolic parameters)."""

    def __init__(self, robot: MobileManipulator, params: Sequence[str], factory: Callable | None):
        base = _sites(robot)
        self.values = {k: exact(v) for k, v in base.items()}
        self.symbols: dict[str, sp.Symbol] = {}
        if not params:
            return
        if factory is None:
            from mobman.model.robots import ROBOTS, design

            if robot.name not in ROBOTS:
                raise ModelError(
                    f"symbolic: robot {robot.name!r} is not built-in; give factory= to use params"
                )
            allowed = list(inspect.signature(ROBOTS[robot.name]).parameters)
            built_in = robot.name

            def designed(**values: float) -> MobileManipulator:  # its arms mounted as the robot's were
                return design(built_in, values)

            factory = designed
        else:
            allowed = list(inspect.signature(factory).parameters)
        defaults = dict(robot.parameters)
        missing = [p for p in params if p not in allowed or p not in defaults]
        if missing:
            raise ModelError(f"symbolic: unknown parameter(s) {missing} of {robot.name}; allowed: {allowed}")
        for name in params:  # a length (the factory rejects −1) is a positive symbol, anything else real
            try:
                factory(**{**defaults, name: -1.0})
                self.symbols[name] = sp.Symbol(name, real=True)
            except ModelError:
                self.symbols[name] = sp.Symbol(name, positive=True)
        for name in params:
            one = _sites(factory(**{**defaults, name: defaults[name] + 1.0}))
            two = _sites(factory(**{**defaults, name: defaults[name] + 2.0}))
            for key, v0 in base.items():
                slope = one[key] - v0
                if abs(two[key] - v0 - 2 * slope) > 1e-9 * max(1.0, abs(v0)):
                    raise ModelError(f"symbolic: model number {key} is not affine in parameter {name!r}")
                if abs(slope) > 1e-12:
                    self.values[key] += exact(slope) * (self.symbols[name] - exact(defaults[name]))
        self.values = {k: sp.expand(v) for k, v in self.values.items()}

    def transform(self, key: str) -> Pose:
        m = sp.Matrix(4, 4, [self.values[f"{key}[{k}]"] for k in range(16)])
        return m[:3, :3], m[:3, 3]


# --- the symbolic model ------------------------------------------------------------------------------


def coordinates(robot: MobileManipulator) -> tuple[sp.Symbol, ...]:
    """Real symbols for the generalized coordinates, named as ``robot.coordinate_names`` ('.' → '_')."""
    return tuple(sp.Symbol(n.replace(".", "_"), real=True) for n in robot.coordinate_names)


def _compose(a: Pose, b: Pose) -> Pose:
    """(R_a, p_a) ∘ (R_b, p_b), simplified entry by entry so angle sums fold as the chain grows."""
    return (a[0] * b[0]).applyfunc(simplify), (a[0] * b[1] + a[1]).applyfunc(simplify)


def _rotation(axis: Sequence[float], angle: sp.Expr) -> sp.Matrix:
    """Rodrigues' formula I + sin(a) K + (1 − cos a) K², as in :meth:`Joint.pose_after`."""
    x, y, z = (exact(v) for v in axis)
    k = sp.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return sp.eye(3) + sp.sin(angle) * k + (1 - sp.cos(angle)) * k * k


class SymbolicRobot:
    """The robot's kinematics in SymPy: coordinates ``q``, parameter symbols, frames, S and constraints.

    Frames are built per arm on first use and Jacobians are cached per task; :func:`model` caches whole
    instances, so the public functions share the work for one robot.
    """

    def __init__(self, robot: MobileManipulator, params: Sequence[str] = (), factory: Callable | None = None):
        self.robot = robot
        self.q = coordinates(robot)
        self.constants = _Constants(robot, tuple(params), factory)
        self.params = self.constants.symbols
        c, s = sp.cos(self.q[2]), sp.sin(self.q[2])
        self.platform_pose: Pose = (
            sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
            sp.Matrix([self.q[0], self.q[1], 0]),
        )
        self._links: dict[int, tuple[Pose, ...]] = {}
        self._jacobians: dict[Task, sp.Matrix] = {}

    def mount_pose(self, arm: int) -> Pose:
        """World pose of arm ``arm``'s mount (base) frame."""
        return _compose(self.platform_pose, self.constants.transform(f"mount{arm}"))

    def link_poses(self, arm: int) -> tuple[Pose, ...]:
        """World poses of arm ``arm``'s joint frames (after each motion), then its tool frame
        (mirrors :meth:`Arm.link_poses`: origin, then motion C q_a + offset about the axis)."""
        if arm not in self._links:
            spec = self.robot.arms[arm]
            pose = self.mount_pose(arm)
            coupling = spec.coupling_matrix
            motion = sp.Matrix(*coupling.shape, [exact(v) for v in coupling.ravel()]) * sp.Matrix(
                self.q[self.robot.arm_slice(arm)]
            )
            poses = []
            for j, joint in enumerate(spec.joints):
                pose = _compose(pose, self.constants.transform(f"arm{arm}.joint{j}.origin"))
                value = motion[j] + self.constants.values[f"arm{arm}.joint{j}.offset"]
                if joint.kind == "revolute":
                    pose = _compose(pose, (_rotation(joint.axis, value), sp.zeros(3, 1)))
                else:
                    pose = _compose(pose, (sp.eye(3), value * sp.Matrix([exact(v) for v in joint.axis])))
                poses.append(pose)
            poses.append(_compose(pose, self.constants.transform(f"arm{arm}.tool")))
            self._links[arm] = tuple(poses)
        return self._links[arm]

    def generic_rank(self, a: sp.Matrix, samples: int = 8, seed: int = 0) -> int:
        """Maximum numerical rank of a symbolic matrix of q over seeded random configurations (the same
        sampling and tolerance as :func:`mobman.redundancy.redundancy_report`, so it gives D or D̄)."""
        from mobman.kinematics import rank
        from mobman.redundancy import RTOL, sample_configurations

        values = {p: float(dict(self.robot.parameters)[n]) for n, p in self.params.items()}
        fn = sp.lambdify(self.q, a.subs(values), "numpy")
        q = sample_configurations(self.robot, samples, seed)
        evaluated = np.stack([np.asarray(fn(*row), dtype=float).reshape(a.shape) for row in q])
        return int(rank(evaluated, RTOL).max())

    def _platform_values(self) -> dict[str, sp.Expr]:
        return {k: self.constants.values[f"platform.{k}"] for k in self.robot.platform.parameters()}

    def S(self) -> sp.Matrix:
        """S(q) = diag(S_p(q_p), I) (Bayle §4.2), the platform's ``symbolic_S``."""
        p = self.robot.platform
        s_p = p.symbolic_S(self.q[: p.n_q], self._platform_values())
        n_a = self.robot.n_q - p.n_q
        return sp.diag(s_p, sp.eye(n_a)) if n_a else s_p

    def constraints(self) -> sp.Matrix:
        """G(q) with G S = 0 (Bayle §4.1), the platform's ``symbolic_constraints``."""
        p = self.robot.platform
        g_p = p.symbolic_constraints(self.q[: p.n_q], self._platform_values())
        return g_p.row_join(sp.zeros(g_p.rows, self.robot.n_q - p.n_q))

    # --- tasks ---------------------------------------------------------------------------------------

    def forward(self, task: Task | None = None) -> sp.Matrix:
        """ξ = f(q) for the task (the robot's own by default), as a column matrix: the task's own closed form
        (``task.symbolic(self)``), simplified entry by entry."""
        task = self.robot.task if task is None else task
        task.check(self.robot)
        return sp.Matrix([simplify(e) for e in task.symbolic(self)])

    def vector(self, values: Sequence[float]) -> sp.Matrix:
        """A column of model numbers as exact SymPy numbers (:func:`exact`)."""
        return sp.Matrix([exact(v) for v in values])

    def angle(self, y: sp.Expr, x: sp.Expr) -> sp.Expr:
        """atan2(y, x) of two rotation entries, as the angle u itself where (y, x) = c (sin u, cos u) with c > 0
        (a heading or elevation that follows a joint over the whole turn, equal to u modulo 2π)."""
        y, x = simplify(y), simplify(x)
        for factor in sp.Mul.make_args(y):
            if isinstance(factor, sp.sin):
                u = factor.args[0]
                c = sp.factor_terms(y / factor)
                if c.is_positive and sp.expand(x - c * sp.cos(u)) == 0:
                    return u
        return sp.atan2(y, x)

    def exact(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with its floating-point numbers made exact where they are simple (:func:`exact`)."""
        return expr.replace(lambda e: e.is_Float, lambda e: exact(float(e)))

    def jacobian(self, task: Task | None = None) -> sp.Matrix:
        """J = ∂f/∂q of the simplified ξ, simplified entry by entry (Bayle §3)."""
        task = self.robot.task if task is None else task
        if task not in self._jacobians:
            xi = self.forward(task)
            self._jacobians[task] = xi.jacobian(sp.Matrix(self.q)).applyfunc(_chart).applyfunc(simplify)
        return self._jacobians[task]

    def reduced_jacobian(self, task: Task | None = None) -> sp.Matrix:
        """J̄ = J S (Bayle eq. 2), simplified."""
        return (self.jacobian(task) * self.S()).applyfunc(simplify)

    def augmented_jacobian(self, task: Task) -> sp.Matrix:
        """[G(q); J_task(q)] — Korayem's augmented Jacobian (eq. 30) when the task stacks the EE rows and the
        extra rows; square (n_q × n_q) when the task has n_q − (number of constraints) rows."""
        return self.constraints().col_join(self.jacobian(task))


@lru_cache(maxsize=32)
def model(
    robot: MobileManipulator, params: tuple[str, ...] = (), factory: Callable | None = None
) -> SymbolicRobot:
    """The (cached) symbolic model of a robot with the given parameters kept as symbols."""
    return SymbolicRobot(robot, params, factory)


def _chart(expr: sp.Expr) -> sp.Expr:
    """Derivatives of atan2 on the chart where the angle's cosine is positive: √(u²) = |u| → u.

    Compound trigonometric arguments are replaced by fresh symbols while simplifying (the derivative of an
    angle is a rational function of sin u, cos u of a few angles u), which keeps ``trigsimp`` fast.
    """
    arguments = {f.args[0] for f in expr.atoms(sp.sin, sp.cos) if not f.args[0].is_Symbol}
    atoms = {u: sp.Dummy(f"u{i}", real=True) for i, u in enumerate(arguments)}
    expr = sp.trigsimp(sp.together(expr.subs(atoms)))
    return expr.replace(sp.Abs, lambda u: u).subs({v: u for u, v in atoms.items()})


def _linear_in_trig(expr: sp.Expr) -> bool:
    """True when no term has a product or power of sin/cos: nothing for ``trigsimp`` to fold."""
    for term in sp.Add.make_args(expr):
        factors = [f for f in sp.Mul.make_args(term) if f.has(sp.sin, sp.cos)]
        if len(factors) > 1 or (factors and not isinstance(factors[0], (sp.sin, sp.cos))):
            return False
    return True


@lru_cache(maxsize=4096)
def simplify(expr: sp.Expr) -> sp.Expr:
    """The project's trigonometric simplification: ``trigsimp`` then ``factor_terms``; falls back to
    ``simplify`` when trigsimp leaves a rational expression with a non-trivial denominator."""
    expr = sp.expand(expr)
    if _linear_in_trig(expr):
        return sp.factor_terms(expr)
    expr = sp.factor_terms(sp.trigsimp(expr))
    if sp.denom(sp.together(expr)).free_symbols:
        expr = sp.factor_terms(sp.simplify(expr))
    return expr


def trig_normal(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """Canonical factored form of a rational function of q and sin/cos of q.

    Angle sums are expanded (``expand_trig``), sin q_i and cos q_i become variables s_i, c_i, numerator and
    denominator are reduced modulo s_i² + c_i² − 1 (a Gröbner basis: the remainder, of degree ≤ 1 in each s_i,
    is unique) and factored, then mapped back. Two expressions are equal iff ``trig_normal`` of their difference
    is 0, which makes it the robust test of identities such as Bayle's printed J̄ (``simplify`` is not).
    """
    return _trig_normal(sp.sympify(expr), tuple(q))


@lru_cache(maxsize=4096)
def _trig_normal(expr: sp.Expr, q: tuple[sp.Symbol, ...]) -> sp.Expr:
    """Canonical form of ``expr`` (cached; see :func:`trig_normal`)."""
    present = [v for v in q if expr.has(v)]
    if not present:
        return sp.factor(sp.together(expr))
    s = sp.symbols(f"_s0:{len(present)}", real=True)
    c = sp.symbols(f"_c0:{len(present)}", real=True)
    forward = {}
    for v, si, ci in zip(present, s, c):
        forward[sp.sin(v)] = si
        forward[sp.cos(v)] = ci
    numerator, denominator = sp.fraction(sp.together(sp.expand_trig(expr).subs(forward)))
    ideal = [si**2 + ci**2 - 1 for si, ci in zip(s, c)]
    gens = (*s, *c, *sorted((numerator.free_symbols | denominator.free_symbols) - set(s) - set(c), key=str))

    def reduce(poly: sp.Expr) -> sp.Expr:
        """Remainder eliminating sin² (or cos²), factored; the shorter of the two canonical forms."""
        poly = sp.expand(poly)
        if poly == 0:
            return poly
        forms = []
        for order in (gens, (*c, *s, *gens[2 * len(present) :])):
            _, remainder = sp.reduced(poly, ideal, *order, order="lex")
            forms.append(sp.factor(remainder))
        return min(forms, key=sp.count_ops)

    back = {si: sp.sin(v) for v, si in zip(present, s)} | {ci: sp.cos(v) for v, ci in zip(present, c)}
    return (reduce(numerator) / reduce(denominator)).subs(back)


# --- public functions -------------------------------------------------------------------------------


def jacobian(
    robot: MobileManipulator,
    task: Task | None = None,
    params: Sequence[str] = (),
    factory: Callable | None = None,
) -> sp.Matrix:
    """Symbolic J(q) = ∂f/∂q (``params``: robot parameters to keep as symbols)."""
    return model(robot, tuple(params), factory).jacobian(task)


def reduced_jacobian(
    robot: MobileManipulator,
    task: Task | None = None,
    params: Sequence[str] = (),
    factory: Callable | None = None,
) -> sp.Matrix:
    """Symbolic J̄(q) = J(q) S(q) (Bayle eq. 2); print it with ``sympy.latex``."""
    return model(robot, tuple(params), factory).reduced_jacobian(task)


def augmented_jacobian(
    robot: MobileManipulator, task: Task, params: Sequence[str] = (), factory: Callable | None = None
) -> sp.Matrix:
    """Symbolic [G(q); J_task(q)] (Korayem eq. 30, 36, 37)."""
    return model(robot, tuple(params), factory).augmented_jacobian(task)


@dataclass(frozen=True)
class RankDrop:
    """Where a Jacobian loses rank: its generic rank, the expressions that all vanish there (factored), and
    the condition as a disjunction of conjunctions of equations ``factor = 0``."""

    rank: int
    expressions: tuple[sp.Expr, ...]
    condition: sp.Basic

    def __str__(self) -> str:
        return f"rank {self.rank} drops where {self.condition}"


def rank_drop_conditions(
    robot: MobileManipulator,
    task: Task | None = None,
    params: Sequence[str] = (),
    factory: Callable | None = None,
    which: str = "velocity",
) -> RankDrop:
    """Factored conditions for d̄(q) < D̄ (``which="velocity"``, VSC) or d(q) < D (``"kinematic"``, KSC)."""
    if which not in ("velocity", "kinematic"):
        raise ModelError(f"rank_drop_conditions: which must be 'velocity' or 'kinematic', got {which!r}")
    sym = model(robot, tuple(params), factory)
    a = sym.reduced_jacobian(task) if which == "velocity" else sym.jacobian(task)
    r = sym.generic_rank(a)
    if r == a.rows == a.cols:
        expressions = [a.det()]
    else:
        expressions = [
            a.extract(list(rows), list(cols)).det()
            for rows in itertools.combinations(range(a.rows), r)
            for cols in itertools.combinations(range(a.cols), r)
        ]
    expressions = [trig_normal(e, sym.q) for e in expressions]
    expressions = _distinct(e for e in expressions if e != 0)
    return RankDrop(r, tuple(expressions), _condition(expressions))


def consistency_relations(
    robot: MobileManipulator,
    task: Task | None = None,
    params: Sequence[str] = (),
    factory: Callable | None = None,
) -> sp.Matrix:
    """Rows y(q) with y J̄ = 0 where D̄ < m: ξ̇ is admissible iff y ξ̇ = 0 (Bayle §4.3, §5.2), simplified with
    denominators and common factors cleared. Valid where the rows do not all vanish (off the VSC)."""
    sym = model(robot, tuple(params), factory)
    jbar = sym.reduced_jacobian(task)
    rows = []
    for vector in jbar.T.nullspace(simplify=simplify):
        vector = vector.applyfunc(lambda e: trig_normal(e, sym.q))
        common = sp.lcm([sp.denom(e) for e in vector])
        vector = (vector * common).applyfunc(lambda e: trig_normal(e, sym.q))
        gcd = sp.gcd(list(vector))
        vector = (vector / gcd).applyfunc(lambda e: trig_normal(e, sym.q))
        lead = next(e for e in vector if e != 0)
        rows.append((-vector if lead.could_extract_minus_sign() else vector).T)
    return sp.Matrix.vstack(*rows) if rows else sp.zeros(0, jbar.rows)


def _distinct(expressions: Iterable[sp.Expr]) -> list[sp.Expr]:
    out: list[sp.Expr] = []
    for e in expressions:
        if not any(sp.expand(e - f) == 0 or sp.expand(e + f) == 0 for f in out):  # canonical forms
            out.append(e)
    return out


def _factors(expr: sp.Expr) -> list[sp.Expr]:
    """Non-constant factors (bases of powers) of a factored expression that can vanish."""
    _, factors = sp.factor_list(expr)
    return [f for f, _ in factors if f.free_symbols and not f.is_positive]


def _condition(expressions: Sequence[sp.Expr]) -> sp.Basic:
    """∧ over expressions of (∨ over their factors of factor = 0), as a minimal DNF of equations."""
    atoms: dict[sp.Expr, sp.Symbol] = {}

    def atom(f: sp.Expr) -> sp.Symbol:
        for known, symbol in atoms.items():
            if sp.expand(known - f) == 0 or sp.expand(known + f) == 0:
                return symbol
        atoms[f] = sp.Symbol(f"_c{len(atoms)}")
        return atoms[f]

    clauses = [sp.Or(*[atom(f) for f in _factors(e)]) for e in expressions]
    logic = sp.simplify_logic(sp.And(*clauses), form="dnf", force=True)
    terms = logic.args if isinstance(logic, sp.Or) else (logic,)
    # sin u and cos u never vanish together: drop such terms
    impossible = [
        {atoms[f], atoms[sp.cos(f.args[0])]}
        for f in atoms
        if isinstance(f, sp.sin) and sp.cos(f.args[0]) in atoms
    ]
    terms = [t for t in terms if not any(pair <= set(sp.And.make_args(t)) for pair in impossible)]
    return sp.Or(*terms).subs({s: sp.Eq(f, 0) for f, s in atoms.items()})


__all__ = [
    "RankDrop",
    "model",
    "SymbolicRobot",
    "augmented_jacobian",
    "consistency_relations",
    "coordinates",
    "exact",
    "jacobian",
    "rank_drop_conditions",
    "reduced_jacobian",
    "simplify",
    "trig_normal",
]
