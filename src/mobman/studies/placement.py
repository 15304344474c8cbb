"""Base placement: where to park the platform so that the arm reaches a target of the task, and reaches it
well.

Every candidate platform pose (x, y, θ) of a polar grid around the target is tried. With the platform parked
there, the arm's inverse kinematics is solved from several starting postures by damped least squares within
the joint limits (:mod:`mobman.studies.reaching`). A posture reaches the target when the norm of the task's
error is at most ``tolerance``; of the starts that reach it, each base keeps the one of highest score.

A reached placement is scored by a manipulability measure at its posture (:mod:`mobman.manipulability`):
by default Yoshikawa's w of the arm's Jacobian J_a, which says how well the arm moves the task with the
platform parked, or of the whole system's J̄ = J S (``level="system"``; Bayle eq. 2), which also counts what
the platform's admissible velocities add (Bayle; Nait-Chabane).

``keep_out`` regions of the floor (tables, shelves, walls; :mod:`mobman.studies.floor`) leave out the bases
from which the disc covering the platform overlaps one of them: such a base is ``blocked`` and never reaches
the target, whatever its arm could do from there.

Given a ``scene`` of obstacles (:mod:`mobman.model.scene`) or a collision model, a start's posture counts only
when the robot there, platform and arm, is free of collision with the scene's obstacles and floor and with
itself (the self pairs of its collision model; :mod:`mobman.studies.clearance`): the arm reaching over a table
may not pass through it. A base whose starts reach the target only with colliding postures is ``colliding``
(counted apart from the blocked ones). The scene's boxes standing on the floor are keep-out regions too
(:func:`mobman.studies.floor.scene_regions`).

When no base reaches the target, :func:`out_of_reach` says whether the target itself is beyond the robot's
reach: its height above the highest point (or below the lowest) that the tool reaches with any posture
within the joint limits (:func:`closest_height`; the platform moves on the floor, so no base changes it),
or every candidate base farther from it than the arm reaches (:func:`reach_radius`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
import numpy.typing as npt

from mobman import kinematics as K
from mobman.errors import InputError
from mobman.model import spatial
from mobman.model.collision_model import CollisionModel
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene
from mobman.model.tasks import Pose, Position, Task
from mobman.redundancy import sample_configurations
from mobman.studies import options
from mobman.studies.clearance import clearance_of, free_postures
from mobman.studies.floor import (
    FootprintDisc,
    KeepOut,
    blocked,
    footprint_disc,
    keep_out_regions,
    scene_regions,
)
from mobman.studies.maps import ReachabilityMap, robot_digest
from mobman.studies.options import LEVELS
from mobman.studies.reaching import best, reach, starting_postures

BUCKET = 512
"""The candidate bases of :func:`place_with_map` are solved in whole multiples of this many rows."""

REACH_SAMPLES = 4096
"""Random postures :func:`reach_radius` measures the arm's reach on."""

REACH_MARGIN = 1.25
"""Factor on the largest sampled reach: the postures at the corners of the joint limits, such as a telescoping
arm fully out, are rare among random ones (Stretch: 0.84 m over 4,096 postures, 0.88 m over 20,000)."""


