"""Benchmark: TIAGo's reachability map (``mobman.studies.maps.reachability_map``) against the same inverse
kinematics written with Pinocchio, cell by cell.

    python benchmarks/studies.py            # 1,001 cells in front of the platform (0.1 m), 20 for Pinocchio
    python benchmarks/studies.py --smoke    # tiny sizes (CI)

Every cell centre is reached from 8 starting postures, 60 damped least-squares steps each, within the joint
limits (``mobman.studies.reaching``: λ = 10⁻³, steps capped at 0.5, the joints at a limit that the step pushes
out held), and each reached cell scored by the highest Yoshikawa's w of the tool's position Jacobian among the
starts that reach it. The reference per
cell is what a Python script would write with Pinocchio: ``computeFrameJacobian`` (world-aligned, planar root
joint, the joints off the chain locked) and ``framesForwardKinematics`` at each step, the same step in NumPy,
and NumPy's determinant for w. Both are run on the same cells and the benchmark prints how far they agree: the same
iterations in another round-off may end a start in another posture, so a cell's best w can differ. Every
posture mobman reports is checked with Pinocchio (its tool within the tolerance of the cell's centre, its w
equal to the map's score); the run exits with an error beyond ``AGREEMENT``. The ratio is the reference's time per cell over mobman's; no timing is asserted.

Then collision-free placement: ``mobman.studies.placement.place`` for a target over the table of
``docs/examples/tiago_scene.toml`` (table and shelf), every base × start an inverse-kinematics problem whose
posture must be free of collision with the scene and with itself; the rate of problems per second is printed
with and without the scene (the cost of the collision checks). cuRobo's published rate, 7,000 collision-free
IK problems/s on a GPU, is printed beside it for scale: it is not run here (no GPU, another robot).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.io import scene as scene_file
from mobman.io.real_robots import REAL_ROBOTS
from mobman.model import robots
from mobman.studies.maps import reachability_map
from mobman.studies.placement import place
from mobman.studies.reaching import DAMPING, MAX_STEP, starting_postures

from real_robots import pinocchio_model
from timing import best_time

BOUNDS = [0.2, 0.8, -0.6, 0.6, 0.4, 1.4]
STARTS, ITERATIONS, TOLERANCE = 8, 60, 1e-4
AGREEMENT = 1e-9
"""Largest miss (m, beyond the tolerance) and difference of w (Pinocchio's against the map's) accepted."""

SCENE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_scene.toml"
PLACE_TARGET = [0.95, 0.0, 0.9]
CUROBO_IK_PER_S = 7_000
"""cuRobo's published collision-free IK rate on a GPU (Sundaralingam et al. 2023), for scale only."""


def pinocchio_tool(robot):
    """Pinocchio's TIAGo (:func:`real_robots.pinocchio_model`) as a function of the arm's coordinates, the
    platform at the origin with heading 0: q_a → (the tool's position, its 3 × n_a position Jacobian)."""
    import pinocchio as pin

    model = pinocchio_model(robot)
    data = model.createData()
    frame = model.getFrameId(REAL_ROBOTS["tiago"].tips[0])
    joints = [model.getJointId(j.name) for arm in robot.arms for j in arm.joints]
    rows, columns = [model.idx_qs[j] for j in joints], [model.idx_vs[j] for j in joints]
    q_pin = pin.neutral(model)
    q_pin[:4] = 0.0, 0.0, 1.0, 0.0

    def tool_and_jacobian(q_a):
        q_pin[rows] = q_a
        pin.framesForwardKinematics(model, data, q_pin)
        jac = pin.computeFrameJacobian(model, data, q_pin, frame, pin.LOCAL_WORLD_ALIGNED)
        return data.oMf[frame].translation.copy(), jac[:3, columns]

    return tool_and_jacobian


