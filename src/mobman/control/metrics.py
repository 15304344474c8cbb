"""Scalar indicators of a simulated run (one run; loop over a batch's first axis for several).

- tracking: ``max_error`` / ``rms_error`` of ‖ξ* − ξ‖ over the samples with t ≥ ``transient``;
- platform manoeuvres: ``graining_points`` = sign changes of the platform speed v among the samples where
  |v| > ``v_threshold`` (Nait-Chabane's "graining points": the platform stops and reverses), and
  ``v_initial`` = the first such v (its sign says whether the platform starts forward or backward);
- manipulability: minima (and final values) of the measures recorded in the result;
- ``ee_path_length`` (tool position of the first arm) and ``platform_path_length`` (x, y), in m;
- joint limits: ``joint_limit_violations`` = the number of samples where a coordinate is outside its position
  limits, ``joint_limit_worst`` = the largest excess over a limit (rad or m; 0 when none) and
  ``joint_limit_worst_joint`` its coordinate's name (None when none): only the QP law
  (:class:`~mobman.control.laws.WholeBodyQP`) enforces the limits, so a run reports them;
- velocity limits: ``velocity_limit_ratio`` = the largest |η_i| / η_i,max over the samples (None without
  velocity limits) and ``wheel_speed_ratio`` = the largest |u_j| / u_j,max of the driven wheels' speeds
  u = T⁻¹ η_p (None for a platform without per-wheel limits): above 1, the commanded η leaves the limits;
- the law's flags: for every boolean entry of the recorded ``info`` (``speed_limited``, ``joint_limited`` of
  :class:`~mobman.control.laws.WholeBodyQP`), ``<name>_steps`` = the number of samples where it holds;
- collisions (the QP law with a scene, :mod:`mobman.control.avoidance`): ``min_distance`` (m) the least
  distance of the nearest pair of the law's collision spheres over the samples, ``closest_pair`` its two names
  and ``closest_time`` (s), ``collision_violations`` the number of samples closer than the law's
  ``collision_margin``, ``collision_slack_max`` the largest slack the dampers took (m/s);
- ``control_effort`` = ∫ ‖η‖² dt (rectangle rule);
- ``acceleration_variation`` = Σ_k ‖η̇_{k+1} − η̇_k‖ with η̇ by finite differences: the total variation of the
  quasi-accelerations, large when the platform jerks or manoeuvres.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError

if TYPE_CHECKING:
    from mobman.control.simulation import SimulationResult
    from mobman.model.robot import MobileManipulator

V_THRESHOLD = 1e-3
"""Default |v| (m/s) below which the platform speed counts as zero for the graining points."""


def graining_points(v: npt.ArrayLike, threshold: float = V_THRESHOLD) -> int:
    """Number of sign changes of v, ignoring the samples with |v| ≤ threshold."""
    v = np.asarray(v, dtype=float)
    if v.ndim != 1:
        raise InputError(f"graining_points: v must be one run (1-D), got shape {v.shape}")
    if not (np.isfinite(threshold) and threshold >= 0):
        raise InputError(f"graining_points: threshold must be ≥ 0, got {threshold!r}")
    signs = np.sign(v[np.abs(v) > threshold])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


def first_significant(v: npt.ArrayLike, threshold: float = V_THRESHOLD) -> float:
    """The first value of v with |v| > threshold (0.0 if there is none)."""
    v = np.asarray(v, dtype=float)
    idx = np.flatnonzero(np.abs(v) > threshold)
    return float(v[idx[0]]) if idx.size else 0.0


def _path_length(points: np.ndarray) -> float:
    return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=-1)))


def _excess(limits: np.ndarray, q: npt.ArrayLike) -> np.ndarray:
    """How far each coordinate of q (N × n_q) lies outside its [lower, upper] limits (0 inside)."""
    q = np.asarray(q, dtype=float)
    return np.maximum(limits[:, 0] - q, 0.0) + np.maximum(q - limits[:, 1], 0.0)


def _speed_limits(robot: MobileManipulator) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The robot's velocity limits (n_eta) and its driven wheels' speed limits, each None where not given."""
    velocity, wheels = robot.velocity_limits, robot.platform.actuator_speed_limits
    return (
        None if velocity is None else np.asarray(velocity, dtype=float),
        None if wheels is None else np.asarray(wheels, dtype=float),
    )