@dataclass(frozen=True)
class Placement:
    """Candidate platform poses and what the arm reaches from each.

    ``target``: the task's target (m,), or its targets (K, m) (:func:`place`); ``bases`` (N, 3): the
    platform poses (x, y, θ); ``q`` (N, n_q): the posture kept for each, (N, K, n_q) for K targets (the
    platform's further coordinates, such as a steering angle, at 0; NaN where J was undefined from every
    start); ``error`` (N,): the norm of the task's error there (inf for those; the largest over several
    targets); ``reached`` (N,): error ≤ tolerance with a posture free of collision, and not blocked; ``score`` (N,): the measure at the
    posture where reached (the lowest over several targets), 0 where not;
    ``blocked`` (N,): the platform there would overlap a keep-out region (all False without any), and
    ``footprint`` the disc that covered it (None without keep-out regions); ``colliding`` (N,): not blocked,
    and a start reached the target (every target) but only with postures in collision (module notes; all
    False without a scene or collision model). ``best``: the index of
    the reached base with the highest score, None when no base reaches the target. ``n_platform``: the
    platform's coordinates at the start of each row of ``q``; ``revolute``: which of the arms' coordinates
    are angles of revolute joints.
    """

    target: np.ndarray
    bases: np.ndarray
    q: np.ndarray
    error: np.ndarray
    reached: np.ndarray
    score: np.ndarray
    measure: str
    level: str
    tolerance: float
    n_platform: int
    blocked: np.ndarray
    colliding: np.ndarray
    revolute: tuple[bool, ...] = ()
    footprint: FootprintDisc | None = None

    @property
    def best(self) -> int | None:
        if not self.reached.any():
            return None
        return int(np.argmax(np.where(self.reached, self.score, -np.inf)))

    def ranking(self, count: int = 5, distinct: bool = True) -> np.ndarray:
        """Indices of the ``count`` best reached bases, best first. ``distinct``: a base whose arm posture
        equals (to 1e-6, the angles of revolute joints a whole turn apart equal) that of a base already listed
        is left out. For a target the task's value does not
        change when turned about the vertical, such as a point, every bearing around the centre with the same
        distance and heading towards it is the same placement."""
        reached = np.flatnonzero(self.reached)
        order = reached[np.argsort(-self.score[reached], kind="stable")]
        if not distinct:
            return order[:count]
        arm = self.q[..., self.n_platform :]  # with several targets, the postures of them all
        revolute = (
            np.array(self.revolute, dtype=bool) if self.revolute else np.zeros(arm.shape[-1], dtype=bool)
        )
        turns = np.tile(revolute, math.prod(arm.shape[1:-1]))
        arm = arm.reshape(len(arm), turns.size)

        def same(a: np.ndarray, b: np.ndarray) -> bool:
            difference = a - b
            # a revolute joint's angles a whole turn apart are the same posture
            difference[turns] = np.angle(np.exp(1j * difference[turns]))
            return bool(np.max(np.abs(difference)) <= 1e-6)

        chosen: list[int] = []
        for k in order:
            if len(chosen) == count:
                break
            if not any(same(arm[k], arm[c]) for c in chosen):
                chosen.append(int(k))
        return np.asarray(chosen, dtype=int)


def reach_radius(robot: MobileManipulator, arm: int = 0) -> float:
    """How far from the platform's reference point arm ``arm``'s tool reaches, horizontally: the largest
    distance over :data:`REACH_SAMPLES` seeded postures within the joint limits
    (:func:`mobman.redundancy.sample_configurations`) times :data:`REACH_MARGIN`, and at most the sum of the
    mount's offset, every joint origin's offset, the prismatic joints' largest travel and the tool's offset
    (a bound that counts vertical offsets as reach too)."""
    q = sample_configurations(robot, REACH_SAMPLES, seed=0)
    q[:, : robot.n_platform] = 0.0
    tool = np.asarray(K.forward(robot, q, Position("xy", arm=arm)))
    mount = np.linalg.norm(spatial.fixed_pose(robot.mounts[arm].transform)[1])
    chain = robot.arms[arm]
    offsets = sum(float(np.linalg.norm(spatial.fixed_pose(j.origin)[1])) for j in chain.joints)
    travel = sum(
        max(abs(j.lower), abs(j.upper))
        for j in chain.joints
        if j.kind == "prismatic" and math.isfinite(j.lower)
    )
    bound = mount + offsets + travel + np.linalg.norm(spatial.fixed_pose(chain.tool)[1])
    return float(min(REACH_MARGIN * np.linalg.norm(tool, axis=1).max(), bound))


HEIGHT_STARTS = 64
"""Starting postures of :func:`closest_height`'s search (the zero posture and seeded random ones)."""

HEIGHT_ITERATIONS = 100
"""Damped least-squares steps of :func:`closest_height` from each start."""

HEIGHT_MARGIN = 1e-3
"""Least gap (m) between a target's height and :func:`closest_height` that :func:`out_of_reach` calls out of
reach (with the placement's tolerance, the larger): the search finds a local extremum, slightly inside the
true one."""


