"""Benchmark: TIAGo's collision-aware whole-body QP law (docs/examples/tiago_avoid.toml: the hand over the table of
tiago_scene.toml, velocity dampers on the 32 nearest sphere pairs) against Pinocchio + coal + quadprog solving
the same program per control step.

    python benchmarks/avoidance.py            # 64 configurations of the spec's run; the run; 64 runs at once
    python benchmarks/avoidance.py --smoke    # tiny sizes (CI)

The program (docs/control.md, docs/collision.md): min ½‖J̄η − u‖² + ½μ‖R⁻¹η‖² + ½ w s² within TIAGo's velocity
limits, its wheels' speed limits and the joints' velocity dampers, with ḋ + s ≥ −ξ (d − d_s)/(d_i − d_s) for
each of the 32 nearest pairs of its collision spheres (cover tolerance 0.1 m: 179 spheres, 6,513 pairs with
the table, the shelf, the floor and TIAGo itself) closer than d_i, ḋ = n̂ᵀ J̄_pair η. mobman's law computes
every pair's distance, picks the 32 nearest, forms their rows and solves with qpax (20 interior-point
iterations), all in JAX. The reference per step is what a Python controller would write with the peers (the
holistic/NEO controller's recipe): Pinocchio's ``computeJointJacobians`` and the tool's frame Jacobian, coal's
distance of every pair (``computeDistances`` on the Pinocchio ``GeometryModel`` of mobman's spheres, obstacles
and pairs, benchmarks/collision.py), the distances read out, the 32 nearest taken with NumPy, their rows
n̂ᵀ (J_i − J_j) S from coal's normals and the spheres' Jacobians, and quadprog's active-set solution of the same
program. Both are evaluated at the configurations of the spec's run with ξ* = ξ and a random ξ̇*, so u = ξ̇*;
their η agree (printed; the run exits with an error above ``AGREEMENT``).

Rows: a law evaluation per call (jit, one configuration), a step of the spec's compiled closed loop (the
``hold`` integrator of the spec: one evaluation a step, held over it, as a digital controller's loop), the
same for 64 runs from perturbed starts in one call, and the reference. The ratios are the reference's time
over mobman's; no timing is asserted.
"""

from __future__ import annotations

import sys
from pathlib import Path

import jax
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.control import simulate, spec
from mobman.control.laws.qp import SLACK_WEIGHT, bounds

from collision import Reference
from real_robots import pinocchio_q
from timing import best_time, law_options, one_per_call

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_avoid.toml"
AGREEMENT = 1e-6
"""Largest |η − η_reference| (m/s, rad/s) the benchmark accepts."""


