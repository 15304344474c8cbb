"""Yamamoto & Yun (1999): kinematic and dynamic task-space ellipsoids of a dual-arm mobile manipulator.

Robot of Tables 1–2 (:func:`mobman.model.robots.yamamoto_dual_arm`), a 2 kg object held rigidly by both hands.
The arms take mirror-symmetric postures, each at the global maximum of its own kinematic manipulability
√det(J Jᵀ) (tool-point position, 2 × 3 Jacobian), with both tool points at the object, in front of the
platform (0°) or on its left (90°). Fig. 3: kinematic ellipsoids for platform speed limits from very low to the
table's (1/r rad/s per wheel); Fig. 4: dynamic ellipsoids for wheel torque limits from 200 N·m down.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from mobman import kinematics
from mobman.dynamics import yamamoto_model
from mobman.dynamics.ellipsoids import Ellipsoid, dynamic_ellipsoid, kinematic_ellipsoid
from mobman.dynamics.grasp import HeldObject
from mobman.experiments.report import Reproduction
from mobman.model.robot import MobileManipulator
from mobman.model.task import Position

TITLE = "Yamamoto & Yun (1999), Unified analysis on mobility and manipulability of mobile manipulators"

WHEEL_TORQUE_MAX = 200.0  # N·m, Table 2
JOINT_TORQUE_MAX = (200.0, 100.0, 30.0)  # N·m, Table 1
OBJECT_MASS = 2.0  # m_o (kg), Table 2
OBJECT_INERTIA = 0.01  # kg m² about the vertical: not in the paper; a 2 kg disc of radius 0.1 m
ANGLES = (0.0, 90.0)
TRANSLATION = (0, 1)  # (x_o, y_o) of the object coordinates (x_o, y_o, angle_o)


def torque_limits(robot: MobileManipulator) -> np.ndarray:
    """τ_max of the actuators: both wheels, then each arm's joints (Tables 1–2)."""
    return np.array((WHEEL_TORQUE_MAX,) * 2 + JOINT_TORQUE_MAX * len(robot.arms))


def held_object() -> HeldObject:
    return HeldObject(OBJECT_MASS, (0.0, 0.0, OBJECT_INERTIA))


def optimal_posture(robot: MobileManipulator) -> tuple[float, float]:
    """(θ2, θ3) maximising the tool-point manipulability √det(J Jᵀ) of one arm (θ1 does not change it).

    One batched evaluation over a 48 × 96 grid of (θ2, θ3) ∈ (0, π) × (−π, π), refined on a grid as fine again
    around the best point (resolution ≈ 0.08°); θ2 > 0 is the arm-1 (right-hand) branch, the mirror branch is (−θ2, −θ3).
    """
    def best(t2, t3):
        grid2, grid3 = np.meshgrid(t2, t3, indexing="ij")
        q = np.zeros(grid2.shape + (robot.n_q,))
        s = robot.arm_slice(0)
        q[..., s.start + 1], q[..., s.start + 2] = grid2, grid3
        j = np.asarray(kinematics.jacobian(robot, q, Position("xy", arm=0)))[..., s]
        w = np.linalg.det(j @ np.swapaxes(j, -1, -2))
        i = np.unravel_index(np.argmax(w), w.shape)
        return grid2[i], grid3[i]

    n = 48  # the same grid shape twice: one compilation
    t2, t3 = best(np.linspace(0.05, np.pi - 0.05, n), np.linspace(-np.pi, np.pi, 2 * n))
    step = np.pi / n
    return best(t2 + np.linspace(-step, step, n), t3 + np.linspace(-2 * step, 2 * step, 2 * n))


def paper_configuration(robot: MobileManipulator, angle_deg: float, posture: tuple[float, float]) -> np.ndarray:
    """Platform at the origin heading +x; both tool points at the same point in direction ``angle_deg`` from
    the platform axis, arm 1 with (θ2, θ3) = posture, arm 2 its mirror image about that direction."""
    t2, t3 = posture
    q = np.zeros(robot.n_q)
    s1, s2 = robot.arm_slice(0), robot.arm_slice(1)
    q[s1] = (0.0, t2, t3)
    tip = np.asarray(kinematics.forward(robot, q, Position("xy", arm=0)))
    gamma = np.arctan2(tip[1], tip[0])
    alpha = np.radians(angle_deg)
    q[s1] = (alpha - gamma, t2, t3)
    q[s2] = (alpha + gamma, -t2, -t3)
    return q


