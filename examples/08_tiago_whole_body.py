"""Whole-body pose control of a real robot: TIAGo's platform, torso and arm track a 6-D hand pose together.

The spec docs/examples/tiago_pose.toml (the same as `mobman simulate docs/examples/tiago_pose.toml`): Bayle's
law η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P (Bayle, Fourquet & Renaud 2003, eq. 5–6) with the pose error
e = (p* − p, log(R* Rᵀ)) and P the eccentricity w5 of the whole system's J̄. The path, a line of 0.42 m and a
slerp through 0.92 rad, starts off the hand; the error norm decays as exp(−W t). Bayle's law does not enforce
joint limits: the run reports how it leaves them, and how close each joint comes (the QP law keeps them:
examples/10_whole_body_within_limits.py).

    python examples/08_tiago_whole_body.py
"""

from pathlib import Path

import numpy as np

from mobman.control import metrics, simulate, spec

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_pose.toml"

parsed = spec.load(SPEC)
robot = parsed.robot
result = simulate(
    robot,
    parsed.task,
    parsed.law,
    parsed.reference,
    parsed.q0,
    parsed.duration,
    parsed.dt,
    integrator=parsed.integrator,
)  # one compiled call
summary = metrics.summarize(result, robot)

position = np.linalg.norm(result.error[:, :3], axis=1)  # m
orientation = np.linalg.norm(result.error[:, 3:], axis=1)  # rad
expected = np.hypot(position[0], orientation[0]) * np.exp(-float(parsed.law.W) * result.t[-1])
print(f"{robot.name}: {len(result.t)} samples over {parsed.duration} s")
print(f"pose error at t = 0: {position[0]:.4f} m, {orientation[0]:.4f} rad")
print(
    f"pose error at the end: {position[-1]:.1e} m, {orientation[-1]:.1e} rad (‖e(0)‖ exp(−W t): {expected:.1e})"
)

moved = result.q[-1] - result.q[0]
for name, change in zip(robot.coordinate_names, moved):
    print(f"  {name:>17}: {change:+.3f}")

limits = np.asarray(robot.position_limits)
margin = np.min(np.minimum(result.q - limits[:, 0], limits[:, 1] - result.q), axis=0)  # m (torso), rad (arm)
closest = int(np.argmin(margin))
count = summary["joint_limit_violations"]
worst = (
    f" (worst {summary['joint_limit_worst']:.3g} at {summary['joint_limit_worst_joint']})" if count else ""
)
print(f"samples outside the joint limits: {count}{worst}")
print(f"closest to a limit: {robot.coordinate_names[closest]}, {margin[closest]:.3f} from it")