class Controller:
    """The reference: one step of the collision-aware QP with Pinocchio, coal and quadprog (module notes)."""

    def __init__(self, reference: Reference, law, robot) -> None:
        self.reference, self.law = reference, law
        self.frame = reference.model.getFrameId("arm_tool_link")
        b = bounds(robot)
        self.speed, self.wheels = b.scale, b.wheels / b.scale  # TIAGo has velocity limits: |η| ≤ scale
        self.lower, self.upper = b.lower, b.upper
        self.weight = np.broadcast_to(np.asarray(law.scale(robot), dtype=float), (robot.n_eta,))  # R
        self.n_platform, self.n_eta, self.n_eta_platform = robot.n_platform, robot.n_eta, robot.platform.n_eta

    def eta(self, q_pin: np.ndarray, q: np.ndarray, u: np.ndarray) -> np.ndarray:
        import pinocchio as pin
        import quadprog

        ref, law = self.reference, self.law
        model, data = ref.model, ref.data
        aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        pin.computeJointJacobians(model, data, q_pin)
        pin.updateFramePlacements(model, data)
        jbar = pin.getFrameJacobian(model, data, self.frame, aligned)[:3, ref.columns]
        pin.updateGeometryPlacements(model, data, ref.geometry, ref.geometry_data)
        pin.computeDistances(ref.geometry, ref.geometry_data)
        results = ref.geometry_data.distanceResults
        distance = np.array([r.min_distance for r in results])
        count = min(law.collision_rows, len(distance))
        near = np.argpartition(distance, count - 1)[:count]
        near = near[distance[near] < law.influence_distance]
        rows = np.zeros((len(near), self.n_eta))
        for k, p in enumerate(near.tolist()):
            rate = self._velocity(ref.first[p])
            if ref.self_pair[p]:
                rate = rate - self._velocity(ref.second[p])
            rows[k] = -np.asarray(results[p].normal) @ rate
        margin, influence = law.collision_margin, law.influence_distance
        bound = -law.collision_gain * (distance[near] - margin) / (influence - margin)
        # the program over (η, s): the joints' dampers clipped into the velocity box, the wheels' diamond
        q_eta = np.concatenate([np.zeros(self.n_eta_platform), q[self.n_platform :]])
        high = np.minimum(self.speed, np.maximum(-self.speed, law.limit_gain * (self.upper - q_eta)))
        low = np.maximum(-self.speed, np.minimum(self.speed, law.limit_gain * (self.lower - q_eta)))
        n = self.n_eta
        hessian = np.zeros((n + 1, n + 1))
        hessian[:n, :n] = jbar.T @ jbar + law.regularization * np.diag(1.0 / self.weight**2)
        hessian[n, n] = SLACK_WEIGHT
        linear = np.concatenate([jbar.T @ u, [0.0]])
        eye, wheels = np.eye(n), self.wheels
        constraints = np.vstack(
            [
                np.hstack([np.vstack([-eye, eye, -wheels, wheels]), np.zeros((2 * n + 2 * len(wheels), 1))]),
                np.hstack([rows, np.ones((len(near), 1))]),
                np.eye(1, n + 1, n),
            ]
        )
        ends = np.concatenate([-high, low, -np.ones(2 * len(wheels)), bound, [0.0]])
        return quadprog.solve_qp(hessian, linear, constraints.T, ends, 0)[0][:n]

    def _velocity(self, sphere: int) -> np.ndarray:
        """The linear velocity Jacobian (3 × n_eta, S's columns) of a sphere's centre from its joint's."""
        import pinocchio as pin

        ref = self.reference
        joint = int(ref.sphere_joint[sphere])
        jac = pin.getJointJacobian(ref.model, ref.data, joint, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        centre = ref.geometry_data.oMg[int(sphere)].translation - ref.data.oMi[joint].translation
        return (jac[:3] + np.cross(jac[3:], centre, axis=0))[:, ref.columns]


def main(argv=None) -> int:
    args = law_options(__doc__.splitlines()[0], argv)
    parsed = spec.load(SPEC)
    robot, task, law = parsed.robot, parsed.task, parsed.law
    run = parsed.simulate()
    steps = len(run.t) - 1
    pick = np.linspace(0, steps, args.configurations).astype(int)
    q, xi = np.asarray(run.q[pick]), np.asarray(run.xi[pick])
    rng = np.random.default_rng(0)
    xi_dot = rng.normal(size=(len(q), task.dim)) * 0.3
    evaluate = jax.jit(lambda qq, xs, xsd: law(robot, task, qq, 0.0, xs, xsd).eta)
    ours, t_call = one_per_call(evaluate, q, xi, xi_dot)

    spheres = law.collision_model(robot)
    controller = Controller(Reference(robot, spheres, law.scene), law, robot)
    q_pin = pinocchio_q(q)

    def reference():
        return np.stack([controller.eta(p, qi, u) for p, qi, u in zip(q_pin, q, xi_dot)])

    theirs = reference()
    t_ref = best_time(reference, 3) / len(q)
    agreement = float(np.max(np.abs(ours - theirs)))
    near = [int(np.sum(d < law.influence_distance)) for d in controller_distances(controller, q_pin)]

    def simulation(q0):
        return lambda: (
            simulate(
                robot,
                task,
                law,
                parsed.reference,
                q0,
                parsed.duration,
                parsed.dt,
                integrator=parsed.integrator,
            ).q
        )

    simulation(parsed.q0)()
    t_step = best_time(simulation(parsed.q0), 3) / steps
    q0s = parsed.q0 + rng.normal(size=(args.batch, robot.n_q)) * 0.01
    simulation(q0s)()
    t_batch = best_time(simulation(q0s), 3) / (steps * args.batch)

    print(
        f"TIAGo, {len(spheres.spheres)} spheres, {len(controller.reference.first)} pairs, the collision-aware QP "
        f"law of {SPEC.name} ({law.collision_rows} damper rows); device {jax.devices()[0].platform}"
    )
    print(f"{'variant':62s} {'µs/step':>10s} {'reference / mobman':>19s}")
    rows = [
        ("QP law with collision dampers, one configuration per call", t_call),
        (f"a step of the compiled closed loop ({parsed.integrator}, {steps} steps)", t_step),
        (f"  {args.batch} runs in one call, per run and step", t_batch),
        ("reference: Pinocchio + coal + quadprog, per step", t_ref),
    ]
    for name, t in rows:
        print(f"{name:62s} {1e6 * t:10.1f} {t_ref / t:19.2f}")
    print(
        f"max |η − reference| = {agreement:.1e} over {len(q)} configurations "
        f"({min(near)}–{max(near)} pairs within the influence distance)"
    )
    if not agreement <= AGREEMENT:
        print("error: mobman and the reference disagree", file=sys.stderr)
        return 1
    return 0


def controller_distances(controller: Controller, q_pin: np.ndarray) -> list[np.ndarray]:
    """coal's distances of every pair at each configuration (for the count of pairs within d_i)."""
    import pinocchio as pin

    ref = controller.reference
    out = []
    for qi in q_pin:
        pin.computeDistances(ref.model, ref.data, ref.geometry, ref.geometry_data, qi)
        out.append(np.array([r.min_distance for r in ref.geometry_data.distanceResults]))
    return out


if __name__ == "__main__":
    sys.exit(main())
