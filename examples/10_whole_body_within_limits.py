"""Whole-body control within the limits: TIAGo's hand rises to 1.35 m and turns, more than its torso's lift
gives, and the QP law keeps every joint inside its limits, every quasi-velocity within its limit and each
wheel under its speed limit (the same as `mobman simulate docs/examples/tiago_limits.toml`).

The spec's law is Bayle's law (Bayle, Fourquet & Renaud 2003, eq. 5–6) as a quadratic program
(mobman.control.laws.WholeBodyQP); the same run with Bayle's law itself is shown beside it: it tracks the pose
as well, by lifting the torso past its limit and driving joints above their speed limits.

    python examples/10_whole_body_within_limits.py
"""

from dataclasses import replace
from pathlib import Path

import numpy as np

from mobman.control import laws, metrics, spec

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_limits.toml"

parsed = spec.load(SPEC)
robot = parsed.robot
qp = parsed.law
bayle = laws.BaylePseudoInverse(W=qp.W, k=qp.k, criterion=qp.criterion)
lower, upper = np.asarray(robot.position_limits).T
print(f"{robot.name}: {parsed.duration} s at dt = {parsed.dt} s; torso limits {lower[3]}..{upper[3]} m")
for name, law in (("QP law", qp), ("Bayle's law", bayle)):
    result = replace(parsed, law=law).simulate()  # one compiled call
    summary = metrics.summarize(result, robot)
    worst = summary["joint_limit_worst_joint"]
    print(f"{name}:")
    print(f"  final pose error {summary['final_error']:.1e} (m and rad), RMS {summary['rms_error']:.4f}")
    print(f"  highest torso {result.q[:, 3].max():.4f} m")
    print(
        f"  samples outside the joint limits: {summary['joint_limit_violations']}"
        + (f" (worst {summary['joint_limit_worst']:.3f} at {worst})" if worst else "")
    )
    print(
        f"  largest |η_i| / η_i,max: {summary['velocity_limit_ratio']:.3f}, "
        f"largest wheel speed / limit: {summary['wheel_speed_ratio']:.3f}"
    )
    if "joint_limited_steps" in summary:
        print(
            f"  samples with a joint at its damper: {summary['joint_limited_steps']}, "
            f"with a speed limit active: {summary['speed_limited_steps']}"
        )