def _height_task(task: Task) -> tuple[int, Position] | None:
    """The row of ``task``'s height and the task of that height alone (a point's z): None for a task
    without one."""
    if isinstance(task, Position) and "z" in task.components:
        return task.components.index("z"), Position("z", task.arm, task.link, task.point)
    if isinstance(task, Pose):
        return 2, Position("z", task.arm, task.link)
    return None


def closest_height(robot: MobileManipulator, height: float, task: Task | None = None) -> float | None:
    """The height (m) nearest ``height`` that the point of ``task`` (a :class:`Position` with z, or a
    :class:`Pose`; default the robot's task) reaches with the arm's joints within their limits, None for a
    task without a height: damped least squares on that height alone (:func:`mobman.studies.reaching.reach`)
    from :data:`HEIGHT_STARTS` postures, :data:`HEIGHT_ITERATIONS` steps each. Towards a height out of reach
    the steps climb to the highest (or lowest) posture: a local extremum, so the value is the best of the
    starts (TIAGo: 1.700 m, where 400,000 random postures reach 1.692 m)."""
    found = _height_task(K.resolve_task(robot, task))
    if found is None:
        return None
    _, alone = found
    starts = starting_postures(robot, HEIGHT_STARTS)
    q, _ = reach(robot, np.zeros(3), [float(height)], starts, alone, HEIGHT_ITERATIONS)
    heights = np.asarray(K.forward(robot, q, alone))[..., 0]
    return float(heights[np.nanargmin(np.abs(heights - height))])


def out_of_reach(robot: MobileManipulator, result: Placement, task: Task | None = None) -> str | None:
    """Why no base of ``result`` reaches its target(s), where the target is beyond the robot's reach (module
    notes): its height more than the tolerance above the highest point (below the lowest) the tool reaches, or
    every base farther from it than the arm reaches horizontally. None where neither holds (the grid or the
    starts may then have missed it)."""
    task = K.resolve_task(robot, task)
    targets = np.atleast_2d(result.target)
    found = _height_task(task)
    if found is not None:
        row, _ = found
        for z in targets[:, row]:
            nearest = closest_height(robot, z, task)
            assert nearest is not None  # the task has a height
            if abs(z - nearest) > max(result.tolerance, HEIGHT_MARGIN):
                side = "above the highest" if z > nearest else "below the lowest"
                return (
                    f"the target's height {z:.4g} m is {abs(z - nearest):.3g} m {side} point the tool reaches "
                    f"({nearest:.4g} m, with any posture within the joint limits)"
                )
    if _horizontal(task) and len(result.bases):
        radius = reach_radius(robot, getattr(task, "arm", 0))
        gaps = np.linalg.norm(result.bases[:, None, :2] - targets[None, :, :2], axis=-1).max(axis=1)
        if gaps.min() > radius:
            return (
                f"every base lies {gaps.min():.3g} m or more from the target, farther than the arm reaches "
                f"({radius:.3g} m from the platform)"
            )
    return None


def candidate_bases(centre: npt.ArrayLike, radii: npt.ArrayLike, bearings: int, headings: int) -> np.ndarray:
    """Platform poses (x, y, θ), shape (len(radii) · bearings · headings, 3): at each distance of ``radii``
    from ``centre`` (x, y), ``bearings`` directions φ evenly around it, and ``headings`` headings evenly
    over a turn, counted from the direction to the centre (the first faces it: θ = φ + π)."""
    r = np.asarray(radii, dtype=float)
    phi = 2.0 * np.pi * np.arange(bearings) / bearings
    psi = 2.0 * np.pi * np.arange(headings) / headings
    rr, pp, ss = (a.ravel() for a in np.meshgrid(r, phi, psi, indexing="ij"))
    c = np.asarray(centre, dtype=float)
    theta = np.mod(pp + np.pi + ss + np.pi, 2.0 * np.pi) - np.pi
    return np.stack([c[0] + rr * np.cos(pp), c[1] + rr * np.sin(pp), theta], axis=-1)


