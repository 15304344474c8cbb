"""Benchmark: TIAGo's signed sphere distances and their rate rows (``mobman.collision.distances``) against
Pinocchio and coal (``pinocchio.computeDistances``) on the same spheres, obstacles and pairs.

    python benchmarks/collision.py             # 1,024 configurations in one call, 200 for Pinocchio
    python benchmarks/collision.py --smoke     # tiny sizes (CI)
    python benchmarks/collision.py --tolerance 0.05 --n 64 --reference 20

The last is ``mobman distance``'s default cover: 646 spheres and 57,646 pairs, whose results take 9 MB per
configuration (1,024 of them would take 9 GB).

The robot is TIAGo from its URDF (``mobman.robots.build("tiago")``, needs mobman[robots]) with the collision
spheres ``mobman distance`` builds for it (``mobman.cli.distance.robot_collision_model``), by default at the
cover tolerance of the control loop (``CONTROL_TOLERANCE``, 0.1 m: the rows are what the whole-body QP law's
collision dampers read). The scene is the table and the shelf of docs/examples/tiago_scene.toml and 18 seeded
random boxes, cylinders, spheres and capsules 0.3–2 m around the origin, on the floor z ≤ 0. The pairs are
mobman's (``collision.pair_spheres``): every sphere with every obstacle, every arm sphere with the floor, and
the model's self-collision sphere pairs. The configurations are random over TIAGo's joint ranges
(``redundancy.sample_configurations``), the platform within 0.25 m of the origin with any heading.

mobman evaluates a batch of configurations in one compiled call: the distances alone (``distances_one``'s
first result compiled on its own, which XLA prunes to the sphere centres and the distances) and the whole
``PairDistances`` (distances, witness points, normals and the rows over η, ``collision.distances``). The
reference is what a Python script would write with the peers, one configuration at a time: a Pinocchio
``GeometryModel`` holding one ``coal.Sphere`` per collision sphere (on the joint of its body, its centre as the
placement), the obstacles as coal shapes on the universe (a capsule's length its straight part, as mobman's),
the floor as a ``coal.Halfspace`` and mobman's pairs as its collision pairs; ``computeDistances`` at q
(forward kinematics, the geometry placements, then coal's distance of every pair, left in the
``GeometryData``). The reference for the rows adds ``computeJointJacobians`` and forms n̂ᵀ (J_i − J_j) S in
NumPy from the joints' world-aligned Jacobians, the spheres' centres and coal's normals (read from Python).

Both are evaluated on the reference's configurations first: their distances and rows must agree to
``AGREEMENT``, else the run exits with an error. A sphere against a box, a cylinder, a capsule, a sphere or a
half-space is in closed form in both, with one difference of definition: where a sphere's centre lies inside
a cylinder nearer one of its caps than its side, coal's sphere–cylinder function returns the depth below the
side, where mobman's signed distance is the depth below the nearer cap (the shortest way out). The reference
of the agreement takes the cap's closed form for those pairs, from Pinocchio's placements, and prints how many
there were; the timed reference is coal's as it is. The ratios are the reference's time per configuration over
mobman's; no timing is asserted.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import jax
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman import collision
from mobman.cli.distance import robot_collision_model
from mobman.engine.batched import blocked
from mobman.io import scene as scene_file
from mobman.model import robots
from mobman.model.collision_model import CONTROL_TOLERANCE, CollisionModel
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Obstacle, Scene
from mobman.redundancy import sample_configurations

from real_robots import pinocchio_model, pinocchio_q
from timing import best_time, print_peak, roofline, xla_cost

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from coal_shapes import coal_shape  # noqa: E402  (the shapes the distance tests hold coal to)

if TYPE_CHECKING:
    import pinocchio as pin

SCENE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_scene.toml"
OBSTACLES = 20
REPEAT = 3
"""Timed repetitions of each row (its best is printed)."""

AGREEMENT = 1e-9
"""Largest |distance − reference| (m) and |row − reference| (m/s per unit η) the benchmark accepts."""


def benchmark_scene(count: int = OBSTACLES, seed: int = 0) -> Scene:
    """The obstacles of docs/examples/tiago_scene.toml and seeded random ones up to ``count`` (boxes,
    cylinders, spheres and capsules in turn, centres 0.3–2 m from the origin at heights 0.1–1.6 m, any
    orientation), on that file's floor."""
    base = scene_file.load(SCENE)
    rng = np.random.default_rng(seed)
    shapes = ("box", "cylinder", "sphere", "capsule")
    obstacles = list(base.obstacles)
    for k in range(count - len(obstacles)):
        shape = shapes[k % len(shapes)]
        radius, angle = rng.uniform(0.3, 2.0), rng.uniform(-np.pi, np.pi)
        position = (radius * np.cos(angle), radius * np.sin(angle), rng.uniform(0.1, 1.6))
        size: tuple[float, ...] = {
            "box": tuple(rng.uniform(0.05, 0.5, 3)),
            "cylinder": (rng.uniform(0.03, 0.2), rng.uniform(0.1, 0.8)),
            "sphere": (rng.uniform(0.05, 0.25),),
            "capsule": (rng.uniform(0.03, 0.15), rng.uniform(0.1, 0.8)),
        }[shape]
        rpy = rng.uniform(-np.pi, np.pi, 3)
        obstacles.append(Obstacle(f"{shape} {k + 1}", shape, size, position, tuple(rpy)))
    return Scene(tuple(obstacles), base.floor)


