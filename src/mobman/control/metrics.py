"""Scalar indicators of a simulated run (one run; loop over a batch's first axis for several).

- tracking: ``max_error`` / ``rms_error`` of ‖ξ* − ξ‖ over the samples with t ≥ ``transient``;
- platform manoeuvres: ``graining_points`` = sign changes of the platform speed v among the samples where
  |v| > ``v_threshold`` (Nait-Chabane's "graining points": the platform stops and reverses), and
  ``v_initial`` = the first such v (its sign says whether the platform starts forward or backward);
- manipulability: minima (and final values) of the measures recorded in the result;
- ``ee_path_length`` (tool position of the first arm) and ``platform_path_length`` (x, y), in m;
- joint limits: ``joint_limit_violations`` = the number of samples where a coordinate is outside its position
  limits, ``joint_limit_worst`` = the largest excess over a limit (rad or m; 0 when none) and
  ``joint_limit_worst_joint`` its coordinate's name (None when none): the laws do not enforce the limits, so
  a run reports them;
- ``control_effort`` = ∫ ‖η‖² dt (rectangle rule);
- ``acceleration_variation`` = Σ_k ‖η̇_{k+1} − η̇_k‖ with η̇ by finite differences: the total variation of the
  quasi-accelerations, large when the platform jerks or manoeuvres.
"""

from __future__ import annotations

import numpy as np

from mobman.errors import InputError

V_THRESHOLD = 1e-3
"""Default |v| (m/s) below which the platform speed counts as zero for the graining points."""


def graining_points(v, threshold: float = V_THRESHOLD) -> int:
    """Number of sign changes of v, ignoring the samples with |v| ≤ threshold."""
    v = np.asarray(v, dtype=float)
    if v.ndim != 1:
        raise InputError(f"graining_points: v must be one run (1-D), got shape {v.shape}")
    if not (np.isfinite(threshold) and threshold >= 0):
        raise InputError(f"graining_points: threshold must be ≥ 0, got {threshold!r}")
    signs = np.sign(v[np.abs(v) > threshold])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


def first_significant(v, threshold: float = V_THRESHOLD) -> float:
    """The first value of v with |v| > threshold (0.0 if there is none)."""
    v = np.asarray(v, dtype=float)
    idx = np.flatnonzero(np.abs(v) > threshold)
    return float(v[idx[0]]) if idx.size else 0.0


def _path_length(points: np.ndarray) -> float:
    return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=-1)))


def joint_limit_violations(robot, q) -> dict:
    """How a path of configurations q (N × n_q) leaves the robot's joint position limits: the number of
    samples outside, the worst excess (rad or m) and the name of its coordinate (see the module docstring)."""
    q = np.asarray(q, dtype=float)
    limits = np.asarray(robot.position_limits, dtype=float)
    excess = np.maximum(limits[:, 0] - q, 0.0) + np.maximum(q - limits[:, 1], 0.0)
    worst = np.max(excess, axis=0)
    joint = int(np.argmax(worst))
    return {
        "joint_limit_violations": int(np.count_nonzero(np.any(excess > 0.0, axis=-1))),
        "joint_limit_worst": float(worst[joint]),
        "joint_limit_worst_joint": robot.coordinate_names[joint] if worst[joint] > 0.0 else None,
    }


def summarize(result, robot=None, transient: float = 0.0, v_threshold: float = V_THRESHOLD) -> dict:
    """The metrics of one run as a JSON-friendly dict (see the module docstring)."""
    from mobman.kinematics import forward
    from mobman.model.task import Position

    robot = result.robot if robot is None else robot
    if result.q.ndim != 2:
        raise InputError(f"summarize: one run expected, got q of shape {result.q.shape} (a batch?)")
    dt = result.dt
    err = np.linalg.norm(result.error, axis=-1)
    after = err[result.t >= transient]
    if after.size == 0:
        raise InputError(f"transient {transient} s is longer than the run ({result.t[-1]} s)")
    v = result.eta[:, 0]
    ee = np.asarray(forward(robot, result.q, Position("xyz")))
    eta_dot = np.diff(result.eta, axis=0) / dt
    out = {
        "duration": float(result.t[-1]),
        "dt": dt,
        "max_error": float(after.max()),
        "rms_error": float(np.sqrt(np.mean(after**2))),
        "final_error": float(err[-1]),
        "graining_points": graining_points(v, v_threshold),
        "v_initial": first_significant(v, v_threshold),
        "ee_path_length": _path_length(ee),
        "platform_path_length": _path_length(result.q[:, :2]),
        "control_effort": float(np.sum(result.eta**2) * dt),
        "acceleration_variation": float(np.sum(np.linalg.norm(np.diff(eta_dot, axis=0), axis=-1))),
        "saturated_steps": int(np.count_nonzero(result.saturated)),
        "damped_steps": int(np.count_nonzero(result.damped)),
        **joint_limit_violations(robot, result.q),
    }
    for name, values in result.measures.items():
        out[f"{name}_min"] = float(np.min(values))
        out[f"{name}_max"] = float(np.max(values))
        out[f"{name}_final"] = float(values[-1])
    return out


__all__ = ["V_THRESHOLD", "first_significant", "graining_points", "joint_limit_violations", "summarize"]
