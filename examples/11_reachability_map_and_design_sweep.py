"""Design studies: where TIAGo's hand reaches in front of its platform, and which link lengths of a planar
arm serve a workspace best (mobman.studies; the same as `mobman map tiago --bounds … --step 0.1` and
`mobman sweep korayem-planar --vary l1=0.3:0.7:3 --bounds … --step 0.1`).

The map solves the arm's inverse kinematics within the joint limits for every cell centre of a grid, the
platform parked, and scores the reached cells by Yoshikawa's w of the hand's position Jacobian. The sweep
builds each design of a grid of parameters and scores it by w over random postures, its reach and the share
of a box its tool reaches.

    python examples/11_reachability_map_and_design_sweep.py
"""

import numpy as np

from mobman.model import robots
from mobman.studies.maps import reachability_map
from mobman.studies.sweep import sweep

tiago = robots.build("tiago")
result = reachability_map(tiago, bounds=[0.2, 0.8, -0.6, 0.6, 0.4, 1.4], step=0.1)
best = result.best()
print(
    f"TIAGo's hand reaches {result.reached.sum()} of {result.reached.size} cells ({result.fraction:.0%}) "
    f"in front of its platform; the highest w, {result.score[best]:.3f}, at {result.centres()[best]} m"
)
for k, z in enumerate(result.axes[2]):
    print(f"  z = {z:.1f} m: {result.reached[:, :, k].sum():3d} cells reached")

designs = sweep(
    "korayem-planar", {"l1": [0.3, 0.5, 0.7]}, samples=500, bounds=[0.4, 1.6, -0.6, 0.6, 0.0, 0.0], step=0.1
)
print("korayem-planar, its upper arm l1 varied: the box's coverage, the reach and the mean w")
for index in designs.ranking("coverage"):
    m = {name: float(values[index]) for name, values in designs.metrics.items()}
    print(
        f"  l1 = {designs.design(index)['l1']:.1f} m: coverage {m['coverage']:.0%}, reach {m['reach']:.2f} m, "
        f"mean w {m['mean']:.4f}"
    )
assert np.all(np.diff(designs.metrics["reach"]) > 0)  # a longer upper arm reaches further
