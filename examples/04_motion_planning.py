"""Motion planning in the endogenous configuration space: Tchoń, Jakubiak & Muszyński (2002) §4.

The kinematic car carrying an RTR arm reaches the target y_d = (0, 0, 1) from the paper's start P with the
Jacobian pseudo-inverse algorithm (Newton's step Δθ = 1, tolerance 1e-12).

    python examples/04_motion_planning.py
"""

import numpy as np

from mobman.experiments import tchon2002
from mobman.planning.algorithms import Options, plan
from mobman.planning.endpoint import dexterity, endpoint

setting = tchon2002.setting()  # car + RTR arm, T = 1, two harmonics: z ∈ R^13
z0 = tchon2002.initial_configuration()  # λ01 = 0.01, λ02 = −0.01, x0 = (0, 2, π/4)
q0 = tchon2002.start_pose("P")  # (5, 0, 0, π/6)
target = [0.0, 0.0, 1.0]

result = plan(setting, z0, q0, target, Options("pinv", step=1.0, tol=1e-12))
print(f"{result.status} in {result.iterations} iterations, final error {result.final_error:.1e}")
np.set_printoptions(precision=4, suppress=True)
print("control coefficients λ (u1, u2 × 5 harmonics):\n", result.lam.reshape(2, 5))
print("arm joints x:", result.x)
print("endpoint K(z):", np.asarray(endpoint(setting, result.z, q0)))
print(
    f"dexterity at the start {float(dexterity(setting.jacobian_setting, z0, q0)):.3f}, "
    f"at the solution {float(dexterity(setting.jacobian_setting, result.z, q0)):.3f}"
)
