"""Analyse one configuration of a built-in robot: ξ, J, J̄, ranks, redundancy and singular configurations.

Bayle, Fourquet & Renaud (2003) §5.1: the HILARE platform (differential drive) carrying a planar 2R arm, with
the end-effector position and orientation as the task (m = 3).

    python examples/01_analyze_a_robot.py
"""

import numpy as np

from mobman import kinematics, redundancy
from mobman.model import robots

robot = robots.bayle_planar(l1=0.5, l2=0.5)
print("coordinates q:", robot.coordinate_names, " quasi-velocities η:", robot.control_names)

q = np.array([0.0, 0.0, 0.0, 0.3, 1.2])  # (x, y, θ, q4, q5)
np.set_printoptions(precision=3, suppress=True)
print("ξ = f(q):", np.asarray(kinematics.forward(robot, q)))
print("J = ∂f/∂q:\n", np.asarray(kinematics.jacobian(robot, q)))
print("J̄ = J S (ξ̇ = J̄ η):\n", np.asarray(kinematics.reduced_jacobian(robot, q)))

report = redundancy.redundancy_report(robot)
print("redundancy:", report.as_dict())  # M = 5, δ = 4, D = 3, R = 2, D̄ = 3, R̄ = 1

# Bayle §5.1: velocity-singular exactly when q4 = ±π/2 (the arm's base direction along the wheel axle)
for q4 in (0.3, np.pi / 2):
    test = redundancy.is_velocity_singular(robot, np.array([0.0, 0.0, 0.0, q4, 1.2]))
    print(f"q4 = {q4:.4f}: velocity singular {bool(test.singular)}, order {int(test.order)}")
