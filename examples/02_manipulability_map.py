"""Manipulability of the arm and of the whole system over a grid of arm configurations, in one batched call.

Nait-Chabane, Hoppenot & Colle (2006) eq. 13–26: Yoshikawa's w, the inverse condition number w2 and the
eccentricity w5 of the arm's Jacobian J_a and of the whole system's reduced Jacobian J̄ = J S, for the
end-effector position (x, y) of the HILARE platform with a planar 2R arm.

    python examples/02_manipulability_map.py
"""

import numpy as np

from mobman import manipulability as mp
from mobman.model import robots
from mobman.model.tasks import Position

l1 = l2 = 0.5
robot, task = robots.bayle_planar(l1=l1, l2=l2), Position("xy")
angles = np.linspace(-np.pi, np.pi, 181)
q4, q5 = np.meshgrid(angles, angles, indexing="ij")
zero = np.zeros_like(q4)
q = np.stack([zero, zero, zero, q4, q5], axis=-1)  # (181, 181, 5): 32,761 configurations

arm = mp.measures(mp.arm_jacobian(robot, q, task))  # each measure (181, 181)
system = mp.measures(mp.system_jacobian(robot, q, task))
for name in mp.MEASURES:
    print(
        f"{name:18s} arm: max {float(np.max(arm[name])):.3f}   whole system: max {float(np.max(system[name])):.3f}"
    )

# Yoshikawa's closed form for the 2R arm: w = l1 l2 |sin q5|
error = float(np.max(np.abs(np.asarray(arm["yoshikawa"]) - l1 * l2 * np.abs(np.sin(q5)))))
print(f"arm w against l1 l2 |sin q5|: max difference {error:.1e}")
best = np.unravel_index(np.argmin(np.asarray(system["eccentricity"])), q4.shape)
print(
    f"roundest whole-system ellipse (w5 = {float(system['eccentricity'][best]):.3f}) at "
    f"q4 = {q4[best]:.3f}, q5 = {q5[best]:.3f} rad"
)