def pinocchio_cells(robot, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(reached, w) of each centre by the same solver, one cell and one step at a time with Pinocchio."""
    tool_and_jacobian = pinocchio_tool(robot)
    lower, upper = np.array(robot.position_limits[3:]).T
    starts = starting_postures(robot, STARTS)

    def solve(j, e):
        return j.T @ np.linalg.solve(j @ j.T + DAMPING**2 * np.eye(3), e)

    reached, score = np.zeros(len(centres), bool), np.full(len(centres), np.nan)
    for c, target in enumerate(centres):
        closest, best_w = np.inf, -np.inf
        for start in starts:
            q_a = np.clip(start, lower, upper)
            for _ in range(ITERATIONS):
                tool, j = tool_and_jacobian(q_a)
                e = target - tool
                delta = solve(j, e)
                held = ((q_a <= lower) & (delta < 0)) | ((q_a >= upper) & (delta > 0))
                delta = solve(np.where(held, 0.0, j), e)
                delta *= min(1.0, MAX_STEP / max(np.abs(delta).max(), 1e-300))
                q_a = np.clip(q_a + delta, lower, upper)
            tool, j = tool_and_jacobian(q_a)
            closest = min(closest, np.linalg.norm(target - tool))
            if np.linalg.norm(target - tool) <= TOLERANCE:  # of the starts that reach it, the highest w
                best_w = max(best_w, np.sqrt(max(np.linalg.det(j @ j.T), 0.0)))
        if closest <= TOLERANCE:
            reached[c], score[c] = True, best_w
    return reached, score


def check_with_pinocchio(robot, result) -> float:
    """The largest distance of the tool from its cell's centre (beyond the tolerance) and difference of w
    from the map's score, at every reached cell's posture, by Pinocchio."""
    tool_and_jacobian = pinocchio_tool(robot)
    worst = 0.0
    for q, centre, w in zip(
        result.q[result.reached], result.centres()[result.reached], result.score[result.reached]
    ):
        tool, j = tool_and_jacobian(q[3:])
        miss = max(np.linalg.norm(tool - centre) - TOLERANCE, 0.0)
        worst = max(worst, miss, abs(np.sqrt(np.linalg.det(j @ j.T)) - w))
    return worst


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--step", type=float, default=0.1, help="cell size of mobman's map (m)")
    parser.add_argument("--reference", type=int, default=20, help="cells the Pinocchio loop is timed on")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.step, args.reference = 0.3, 2
    robot = robots.build("tiago")
    options = {"bounds": BOUNDS, "step": args.step, "starts": STARTS, "iterations": ITERATIONS}
    t0 = time.perf_counter()
    first = reachability_map(robot, **options)
    t_first = time.perf_counter() - t0
    t_map = best_time(lambda: reachability_map(robot, **options).score, 3)
    cells = first.reached.size
    centres = first.centres().reshape(-1, 3)
    pick = np.linspace(0, cells - 1, min(args.reference, cells)).astype(int)
    t0 = time.perf_counter()
    reached, score = pinocchio_cells(robot, centres[pick])
    t_pin = (time.perf_counter() - t0) / len(pick)
    ours = first.reached.reshape(-1)[pick], first.score.reshape(-1)[pick]
    both = reached & ours[0]
    spread = float(np.max(np.abs(score[both] - ours[1][both]))) if both.any() else 0.0
    gap = check_with_pinocchio(robot, first)
    per_cell = t_map / cells
    print(
        f"TIAGo's reachability map: {first.shape} cells of {args.step:g} m, {STARTS} starts × {ITERATIONS} steps"
    )
    print(f"{'variant':<62}{'ms/cell':>10}{'Pinocchio / mobman':>20}")
    print(
        f"{'mobman reachability_map, ' + f'{cells:,} cells in one call':<62}{1e3 * per_cell:>10.3f}{t_pin / per_cell:>20.1f}"
    )
    print(f"{'  the same, first call (compiling included)':<62}{1e3 * t_first / cells:>10.3f}{'':>20}")
    print(
        f"{f'Pinocchio + NumPy, the same solver per cell ({len(pick)} cells)':<62}{1e3 * t_pin:>10.3f}{1.0:>20.2f}"
    )
    print(
        f"reached: mobman {int(ours[0].sum())}, Pinocchio {int(reached.sum())} of the {len(pick)} cells; the best w "
        f"where both reach differs by up to {spread:.1e} (a start's iterates, in other round-off, may end in "
        "another posture)"
    )
    print(
        f"every posture mobman reports, by Pinocchio: tool off its centre and w off its score by at most {gap:.1e}"
    )
    placement_rates(robot, args.smoke)
    if gap > AGREEMENT:
        print(f"error: mobman and Pinocchio disagree by {gap:.1e} > {AGREEMENT:g}", file=sys.stderr)
        return 1
    return 0


def placement_rates(robot, smoke: bool) -> None:
    """Collision-free placement IK problems per second (module notes), with and without the scene."""
    grid = {"bearings": 4, "headings": 4, "starts": 2} if smoke else {}
    scene = scene_file.load(SCENE)
    print(f"placement for {PLACE_TARGET} over {SCENE.name}'s table: problems = bases × starts")
    print(f"{'variant':<62}{'problems':>10}{'problems/s':>14}{'reached':>9}")
    for name, extra in (("with the scene (postures free of collision)", {"scene": scene}), ("no scene", {})):
        result = place(robot, PLACE_TARGET, **grid, **extra)  # compiles
        t = best_time(lambda extra=extra: place(robot, PLACE_TARGET, **grid, **extra).score, 2)
        problems = result.bases.shape[0] * grid.get("starts", 4)
        print(
            f"{'mobman place, ' + name:<62}{problems:>10,}{problems / t:>14,.0f}{int(result.reached.sum()):>9}"
        )
    print(f"{'cuRobo, published (GPU; not run here)':<62}{'':>10}{CUROBO_IK_PER_S:>14,}")


if __name__ == "__main__":
    sys.exit(main())