def configurations(robot: MobileManipulator, count: int, seed: int) -> np.ndarray:
    """Random configurations over TIAGo's joint ranges, the platform within 0.25 m of the origin, any heading."""
    q = sample_configurations(robot, count, seed)
    rng = np.random.default_rng(seed + 1)
    q[:, :2] = rng.uniform(-0.25, 0.25, (count, 2))
    q[:, 2] = rng.uniform(-np.pi, np.pi, count)
    return q


def pinocchio_geometry(model: pin.Model, spheres: CollisionModel, scene: Scene) -> pin.GeometryModel:
    """Pinocchio's ``GeometryModel`` of mobman's pairs: sphere k is geometry k (a ``coal.Sphere`` on the joint
    of its body: the planar root joint for the platform, a chain joint for a link), then the obstacles on the
    universe, then the floor (a ``coal.Halfspace``); the collision pairs in the order of
    ``collision.pair_spheres``, the robot's sphere first."""
    import coal
    import pinocchio as pin

    robot = spheres.robot
    joint = {(-1, 0): model.getJointId("root_joint")}
    for a, arm in enumerate(robot.arms):
        for k, j in enumerate(arm.joints):
            joint[(a, k)] = model.getJointId(j.name)
    geometry = pin.GeometryModel()
    for k, s in enumerate(spheres.spheres):
        placement = pin.SE3(np.eye(3), np.array(s.centre))
        geometry.addGeometryObject(
            pin.GeometryObject(f"sphere {k}", joint[s.body], placement, coal.Sphere(s.radius))
        )
    n_s, n_o = len(spheres.spheres), len(scene.obstacles)
    for o in scene.obstacles:
        placement = pin.SE3(o.rotation, np.array(o.position))
        geometry.addGeometryObject(pin.GeometryObject(o.name, 0, placement, coal_shape(o.shape, o.size)))
    floor = geometry.addGeometryObject(
        pin.GeometryObject(
            "floor", 0, pin.SE3.Identity(), coal.Halfspace(np.array([0.0, 0.0, 1.0]), scene.floor)
        )
    )
    first, second = collision.pair_spheres(spheres, scene)
    for k, (i, j) in enumerate(zip(first.tolist(), second.tolist())):
        other = j if j >= 0 else n_s + k % n_o if k < n_s * n_o else floor
        geometry.addCollisionPair(pin.CollisionPair(i, other))
    return geometry


