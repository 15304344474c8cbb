"""The largest payload a mobile manipulator can carry along a motion, and the actuator that limits it.

Korayem, Ghariblu & Basu: DC-motor envelopes T± = ±k1 − k2 ω (eq. 34) on the joints of `korayem_planar`;
the reduced inverse dynamics is affine in the payload's mass, so the capacity is one vectorised minimum.

    python examples/06_load_capacity.py
"""

import numpy as np

from mobman import dynamics as dyn
from mobman.dynamics.load_capacity import eta_dot_from_samples
from mobman.experiments import korayem_load

model = korayem_load.dynamic_model()  # korayem_planar with documented link, platform and wheel inertials
t = np.linspace(0.0, 2.0, 401)
s, s_dot = 3 * (t / 2) ** 2 - 2 * (t / 2) ** 3, 3 * (t / 2) * (1 - t / 2)  # rest to rest in 2 s
zero = np.zeros_like(t)
q = np.column_stack([0.5 * s, zero, zero, 0.3 + 0.8 * s, 1.2 - 0.6 * s])  # (x, y, θ, θ1, θ2)
eta = np.column_stack([0.5 * s_dot, zero, 0.8 * s_dot, -0.6 * s_dot])  # (v, ω, θ̇1, θ̇2), q̇ = S(q) η

for stall in (63.22, 30.0):
    motor = dyn.DCMotor(stall_torque=stall, no_load_speed=3.5)
    result = dyn.max_load(model, t, q, eta, eta_dot_from_samples(t, eta), {"theta1": motor, "theta2": motor})
    print(
        f"stall torque {stall} N·m: maximum load {result.max_load:.2f} kg, limited by "
        f"{result.limiting_actuator} at t = {result.limiting_time:.3f} s"
    )