def place(
    robot: MobileManipulator,
    target: npt.ArrayLike,
    *,
    task: Task | None = None,
    centre: npt.ArrayLike | None = None,
    radii: npt.ArrayLike | None = None,
    bearings: int = 16,
    headings: int = 16,
    starts: int = 4,
    iterations: int = 60,
    tolerance: float = 1e-6,
    measure: str = "yoshikawa",
    level: str = "arm",
    seed: int = 0,
    keep_out: Sequence[KeepOut | Sequence[float]] = (),
    footprint: FootprintDisc | float | Sequence[float] | None = None,
    scene: Scene | None = None,
    collision: CollisionModel | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Placement:
    """Try every platform pose of :func:`candidate_bases` for the task target ξ* ``target`` (m,) (module
    notes) and score the reached ones.

    ``target`` (K, m): several targets reached from the same base, each with a posture of its own (to pick
    at one and place at another without moving the platform): a base reaches them when it reaches every one,
    and is scored by the lowest of their postures' scores (the weakest posture decides); ``q`` is then
    (N, K, n_q), a posture per target. ``centre``: the (x, y) the grid is centred on, by default the
    target's own x and y (the task's first two coordinates when they are x and y, as in ``Position("xyz")``
    and ``Pose``; the middle of the targets' bounding box for several); ``radii``: the distances from
    it, by default 8 from 0 to :func:`reach_radius`; ``starts``: starting postures per base (the arm's
    coordinates at 0 clipped to the limits, then seeded random ones over the limits,
    :func:`mobman.redundancy.sample_configurations`); ``measure``: one of
    :data:`mobman.manipulability.MEASURES`; ``level``: ``"arm"`` (J_a) or ``"system"`` (J̄); ``keep_out``:
    regions of the floor (:class:`mobman.studies.floor.KeepOut` or x_min, x_max, y_min, y_max) the platform's
    ``footprint`` may not overlap (a :class:`mobman.studies.floor.FootprintDisc`, a radius or radius, x, y;
    by default :func:`mobman.studies.floor.footprint_disc` of the robot); ``scene``: the obstacles and floor
    a posture must be free of (with ``collision``, the robot's collision model, whose self pairs it must be
    free of too; by default :func:`mobman.model.collision_model.collision_model` at
    :data:`mobman.studies.clearance.COVER_TOLERANCE` when a scene is given; neither: postures not checked);
    ``progress(done, total)``: called as the inverse kinematics' rows (base, target and start) are solved.
    """
    task = K.resolve_task(robot, task)
    targets = _targets(target, task)
    centre = _centre(task, targets) if centre is None else options.vector(centre, "centre", 2, "x, y")
    radii = np.linspace(0.0, reach_radius(robot), 8) if radii is None else _distances(radii)
    for name, value in (("bearings", bearings), ("headings", headings), ("starts", starts)):
        options.count(value, name)
    options.iterations(iterations)
    options.seed(seed)
    options.tolerance(tolerance)
    options.scoring(measure, level)
    # every base, target and start at once: a posture and a Jacobian (m × n_q) each
    pairs = {"radii": len(radii), "bearings": bearings, "headings": headings, "starts": starts}
    options.memory(pairs, math.prod(pairs.values()) * len(targets) * robot.n_q * (task.dim + 1))
    checks = clearance_of(robot, collision, scene)
    floor = _floor(robot, keep_out, footprint, scene)
    bases = candidate_bases(centre, radii, bearings, headings)
    # every base with every target at once: (N, K) pairs, each its best posture (N, K, n_q)
    starting = starting_postures(robot, starts, seed)
    found, errors = reach(robot, bases[:, None], targets, starting, task, iterations, progress)
    close = errors <= tolerance
    free = free_postures(checks, found, close)
    q, error, score = best(robot, found, errors, tolerance, task, measure, level, free)
    every = ~np.isnan(score).any(axis=1)  # every target reached with a free posture
    colliding = np.all(close.any(axis=-1), axis=1) & ~every
    error, score = error.max(axis=1), np.where(every, score.min(axis=1), 0.0)
    if np.ndim(target) == 1:  # one target: its posture per base
        targets, q = targets[0], q[:, 0]
    return _placement(
        robot, targets, bases, q, error, score, every, colliding, measure, level, tolerance, *floor
    )


def place_with_map(
    robot: MobileManipulator,
    reachability: ReachabilityMap,
    target: npt.ArrayLike,
    *,
    headings: int = 16,
    iterations: int = 20,
    tolerance: float = 1e-6,
    keep_out: Sequence[KeepOut | Sequence[float]] = (),
    footprint: FootprintDisc | float | Sequence[float] | None = None,
    scene: Scene | None = None,
    collision: CollisionModel | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Placement:
    """Base placement from a reachability map of the robot's arm (:mod:`mobman.studies.maps`): inverse
    reachability (Vahrenkamp, Asfour, Dillmann, ICRA 2013).

    A reached cell c of the map (platform frame) with the platform at heading θ puts the tool at
    b + R(θ) c for a platform at b, so every cell within half a step of the target's height and each of
    ``headings`` headings over a turn give the candidate base (x, y) = p − R(θ) c, θ, from which the cell's
    posture holds the tool at the target up to the cell's height. From that posture ``iterations`` damped
    least-squares steps within the joint limits (:mod:`mobman.studies.reaching`) take the tool onto the
    target ``p`` (x, y, z); a base reaches it within ``tolerance``. Bases are scored by the map's measure and
    level. No inverse kinematics from random starts: a map computed once serves any number of targets.
    ``keep_out``, ``footprint``, ``scene``, ``collision`` and ``progress``: as in :func:`place`.
    """
    if not isinstance(reachability, ReachabilityMap):
        raise InputError(f"reachability must be a ReachabilityMap, got {type(reachability).__name__}")
    if reachability.digest != robot_digest(K.checked_robot(robot)):
        raise InputError(f"reachability: the map was computed for another robot than {robot.name!r}")
    if not 0 <= reachability.arm < len(robot.arms):
        raise InputError(f"reachability: arm {reachability.arm} of a robot with {len(robot.arms)} arm(s)")
    target = options.vector(target, "target", 3, "x, y, z")
    headings, iterations = options.count(headings, "headings"), options.iterations(iterations)
    options.tolerance(tolerance)
    checks = clearance_of(robot, collision, scene)
    floor = _floor(robot, keep_out, footprint, scene)
    half = 0.5 * reachability.step + 1e-9
    centres = reachability.centres()
    near = reachability.reached & (np.abs(centres[..., 2] - target[2]) <= half)
    cells, postures = centres[near], reachability.q[near]
    options.memory({"headings": headings, "cells": len(cells)}, len(cells) * headings * robot.n_q * 4)
    theta = 2.0 * np.pi * np.arange(headings) / headings - np.pi
    c, s = np.cos(theta)[None, :], np.sin(theta)[None, :]
    x = target[0] - (c * cells[:, :1] - s * cells[:, 1:2])
    y = target[1] - (s * cells[:, :1] + c * cells[:, 1:2])
    bases = np.stack([x, y, np.broadcast_to(theta, x.shape)], axis=-1).reshape(-1, 3)
    starts = np.repeat(postures[:, robot.n_platform :], headings, axis=0)[:, None, :]
    task = Position("xyz", arm=reachability.arm)
    # the candidates padded to a whole number of BUCKET rows: targets at other heights have other counts,
    # and each count would compile the solver again (seconds) for a query that takes a fraction of one
    found, errors = reach(robot, bases, target, starts, task, iterations, progress, BUCKET)
    close = errors <= tolerance
    free = free_postures(checks, found, close)
    q, error, score = best(
        robot, found, errors, tolerance, Position(reachability.scored, arm=reachability.arm),
        reachability.measure, reachability.level, free,
    )  # fmt: skip
    every = ~np.isnan(score)
    return _placement(
        robot, target, bases, q, error, score, every, close[:, 0] & ~every, reachability.measure,
        reachability.level, tolerance, *floor,
    )  # fmt: skip


def _floor(
    robot: MobileManipulator,
    keep_out: Sequence[KeepOut | Sequence[float]],
    footprint: FootprintDisc | float | Sequence[float] | None,
    scene: Scene | None,
) -> tuple[tuple[KeepOut, ...], FootprintDisc | None]:
    """The keep-out regions, checked, with those of the scene's boxes on the floor, and the disc that covers
    the platform (None without regions)."""
    regions = keep_out_regions(keep_out) + (() if scene is None else scene_regions(scene))
    if not regions:
        return regions, None
    return regions, footprint_disc(robot) if footprint is None else FootprintDisc.of(footprint)


def _placement(
    robot: MobileManipulator,
    target: np.ndarray,
    bases: np.ndarray,
    q: np.ndarray,
    error: np.ndarray,
    score: np.ndarray,
    found: np.ndarray,
    colliding: np.ndarray,
    measure: str,
    level: str,
    tolerance: float,
    regions: tuple[KeepOut, ...],
    footprint: FootprintDisc | None,
) -> Placement:
    """The :class:`Placement` of the solved candidates: reached where ``found`` (within ``tolerance`` with
    free postures) and not blocked; ``colliding`` where not blocked either."""
    off_limits = blocked(bases, footprint, regions) if footprint is not None else np.zeros(len(bases), bool)
    reached = found & ~off_limits
    return Placement(
        target=np.asarray(target),
        bases=bases,
        q=q,
        error=error,
        reached=reached,
        score=np.where(reached, score, 0.0),
        measure=measure,
        level=level,
        tolerance=float(tolerance),
        n_platform=robot.n_platform,
        revolute=_revolute(robot),
        blocked=off_limits,
        colliding=colliding & ~off_limits,
        footprint=footprint,
    )


def _revolute(robot: MobileManipulator) -> tuple[bool, ...]:
    """Which of the arms' coordinates are angles of revolute joints."""
    return tuple(j.kind == "revolute" for arm in robot.arms for j in arm.joints)


def _distances(radii: npt.ArrayLike) -> np.ndarray:
    try:
        arr = np.asarray(radii, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"radii must be one or more finite distances ≥ 0 (m), got {radii!r}") from None
    if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        shown = ", ".join(f"{r:g}" for r in arr.ravel()) or "none"
        raise InputError(f"radii must be one or more finite distances ≥ 0 (m), got {shown}")
    return arr


def _targets(target: npt.ArrayLike, task: Task) -> np.ndarray:
    """One target (m,) or several (K, m) of ``task``, checked, as (K, m)."""
    names = ", ".join(task.names)
    try:
        several = np.ndim(target) == 2
    except ValueError:  # rows of different lengths
        raise InputError(f"target must be {task.dim} numbers ({names}), or rows of them") from None
    if several and len(target) == 0:  # type: ignore[arg-type]
        raise InputError(f"target: no target given; give {task.dim} numbers ({names})")
    rows = target if several else [target]
    return np.stack([options.vector(row, "target", task.dim, names) for row in rows])  # type: ignore[union-attr]


def _horizontal(task: Task) -> bool:
    """Whether the task's first two coordinates are the x and y of a point."""
    first = task.names[:2]
    return len(first) == 2 and first[0].startswith("x") and first[1].startswith("y")


def _centre(task: Task, targets: np.ndarray) -> np.ndarray:
    """The targets' x and y (the middle of their bounding box): the task's first two coordinates when they are
    the x and y of a point."""
    if _horizontal(task):
        return (targets[:, :2].min(axis=0) + targets[:, :2].max(axis=0)) / 2
    raise InputError(
        f"centre: the task's coordinates ({', '.join(task.names)}) do not start with x and y; give the (x, y) "
        "the search is centred on"
    )


__all__ = [
    "BUCKET",
    "LEVELS",
    "Placement",
    "HEIGHT_ITERATIONS",
    "HEIGHT_MARGIN",
    "HEIGHT_STARTS",
    "candidate_bases",
    "closest_height",
    "out_of_reach",
    "place",
    "place_with_map",
    "reach_radius",
    "REACH_MARGIN",
    "REACH_SAMPLES",
]
