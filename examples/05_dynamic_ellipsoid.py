"""Kinematic and dynamic task-space ellipsoids of a dual-arm mobile manipulator holding an object.

Yamamoto & Yun (1999) eq. 23–38 on the robot of their Tables 1–2: the velocities (x_o, y_o, angle_o) of the
held object that the normalised actuator rates allow, and its accelerations from the torque limits.

    python examples/05_dynamic_ellipsoid.py
"""

import numpy as np

from mobman import dynamics as dyn
from mobman.dynamics.ellipsoids import dynamic_ellipsoid, kinematic_ellipsoid
from mobman.dynamics.grasp import HeldObject

model = dyn.yamamoto_model()  # Tables 1–2, horizontal motion
q = np.array([0.0, 0.0, 0.0, 0.3, 0.8, 1.1, -0.3, -0.8, -1.1])
np.set_printoptions(precision=4, suppress=True)

for scale in (1.0, 0.01):  # the platform's speed limits, as given and nearly braked
    kin = kinematic_ellipsoid(model.robot, q, held=True, platform_scale=scale)
    print(f"kinematic, platform speed × {scale}: semi-axes {kin.axes}, volume {float(kin.volume):.3e}")

limits = np.array([200, 200, 200, 100, 30, 200, 100, 30.0])  # wheels, then each arm's joints (N·m)
acc = dynamic_ellipsoid(model, q, limits, obj=HeldObject(2.0, (0, 0, 0.01)), method="exact")
print("dynamic (exact): semi-axes", acc.axes, "\nprincipal directions (columns):\n", acc.directions)