class Reference:
    """Pinocchio and coal per configuration on :func:`pinocchio_geometry` (module notes)."""

    def __init__(self, robot: MobileManipulator, spheres: CollisionModel, scene: Scene) -> None:
        import pinocchio as pin

        self.model = pinocchio_model(robot)
        self.data = self.model.createData()
        self.geometry = pinocchio_geometry(self.model, spheres, scene)
        self.geometry_data = pin.GeometryData(self.geometry)
        pairs = self.geometry.collisionPairs
        self.first = np.array([p.first for p in pairs])
        self.second = np.array([p.second for p in pairs])
        n_s = len(spheres.spheres)
        self.self_pair = self.second < n_s  # both geometries are spheres
        self.sphere_joint = np.array([self.geometry.geometryObjects[k].parentJoint for k in range(n_s)])
        self.columns = np.r_[0, 2, 3 : self.model.nv]  # S: η = (v, ω, q̇_a) of the planar root joint
        # the sphere–cylinder pairs, for :meth:`_cylinder_caps`
        obstacle = self.second - n_s
        shapes = [o.shape for o in scene.obstacles]
        self.cylinder = np.array(
            [k for k, o in enumerate(obstacle) if 0 <= o < len(shapes) and shapes[o] == "cylinder"], dtype=int
        )
        cylinders = [scene.obstacles[o] for o in obstacle[self.cylinder]]
        self.cylinder_rotation = np.array([o.rotation for o in cylinders]).reshape(-1, 3, 3)
        self.cylinder_position = np.array([o.position for o in cylinders]).reshape(-1, 3)
        self.cylinder_size = np.array([o.size for o in cylinders]).reshape(-1, 2)  # radius, length
        self.cylinder_sphere = np.array([spheres.spheres[i].radius for i in self.first[self.cylinder]])

    def distances(self, q_pin: np.ndarray) -> None:
        """``computeDistances`` at each configuration (its results stay in the ``GeometryData``)."""
        import pinocchio as pin

        for qi in q_pin:
            pin.computeDistances(self.model, self.data, self.geometry, self.geometry_data, qi)

    def rows(self, q_pin: np.ndarray, caps: bool = False) -> list[tuple[np.ndarray, np.ndarray, int]]:
        """Per configuration: the distances, the rows n̂ᵀ (J_i − J_j) S over η (P, n_eta), J the linear
        velocity Jacobian of a sphere's centre from its joint's world-aligned Jacobian, n̂ = −coal's normal (coal's
        points from the robot's sphere to the other geometry), and the number of pairs :meth:`_cylinder_caps`
        set (with ``caps``; else 0)."""
        import pinocchio as pin

        out = []
        aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        for qi in q_pin:
            pin.computeJointJacobians(self.model, self.data, qi)
            pin.updateGeometryPlacements(self.model, self.data, self.geometry, self.geometry_data)
            pin.computeDistances(self.geometry, self.geometry_data)
            results = self.geometry_data.distanceResults
            distance = np.array([r.min_distance for r in results])
            normal = -np.array([r.normal for r in results])
            joints = np.stack(
                [pin.getJointJacobian(self.model, self.data, j, aligned) for j in range(self.model.njoints)]
            )[self.sphere_joint][:, :, self.columns]
            centre = np.array([p.translation for p in self.geometry_data.oMg[: len(self.sphere_joint)]])
            origin = np.array([m.translation for m in self.data.oMi])[self.sphere_joint]
            set_here = self._cylinder_caps(centre, distance, normal) if caps else 0
            # v_c = v_o + ω × (c − o), column by column
            jac = joints[:, :3] + np.cross(joints[:, 3:], (centre - origin)[:, :, None], axis=1)
            rates = jac[self.first]
            rates[self.self_pair] -= jac[self.second[self.self_pair]]
            out.append((distance, np.einsum("pk,pkn->pn", normal, rates), set_here))
        return out

    def _cylinder_caps(self, centre: np.ndarray, distance: np.ndarray, normal: np.ndarray) -> int:
        """Where a sphere's centre (``centre``: the spheres' world centres, Pinocchio's placements) lies inside
        a cylinder nearer one of its caps than its side, coal's sphere–cylinder distance is the depth below the
        side, not the signed distance: there set the signed distance −(h − |z|) − r and the normal ±the axis
        through the nearer cap (in place; z the centre's abscissa along the axis, h the half length). Returns
        how many pairs were set."""
        k = self.cylinder
        x = np.einsum("pji,pj->pi", self.cylinder_rotation, centre[self.first[k]] - self.cylinder_position)
        side = self.cylinder_size[:, 0] - np.hypot(x[:, 0], x[:, 1])
        cap = self.cylinder_size[:, 1] / 2 - np.abs(x[:, 2])
        at_cap = (side >= 0) & (cap >= 0) & (cap < side)
        distance[k[at_cap]] = -cap[at_cap] - self.cylinder_sphere[at_cap]
        normal[k[at_cap]] = np.sign(x[at_cap, 2])[:, None] * self.cylinder_rotation[at_cap, :, 2]
        return int(at_cap.sum())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1024, help="configurations in one call (mobman)")
    parser.add_argument("--reference", type=int, default=200, help="configurations timed with Pinocchio")
    parser.add_argument("--tolerance", type=float, default=CONTROL_TOLERANCE, help="cover tolerance (m)")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.n, args.reference = 8, 4
    if args.reference > args.n:  # the reference's configurations are the batch's first
        parser.error(f"--reference must be at most --n ({args.n})")
    robot = robots.build("tiago")
    spheres = robot_collision_model("tiago", robot, {}, args.tolerance)
    scene = benchmark_scene()
    q = configurations(robot, args.n, seed=0)
    n_pairs = len(collision.pair_names(spheres, scene))

    only = jax.jit(blocked(lambda x: collision.distances_one(spheres, scene, x)[0], block=collision.BLOCK))

    def distances_only():
        return np.asarray(only(q))

    def whole():
        return collision.distances(spheres, scene, q)

    # agreement first, on the reference's configurations (the batch's first)
    reference = Reference(robot, spheres, scene)
    q_pin = pinocchio_q(q[: args.reference])
    theirs = reference.rows(q_pin, caps=True)
    ours = collision.distances(spheres, scene, q[: args.reference])
    alone = distances_only()[: args.reference]
    err_d = max(
        float(np.max(np.abs(d - mine)))
        for c, (d, _, _) in enumerate(theirs)
        for mine in (ours.distance[c], alone[c])
    )
    err_rows = max(float(np.max(np.abs(ours.rows[c] - r))) for c, (_, r, _) in enumerate(theirs))

    t_only = best_time(distances_only, REPEAT) / args.n
    t_whole = best_time(whole, REPEAT) / args.n
    t_ref = best_time(lambda: reference.distances(q_pin), REPEAT) / args.reference
    t_ref_rows = best_time(lambda: reference.rows(q_pin), REPEAT) / args.reference

    print(
        f"TIAGo, {len(spheres.spheres)} spheres (cover tolerance {args.tolerance:g} m), {len(scene.obstacles)} "
        f"obstacles and the floor: {n_pairs} pairs ({len(spheres.sphere_pairs)} self); "
        f"device {jax.devices()[0].platform}"
    )
    if hasattr(os, "getloadavg"):  # the ratios vary much less than the times with what else runs
        print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'variant':62s} {'configs':>8s} {'µs/config':>10s} {'computeDistances / mobman':>26s}")
    rows = [
        ("distances only, batched (mobman)", args.n, t_only),
        ("distances, witness points, normals and rows, batched (mobman)", args.n, t_whole),
        ("reference: Pinocchio computeDistances (coal), per configuration", args.reference, t_ref),
        ("  with the rows: computeJointJacobians, coal's normals, NumPy", args.reference, t_ref_rows),
    ]
    for name, count, t in rows:
        print(f"{name:62s} {count:8d} {1e6 * t:10.1f} {t_ref / t:26.2f}")
    print(f"the reference with the rows over mobman's batched rows: {t_ref_rows / t_whole:.2f}")
    # what one block of each batched program computes and moves per configuration (XLA's count)
    print_peak()
    block = q[: min(collision.BLOCK, args.n)]
    for label, part, t in (("distances only", 0, t_only), ("whole PairDistances", slice(None), t_whole)):
        program = jax.vmap(lambda x, part=part: collision.distances_one(spheres, scene, x)[part])
        print(roofline(f"{label}, batched", xla_cost(program, block).per(len(block)), t))
    caps = sum(n for _, _, n in theirs)
    print(
        f"max |distance − reference| = {err_d:.1e} m, max |row − reference| = {err_rows:.1e} m/s "
        f"over {args.reference} configurations ({caps} sphere–cylinder pairs from the cap's closed form)"
    )
    if not (err_d <= AGREEMENT and err_rows <= AGREEMENT):
        print("error: mobman and Pinocchio/coal disagree: the geometry or the pairs differ", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
