"""Base placement: where TIAGo's platform should stop so that its hand reaches a point, ranked by the arm's
manipulability (mobman.studies.placement; the same as `mobman place tiago --target 1,0.5,0.8`).

Every pose of a polar grid around the target is tried; the arm's inverse kinematics is solved within the joint
limits from a few starting postures, and the reached placements are scored by Yoshikawa's w of the arm's
Jacobian J_a at the posture found. Then the target stands on a table (x from 0.7 to 1.6 m, y from 0 to 1.2
m): the bases from which the disc covering TIAGo's base would overlap it are left out (mobman.studies.floor;
`mobman place tiago --target 1,0.5,0.8 --keep-out 0.7,1.6,0,1.2`).

    python examples/09_base_placement.py
"""

import numpy as np

from mobman import kinematics
from mobman.model import robots
from mobman.studies.placement import place

robot = robots.build("tiago")
target = np.array([1.0, 0.5, 0.8])
grid = dict(radii=[0.3, 0.5, 0.7, 0.9], bearings=8, headings=8)
table = (0.7, 1.6, 0.0, 1.2)
for title, result in (
    ("in the open", place(robot, target, **grid)),
    ("beside the table", place(robot, target, keep_out=[table], **grid)),
):
    print(f"{title}: {result.reached.sum()} of {len(result.bases)} bases reach {target} m", end="")
    print(f" ({result.blocked.sum()} blocked by the table)" if result.footprint else "")
    for rank, k in enumerate(result.ranking(3), start=1):
        x, y, theta = result.bases[k]
        hand = np.asarray(kinematics.forward(robot, result.q[k]))
        print(
            f"  {rank}. base x = {x:.3f} m, y = {y:.3f} m, θ = {theta:.3f} rad: w = {result.score[k]:.4f}, "
            f"hand error {np.linalg.norm(hand - target):.1e} m"
        )