def joint_limit_violations(robot: MobileManipulator, q: npt.ArrayLike) -> dict:
    """How a path of configurations q (N × n_q) leaves the robot's joint position limits: the number of
    samples outside, the worst excess (rad or m) and the name of its coordinate (see the module docstring)."""
    excess = _excess(np.asarray(robot.position_limits, dtype=float), q)
    worst = np.max(excess, axis=0)
    joint = int(np.argmax(worst))
    return {
        "joint_limit_violations": int(np.count_nonzero(np.any(excess > 0.0, axis=-1))),
        "joint_limit_worst": float(worst[joint]),
        "joint_limit_worst_joint": robot.coordinate_names[joint] if worst[joint] > 0.0 else None,
    }


class RunningSummary:
    """The metrics of one run (see the module docstring) from its samples fed in order, one piece after the
    other (:meth:`add`), so that a long run need never be held in memory whole: :meth:`metrics` gives the
    same numbers as :func:`summarize` of the whole run (sums taken piece by piece, so equal to rounding)."""

    def __init__(
        self, robot: MobileManipulator, transient: float = 0.0, v_threshold: float = V_THRESHOLD
    ) -> None:
        if not (np.isfinite(v_threshold) and v_threshold >= 0):
            raise InputError(f"summarize: v_threshold must be ≥ 0, got {v_threshold!r}")
        self.robot, self.transient, self.v_threshold = robot, transient, v_threshold
        self._limits = np.asarray(robot.position_limits, dtype=float)
        self._first: list[float] = []  # the first two sample times (dt)
        self._last = 0.0
        self._after = [0, 0.0, -np.inf]  # samples with t ≥ transient, Σ e², max e
        self._final_error = 0.0
        self._sign: float | None = None  # sign of the last significant v
        self._grains = 0
        self._v_initial: float | None = None
        self._tail: dict[
            str, np.ndarray
        ] = {}  # the last ee point, platform point and two η of the last piece
        self._lengths = [0.0, 0.0]
        self._effort, self._variation = 0.0, 0.0
        self._saturated, self._damped, self._outside = 0, 0, 0
        self._worst = np.zeros(len(self._limits))
        self._measures: dict[str, list[float]] = {}
        self._flags: dict[str, int] = {}
        self._ratios = [0.0, 0.0]  # the largest velocity and wheel-speed ratios
        self._nearest: dict | None = None  # the collision metrics, with a scene

    def add(self, piece: SimulationResult) -> None:
        """Feed the next samples: a :class:`~mobman.control.simulation.SimulationResult` of one run."""
        from mobman.kinematics import forward
        from mobman.model.tasks import Position

        if piece.q.ndim != 2:
            raise InputError(f"summarize: one run expected, got q of shape {piece.q.shape} (a batch?)")
        t = np.asarray(piece.t, dtype=float)
        self._first = (self._first + [float(x) for x in t[:2]])[:2]
        self._last = float(t[-1])
        if len(self._first) < 2:
            raise InputError(
                "summarize: the first piece of a run must hold two samples at least (the step dt)"
            )
        dt = self._first[1] - self._first[0]
        err = np.linalg.norm(piece.error, axis=-1)
        after = err[t >= self.transient]
        self._after = [
            self._after[0] + after.size,
            self._after[1] + float(np.sum(after**2)),
            max(self._after[2], float(after.max())) if after.size else self._after[2],
        ]
        self._final_error = float(err[-1])
        v = np.asarray(piece.eta[:, 0], dtype=float)
        signs = np.sign(v[np.abs(v) > self.v_threshold])
        if signs.size:
            if self._sign is not None:
                signs = np.concatenate([[self._sign], signs])
            self._grains += int(np.count_nonzero(signs[1:] != signs[:-1]))
            self._sign = float(signs[-1])
            if self._v_initial is None:
                self._v_initial = first_significant(v, self.v_threshold)
        tail = self._tail
        ee = np.asarray(forward(self.robot, piece.q, Position("xyz")))
        paths = (ee, np.asarray(piece.q[:, :2]))
        for i, (name, points) in enumerate(zip(("ee", "platform"), paths)):
            self._lengths[i] += _path_length(np.concatenate([tail.get(name, points[:0]), points]))
            tail[name] = points[-1:]
        eta = np.concatenate([tail.get("eta", piece.eta[:0]), piece.eta])
        eta_dot = np.diff(eta, axis=0) / dt
        self._variation += float(np.sum(np.linalg.norm(np.diff(eta_dot, axis=0), axis=-1)))
        tail["eta"] = eta[-2:]
        self._effort += float(np.sum(piece.eta**2))
        self._saturated += int(np.count_nonzero(piece.saturated))
        self._damped += int(np.count_nonzero(piece.damped))
        excess = _excess(self._limits, piece.q)
        self._outside += int(np.count_nonzero(np.any(excess > 0.0, axis=-1)))
        self._worst = np.maximum(self._worst, np.max(excess, axis=0))
        for name, values in piece.info.items():
            if np.asarray(values).dtype == bool:
                self._flags[name] = self._flags.get(name, 0) + int(np.count_nonzero(values))
        velocity, wheels = _speed_limits(self.robot)
        if velocity is not None:
            self._ratios[0] = max(self._ratios[0], float(np.max(np.abs(piece.eta) / velocity)))
        if wheels is not None:
            speeds = np.asarray(
                self.robot.platform.eta_to_wheel_speeds(piece.eta[:, : self.robot.platform.n_eta])
            )
            self._ratios[1] = max(self._ratios[1], float(np.max(np.abs(speeds) / wheels)))
        if "min_distance" in piece.info:
            self._collisions(piece, t)
        for name, values in piece.measures.items():
            low, high = float(np.min(values)), float(np.max(values))
            seen = self._measures.get(name, [low, high])
            self._measures[name] = [min(seen[0], low), max(seen[1], high), float(values[-1])]

    def _collisions(self, piece: SimulationResult, t: np.ndarray) -> None:
        """Feed the collision metrics (module docstring) of a run of the QP law with a scene; the closest pair
        is named where the result carries its law (an index into its pairs for a batch of laws)."""
        from mobman.collision import pair_names
        from mobman.control.laws import WholeBodyQP

        law = piece.law
        names, margin = None, None
        if isinstance(law, WholeBodyQP) and law.scene is not None:
            names = pair_names(law.collision_model(self.robot), law.scene)
            margin = law.collision_margin
        distance = np.asarray(piece.info["min_distance"])
        k = int(np.argmin(distance))
        seen = self._nearest or {
            "min_distance": np.inf,
            "collision_violations": 0,
            "collision_slack_max": 0.0,
        }
        if margin is not None:
            seen["collision_violations"] += int(np.count_nonzero(distance < margin))
        slack = float(np.max(piece.info["collision_slack"]))
        seen["collision_slack_max"] = max(seen["collision_slack_max"], slack)
        if distance[k] < seen["min_distance"]:
            pair = int(piece.info["closest_pair"][k])
            seen |= {
                "min_distance": float(distance[k]),
                "closest_time": float(t[k]),
                "closest_pair": pair if names is None else list(names[pair]),
            }
        self._nearest = seen

    def metrics(self) -> dict:
        """The metrics of the samples fed so far, as a JSON-friendly dict."""
        count, squares, largest = self._after
        if count == 0:
            raise InputError(f"transient {self.transient} s is longer than the run ({self._last} s)")
        dt = self._first[1] - self._first[0]
        joint = int(np.argmax(self._worst))
        out = {
            "duration": self._last,
            "dt": dt,
            "max_error": largest,
            "rms_error": float(np.sqrt(squares / count)),
            "final_error": self._final_error,
            "graining_points": self._grains,
            "v_initial": 0.0 if self._v_initial is None else self._v_initial,
            "ee_path_length": self._lengths[0],
            "platform_path_length": self._lengths[1],
            "control_effort": self._effort * dt,
            "acceleration_variation": self._variation,
            "saturated_steps": self._saturated,
            "damped_steps": self._damped,
            "joint_limit_violations": self._outside,
            "joint_limit_worst": float(self._worst[joint]),
            "joint_limit_worst_joint": self.robot.coordinate_names[joint]
            if self._worst[joint] > 0.0
            else None,
        }
        velocity, wheels = _speed_limits(self.robot)
        out["velocity_limit_ratio"] = None if velocity is None else self._ratios[0]
        out["wheel_speed_ratio"] = None if wheels is None else self._ratios[1]
        for name, count in self._flags.items():
            out[f"{name}_steps"] = count
        if self._nearest is not None:
            out |= self._nearest
        for name, (low, high, final) in self._measures.items():
            out[f"{name}_min"], out[f"{name}_max"], out[f"{name}_final"] = low, high, final
        return out


def summarize(
    result: SimulationResult,
    robot: MobileManipulator | None = None,
    transient: float = 0.0,
    v_threshold: float = V_THRESHOLD,
) -> dict:
    """The metrics of one run as a JSON-friendly dict (see the module docstring)."""
    robot = result.robot if robot is None else robot
    if robot is None:
        raise InputError("summarize: the result names no robot; pass robot=")
    summary = RunningSummary(robot, transient, v_threshold)
    summary.add(result)
    return summary.metrics()


__all__ = [
    "V_THRESHOLD",
    "RunningSummary",
    "first_significant",
    "graining_points",
    "joint_limit_violations",
    "summarize",
]