def _record(kind: str, angle: float, scale: float, e: Ellipsoid) -> dict:
    shadow = e.projection(TRANSLATION)
    section = e.section(TRANSLATION)
    return {
        "kind": kind,
        "object_angle_deg": angle,
        "platform_scale": scale,
        "axes": shadow.axes,
        "directions": shadow.directions,
        "extents": np.sqrt(np.diagonal(shadow.shape_matrix, axis1=-2, axis2=-1)),
        "area": shadow.volume,
        "section_axes": section.axes,
        "ellipsoid_axes": e.axes,
    }


def _figure(robot, configs, ellipses, scales, unit: str, draw_scale: float, title: str) -> Figure:
    from mobman.viz import draw_robot, frame_points

    fig = Figure(figsize=(10, 5))
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
    for k, (angle, q) in enumerate(configs.items()):
        ax = fig.add_subplot(1, 2, k + 1)
        draw_robot(ax, robot, frame_points(robot, q[None]), 0)
        center = np.asarray(kinematics.forward(robot, q, Position("xy", arm=0)))
        for j, scale in enumerate(scales):
            outline = ellipses[angle].boundary(keep=TRANSLATION)[j] * draw_scale + center
            ax.plot(outline[:, 0], outline[:, 1], color=colors[j % len(colors)], lw=1.2,
                    label=f"platform × {scale:g}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"object at {angle:g}°")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"{title} (drawn at {draw_scale:g} m per {unit})")
    return fig


def _extents(records, kind, angle, scale) -> np.ndarray:
    """Half-widths of the ellipse along the platform's x (heading) and y (lateral) axes."""
    (row,) = [r for r in records if r["kind"] == kind and r["object_angle_deg"] == angle
              and r["platform_scale"] == scale]
    return np.asarray(row["extents"])


def run(out: Path, quick: bool = False) -> Reproduction:
    """Rebuild Fig. 3 and Fig. 4 of the paper into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    model = yamamoto_model()  # Tables 1–2 inertials, horizontal motion (no gravity)
    robot = model.robot
    posture = optimal_posture(robot)
    configs = {a: paper_configuration(robot, a, posture) for a in ANGLES}
    q = np.stack(list(configs.values()))[:, None]  # (angle, scale) batch; one shape, one compilation
    speed_scales = np.array((0.0, 0.01, 0.5, 1.0) if quick else (0.0, 0.01, 0.1, 0.25, 0.5, 0.75, 1.0))
    torque_scales = np.array((1.0, 0.1, 0.01) if quick else (1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01))
    obj = held_object()
    limits = torque_limits(robot)

    kin = kinematic_ellipsoid(robot, q, held=True, platform_scale=speed_scales)  # scale 0: platform fixed
    paper = dict(obj=obj, method="paper", interaction=False)
    dyn = dynamic_ellipsoid(model, q, limits, platform_scale=torque_scales, **paper)
    dyn_fixed = dynamic_ellipsoid(model, q, limits, platform_fixed=True, **paper)
    exact_fixed = dynamic_ellipsoid(model, q, limits, platform_fixed=True, obj=obj, method="exact")
    exact = dynamic_ellipsoid(model, q, limits, platform_scale=torque_scales, obj=obj, method="exact")

    def split(e: Ellipsoid, index) -> Ellipsoid:
        return Ellipsoid(e.center[index], e.matrix[index], e.names, e.feasible[index])

    records, exact_records = [], []
    for i, angle in enumerate(ANGLES):
        for j, s in enumerate(speed_scales):
            records.append(_record("kinematic", angle, float(s), split(split(kin, i), j)))
        for j, s in enumerate(torque_scales):
            records.append(_record("dynamic", angle, float(s), split(split(dyn, i), j)))
            exact_records.append(_record("dynamic", angle, float(s), split(split(exact, i), j)))
    fixed = {name: {a: np.sqrt(np.diagonal(split(e, i).projection(TRANSLATION).shape_matrix))
                    for i, a in enumerate(ANGLES)}
             for name, e in (("kinematic", split(kin, (slice(None), 0))), ("dynamic", split(dyn_fixed, (slice(None), 0))),
                             ("dynamic_exact", split(exact_fixed, (slice(None), 0))))}

    claims = _claims(records, exact_records, fixed, speed_scales, torque_scales)
    figures = []
    for kind, e, scales, unit, draw, title, name in (
        ("kinematic", kin, speed_scales, "m/s", 0.2, "Kinematic ellipses (Fig. 3)", "fig3_kinematic.png"),
        ("dynamic", dyn, torque_scales, "m/s²", 0.02, "Dynamic ellipses (Fig. 4)", "fig4_dynamic.png"),
    ):
        per_angle = {a: split(e, i) for i, a in enumerate(ANGLES)}
        fig = _figure(robot, configs, per_angle, scales, unit, draw, title)
        fig.savefig(out / name, dpi=110)
        figures.append(out / name)

    settings = {
        "posture_deg": {"theta2": float(np.degrees(posture[0])), "theta3": float(np.degrees(posture[1]))},
        "configurations": {f"{a:g}": configs[a] for a in ANGLES},
        "object": {"mass_kg": OBJECT_MASS, "inertia_kgm2": OBJECT_INERTIA, "grasp": "both tool points at the "
                   "object's centre of mass, rigid"},
        "torque_limits": limits,
        "velocity_normalisation": "wheel speeds 1/r rad/s, joint rates 3.14 rad/s",
        "dynamic_model": "paper: eq. 31–38 (J⁺, W⁺), platform–arm interaction neglected (§4.3); "
                         "exact: image of the torque ball through the coupled closed-chain dynamics",
        "ellipse": "projection of the (x_o, y_o, angle_o) ellipsoid on (x_o, y_o)",
    }
    results = {"settings": settings, "ellipses": records, "dynamic_exact": exact_records, "claims": claims,
               "fixed_dual_arm_extents": fixed}
    return Reproduction("yamamoto1999", TITLE, results, _report(settings, claims, records, exact_records), figures)


def _claims(records, exact_records, fixed, speed_scales, torque_scales) -> dict:
    """The paper's statements as numbers: growth/shrink factors of the extents along (x, y) of the platform."""
    lo_v, hi_v = min(s for s in speed_scales if s > 0), max(speed_scales)
    lo_t, hi_t = min(torque_scales), max(torque_scales)

    def ratio(recs, kind, angle, a, b):
        return (_extents(recs, kind, angle, a) / _extents(recs, kind, angle, b)).tolist()

    def rel(a, b):
        return float(np.max(np.abs(np.asarray(a) - np.asarray(b)) / np.asarray(b)))

    full = {a: _extents(records, "dynamic", a, hi_t) for a in ANGLES}
    return {
        "kinematic_growth_xy": {f"{a:g}": ratio(records, "kinematic", a, hi_v, lo_v) for a in ANGLES},
        "kinematic_lowest_speed_vs_fixed_rel_diff": {
            f"{a:g}": rel(_extents(records, "kinematic", a, lo_v), fixed["kinematic"][a]) for a in ANGLES},
        "dynamic_shrink_xy": {f"{a:g}": ratio(records, "dynamic", a, lo_t, hi_t) for a in ANGLES},
        "dynamic_full_torque_0_vs_90_rel_diff": rel(np.sort(full[0.0]), np.sort(full[90.0])),
        "dynamic_full_torque_vs_fixed_rel_diff": {f"{a:g}": rel(full[a], fixed["dynamic"][a]) for a in ANGLES},
        "exact_dynamic_shrink_xy": {f"{a:g}": ratio(exact_records, "dynamic", a, lo_t, hi_t) for a in ANGLES},
        "exact_dynamic_full_torque_vs_fixed_rel_diff": {
            f"{a:g}": rel(_extents(exact_records, "dynamic", a, hi_t), fixed["dynamic_exact"][a]) for a in ANGLES},
    }


UNIFORM = 1.25  # "almost uniformly": the two growth (or shrink) factors differ by less than this ratio
CLOSE = 0.05  # "almost identical / the same": relative difference of the extents below 5 %


def _uniform(factors) -> bool:
    return max(factors) / min(factors) < UNIFORM


def _verdicts(claims) -> dict[str, bool]:
    """Each claim of §4.2–4.3 checked on the numbers of :func:`_claims` (thresholds UNIFORM and CLOSE)."""
    kin, dyn, exact = claims["kinematic_growth_xy"], claims["dynamic_shrink_xy"], claims["exact_dynamic_shrink_xy"]
    return {
        "kinematic: lowest platform speed ≈ fixed dual arm":
            max(claims["kinematic_lowest_speed_vs_fixed_rel_diff"].values()) < CLOSE,
        "kinematic 0°: grows almost uniformly": min(kin["0"]) > 1.2 and _uniform(kin["0"]),
        "kinematic 90°: minor (lateral) axis unchanged while the other grows":
            abs(kin["90"][1] - 1) < 1e-6 and kin["90"][0] > 1.2,
        "dynamic (paper eq. 38): full wheel torque ≈ fixed dual arm":
            max(claims["dynamic_full_torque_vs_fixed_rel_diff"].values()) < CLOSE,
        "dynamic (paper eq. 38): full wheel torque, 0° ≈ 90°": claims["dynamic_full_torque_0_vs_90_rel_diff"] < CLOSE,
        "dynamic (paper eq. 38) 90°: major (lateral) axis unchanged as the torque decreases":
            abs(dyn["90"][1] - 1) < 1e-6 and dyn["90"][0] < 1,
        "dynamic (paper eq. 38) 0°: shrinks almost uniformly": max(dyn["0"]) < 0.9 and _uniform(dyn["0"]),
        "dynamic (exact image): full wheel torque ≈ fixed dual arm":
            max(claims["exact_dynamic_full_torque_vs_fixed_rel_diff"].values()) < CLOSE,
        "dynamic (exact image) 90°: major (lateral) axis unchanged as the torque decreases":
            abs(exact["90"][1] - 1) < 1e-6 and exact["90"][0] < 1,
        "dynamic (exact image) 0°: shrinks almost uniformly": max(exact["0"]) < 0.9 and _uniform(exact["0"]),
    }


def _report(settings, claims, records, exact_records) -> str:
    verdicts = _verdicts(claims)
    fmt = lambda v: "[" + ", ".join(f"{x:.3g}" for x in v) + "]"  # noqa: E731
    posture = settings["posture_deg"]
    lines = [
        "## Settings",
        "",
        f"- Robot of Tables 1–2; both arm bases at the axle midpoint; platform heading +x. Each arm at the global "
        f"maximum of its tool-point manipulability √det(J Jᵀ): θ2 = ±{posture['theta2']:.2f}°, "
        f"θ3 = ±{posture['theta3']:.2f}° (mirror images), both tool points at the object, in front (0°) or on the left "
        "(90°) of the platform.",
        f"- Object: {OBJECT_MASS} kg (Table 2), inertia {OBJECT_INERTIA} kg m² about the vertical (not in the paper: a "
        "2 kg disc of radius 0.1 m), held rigidly by both hands at its centre of mass; task (x_o, y_o, angle_o).",
        "- Kinematic normalisation: wheel speeds ≤ 1/r rad/s (Table 2) × platform_scale, joint rates ≤ 3.14 rad/s.",
        "- Dynamic normalisation: wheel torques ≤ 200 N·m × platform_scale, joint torques ≤ 200, 100, 30 N·m. "
        "No gravity (horizontal motion), at rest (μ_o = 0).",
        "- `dynamic` = the paper's eq. 31–38 (minimum-norm J⁺ in wheel/joint coordinates and W⁺, platform–arm "
        "interaction neglected as in §4.3); `dynamic_exact` = every object acceleration that torques within the "
        "limits produce, through the coupled closed-chain dynamics.",
        "- The ellipse is the projection of the 3-D (x_o, y_o, angle_o) ellipsoid on the plane (x_o, y_o): object "
        "translational velocities / accelerations, the object's rotation free. `extents` are its half-widths along the "
        "platform's x (heading) and y (lateral) axes.",
        "",
        "## Claims",
        "",
        "| claim | holds | numbers |",
        "|---|---|---|",
    ]
    numbers = {
        "kinematic: lowest platform speed ≈ fixed dual arm":
            f"relative difference at platform × 0.01: {fmt(claims['kinematic_lowest_speed_vs_fixed_rel_diff'].values())}",
        "kinematic 0°: grows almost uniformly": f"growth (x, y) from × 0.01 to × 1: {fmt(claims['kinematic_growth_xy']['0'])}",
        "kinematic 90°: minor (lateral) axis unchanged while the other grows":
            f"growth (x, y): {fmt(claims['kinematic_growth_xy']['90'])}",
        "dynamic (paper eq. 38): full wheel torque ≈ fixed dual arm":
            f"relative difference (0°, 90°): {fmt(claims['dynamic_full_torque_vs_fixed_rel_diff'].values())}",
        "dynamic (paper eq. 38): full wheel torque, 0° ≈ 90°":
            f"relative difference: {claims['dynamic_full_torque_0_vs_90_rel_diff']:.3g}",
        "dynamic (paper eq. 38) 90°: major (lateral) axis unchanged as the torque decreases":
            f"shrink (x, y) from 200 to 2 N·m: {fmt(claims['dynamic_shrink_xy']['90'])}",
        "dynamic (paper eq. 38) 0°: shrinks almost uniformly": f"shrink (x, y): {fmt(claims['dynamic_shrink_xy']['0'])}",
        "dynamic (exact image): full wheel torque ≈ fixed dual arm":
            f"relative difference (0°, 90°): {fmt(claims['exact_dynamic_full_torque_vs_fixed_rel_diff'].values())}",
        "dynamic (exact image) 90°: major (lateral) axis unchanged as the torque decreases":
            f"shrink (x, y): {fmt(claims['exact_dynamic_shrink_xy']['90'])}",
        "dynamic (exact image) 0°: shrinks almost uniformly": f"shrink (x, y): {fmt(claims['exact_dynamic_shrink_xy']['0'])}",
    }
    for claim, ok in verdicts.items():
        lines.append(f"| {claim} | {'yes' if ok else '**no**'} | {numbers[claim]} |")
    lines += [
        "",
        f"Thresholds: 'almost uniformly' = growth factors within a ratio {UNIFORM}; '≈' = within {CLOSE:.0%}.",
        "",
        "## Discussion",
        "",
        "- Kinematics: at 90° the platform moves the object only along its heading (x): both η-directions map to x "
        "at a point on the platform's lateral axis, so the lateral (minor) axis is exactly that of the fixed dual arm. "
        "In front (0°) the forward speed moves the object along x and the yaw rate along y, and both extents double.",
        "- Dynamics at 90°: a lateral push on the object loads the platform sideways, where the wheels' no-slip "
        "constraint carries it without any wheel torque: the lateral axis does not depend on the wheel torque, in "
        "both the paper's and the exact ellipsoid.",
        "- Dynamics at 0°: the paper's claim that the ellipse shrinks almost uniformly is **not reproduced**. With "
        "eq. 31–38, the forward (x) extent collapses with the wheel torque (the minimum-norm J⁺ gives the wheels a share "
        "of every x acceleration, and the arms' reaction along x loads the wheels) while the lateral extent keeps about "
        "90 %: the yaw needed for a y acceleration costs little wheel torque. In the exact ellipsoid the y extent does not "
        "change at all (the two shoulder torques can cancel each other's reaction on the platform through an internal "
        "force on the object) and x shrinks by a few percent only. The paper's figure, its grasp geometry and the plane of "
        "its ellipses are unknown, so the difference may lie in those choices.",
        "- At 200 N·m the paper's ellipse at 0° is larger than the fixed dual arm's along x, because J⁺ lets the wheels "
        "contribute; the exact ellipse is within a few percent of the fixed one at both angles, and grows without bound "
        "with the wheel torque along the heading (platform × 100 in the tests).",
    ]
    return "\n".join(lines)
