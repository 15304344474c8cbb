"""Yamamoto & Yun (1999): kinematic and dynamic task-space ellipsoids of a dual-arm mobile manipulator.

Robot of Tables 1–2 (:func:`mobman.model.robots.yamamoto_dual_arm`), a 2 kg object held rigidly by both hands.
The arms take mirror-symmetric postures, each at the global maximum of its own kinematic manipulability
√det(J Jᵀ) (tool-point position, 2 × 3 Jacobian), with both tool points at the object, in front of the
platform (0°) or on its left (90°). Fig. 3: kinematic ellipsoids for platform speed limits from very low to the
table's (1/r rad/s per wheel); Fig. 4: dynamic ellipsoids for wheel torque limits from 200 N·m down.

``results.json``: ``ellipses`` (one entry per ``kind`` kinematic/dynamic, ``object_angle_deg`` 0/90 and
``platform_scale``, the factor on the platform's maximum wheel speed or wheel torque: the ellipse's ``axes``,
semi-axes major first, ``directions``, directions[k] the unit direction of axes[k] in world (x, y), ``extents``
along the platform's x and y, ``area``, ``section_axes`` and the 3-D ``ellipsoid_axes``), ``dynamic_exact`` (the
same for the exact dynamic ellipsoid), ``fixed_dual_arm`` (the braked platform), ``claims`` ({id: claim, holds,
summary, numbers}) and ``settings``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
from matplotlib.figure import Figure

from mobman import kinematics
from mobman.dynamics import DynamicModel, yamamoto_model
from mobman.dynamics.ellipsoids import Ellipsoid, Grasp, dynamic_ellipsoid, kinematic_ellipsoid
from mobman.dynamics.grasp import HeldObject
from mobman.experiments.report import Reproduction
from mobman.io.output import save_figure
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Position

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


def paper_configuration(
    robot: MobileManipulator, angle_deg: float, posture: tuple[float, float]
) -> np.ndarray:
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
    section = e.section(TRANSLATION) if len(e.names) > len(TRANSLATION) else shadow
    return {
        "kind": kind,
        "object_angle_deg": angle,
        "platform_scale": scale,
        "axes": shadow.axes,
        "directions": np.swapaxes(shadow.directions, -1, -2),  # directions[k]: unit direction of axes[k]
        "extents": np.sqrt(np.diagonal(shadow.shape_matrix, axis1=-2, axis2=-1)),
        "area": shadow.volume,
        "section_axes": section.axes,
        "ellipsoid_axes": e.axes,
    }


def _figure(
    robot: MobileManipulator,
    configs: dict[float, np.ndarray],
    ellipses: dict[float, Ellipsoid],
    scales: np.ndarray,
    unit: str,
    draw_scale: float,
    title: str,
    what: str,
) -> Figure:
    from matplotlib import colormaps

    from mobman.viz import draw_robot, frame_points

    fig = Figure(figsize=(10, 5))
    colors = colormaps["viridis"](np.linspace(0.0, 0.9, len(scales)))
    for k, (angle, q) in enumerate(configs.items()):
        ax = fig.add_subplot(1, 2, k + 1)
        draw_robot(ax, robot, frame_points(robot, q[None]), 0)
        center = np.asarray(kinematics.forward(robot, q, Position("xy", arm=0)))
        for j, scale in enumerate(scales):
            outline = ellipses[angle].boundary(keep=TRANSLATION)[j] * draw_scale + center
            ax.plot(
                outline[:, 0],
                outline[:, 1],
                color=colors[j],
                lw=1.2,
                label=f"{what} × {scale:g}" if scale > 0 else "platform fixed",
            )
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"object at {angle:g}°")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"{title} (drawn at {draw_scale:g} m per {unit})")
    return fig


def _split(e: Ellipsoid, index: int | tuple[int, ...]) -> Ellipsoid:
    return Ellipsoid(e.center[index], e.matrix[index], e.names, e.feasible[index])


def _ellipses(
    model: DynamicModel, q: np.ndarray, speed_scales: np.ndarray, torque_scales: np.ndarray, grasp: Grasp
) -> dict:
    """Fig. 3 and Fig. 4 ellipsoids for one grasp, batched over (angle, scale): one compilation per kind."""
    robot, obj, limits = model.robot, held_object(), torque_limits(model.robot)
    common: dict[str, Any] = {"obj": obj, "grasp": grasp}
    paper: dict[str, Any] = {"method": "paper", "interaction": False, **common}
    return {
        "kinematic": kinematic_ellipsoid(robot, q, held=True, grasp=grasp, platform_scale=speed_scales),
        "dynamic": dynamic_ellipsoid(model, q, limits, platform_scale=torque_scales, **paper),
        "dynamic_fixed": dynamic_ellipsoid(model, q, limits, platform_fixed=True, **paper),
        "exact": dynamic_ellipsoid(model, q, limits, platform_scale=torque_scales, method="exact", **common),
        "exact_fixed": dynamic_ellipsoid(model, q, limits, platform_fixed=True, method="exact", **common),
    }


def _records(e: dict, speed_scales: np.ndarray, torque_scales: np.ndarray) -> tuple[list, list, dict]:
    """(ellipses, dynamic_exact, fixed_dual_arm) records of one grasp; scale 0 of the kinematic batch is the
    fixed dual arm."""
    records, exact_records = [], []
    for i, angle in enumerate(ANGLES):
        for j, s in enumerate(speed_scales):
            records.append(_record("kinematic", angle, float(s), _split(e["kinematic"], (i, j))))
        for j, s in enumerate(torque_scales):
            records.append(_record("dynamic", angle, float(s), _split(e["dynamic"], (i, j))))
            exact_records.append(_record("dynamic", angle, float(s), _split(e["exact"], (i, j))))
    fixed = {
        name: [_record(kind, a, 0.0, _split(e[key], (i, 0))) for i, a in enumerate(ANGLES)]
        for name, kind, key in (
            ("kinematic", "kinematic", "kinematic"),
            ("dynamic", "dynamic", "dynamic_fixed"),
            ("dynamic_exact", "dynamic", "exact_fixed"),
        )
    }
    return records, exact_records, fixed


def run(out: Path, quick: bool = False) -> Reproduction:
    """Rebuild Fig. 3 and Fig. 4 of the paper into ``out``, for a rigid grasp and (``point_grasp``) a pivot grasp."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    model = yamamoto_model()  # Tables 1–2 inertials, horizontal motion (no gravity)
    robot = model.robot
    posture = optimal_posture(robot)
    configs = {a: paper_configuration(robot, a, posture) for a in ANGLES}
    q = np.stack(list(configs.values()))[:, None]  # (angle, scale) batch; one shape, one compilation
    speed_scales = np.array((0.0, 0.01, 0.5, 1.0) if quick else (0.0, 0.01, 0.1, 0.25, 0.5, 0.75, 1.0))
    torque_scales = np.array((1.0, 0.1, 0.01) if quick else (1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01))
    limits = torque_limits(robot)

    rigid = _ellipses(model, q, speed_scales, torque_scales, "rigid")
    point = _ellipses(model, q, speed_scales, torque_scales, "point")
    records, exact_records, fixed = _records(rigid, speed_scales, torque_scales)
    point_records, point_exact, point_fixed = _records(point, speed_scales, torque_scales)
    claims = _claims(records, exact_records, fixed, "rigid") | _claims(
        point_records, point_exact, point_fixed, "point"
    )

    figures = []
    for what, e, scales, unit, draw, title, name in (
        (
            "platform speed",
            rigid["kinematic"],
            speed_scales,
            "m/s",
            0.2,
            "Kinematic ellipses (Fig. 3)",
            "fig3_kinematic.png",
        ),
        (
            "wheel torque",
            rigid["dynamic"],
            torque_scales,
            "m/s²",
            0.02,
            "Dynamic ellipses, eq. 38 (Fig. 4)",
            "fig4_dynamic.png",
        ),
        (
            "wheel torque",
            rigid["exact"],
            torque_scales,
            "m/s²",
            0.02,
            "Dynamic ellipses, exact image of the torque ball",
            "fig4_dynamic_exact.png",
        ),
        (
            "wheel torque",
            point["dynamic"],
            torque_scales,
            "m/s²",
            0.02,
            "Dynamic ellipses, eq. 38, point grasp",
            "fig4_dynamic_point_grasp.png",
        ),
    ):
        per_angle = {a: _split(e, i) for i, a in enumerate(ANGLES)}
        fig = _figure(robot, configs, per_angle, scales, unit, draw, title, what)
        save_figure(fig, out / name, dpi=110)
        figures.append(out / name)

    settings = {
        "posture_deg": {"theta2": float(np.degrees(posture[0])), "theta3": float(np.degrees(posture[1]))},
        "configurations": {f"{a:g}": configs[a] for a in ANGLES},
        "object": {
            "mass_kg": OBJECT_MASS,
            "inertia_kgm2": OBJECT_INERTIA,
            "grasp": "both tool points at the "
            "object's centre of mass; rigid (ellipses, dynamic_exact, fixed_dual_arm) or through pivots "
            "(point_grasp)",
        },
        "torque_limits": limits,
        "velocity_normalisation": "wheel speeds 1/r rad/s, joint rates 3.14 rad/s",
        "dynamic_model": "paper: eq. 31–38 (J⁺, W⁺), platform–arm interaction neglected (§4.3); "
        "exact: image of the torque ball through the coupled closed-chain dynamics",
        "ellipse": "rigid grasp: projection of the (x_o, y_o, angle_o) ellipsoid on (x_o, y_o); point grasp: the "
        "(x_o, y_o) ellipse",
    }
    results = {
        "settings": settings,
        "ellipses": records,
        "dynamic_exact": exact_records,
        "claims": claims,
        "fixed_dual_arm": fixed,
        "point_grasp": {
            "ellipses": point_records,
            "dynamic_exact": point_exact,
            "fixed_dual_arm": point_fixed,
        },
    }
    return Reproduction(
        "yamamoto1999", TITLE, results, _report(settings, claims, records, exact_records), figures
    )


UNIFORM = 1.25  # "almost uniformly": the two growth (or shrink) factors within this ratio of each other
CLOSE = 0.05  # "almost identical / the same": relative difference of the semi-axes below 5 %
UNCHANGED = 1e-6  # "unchanged": relative change of a semi-axis below this (round-off)
METHODS = {"paper": "paper eq. 31–38", "exact": "exact image"}


def _row(records: list[dict], kind: str, angle: float, scale: float) -> dict:
    (row,) = [
        r
        for r in records
        if r["kind"] == kind and r["object_angle_deg"] == angle and r["platform_scale"] == scale
    ]
    return row


def _series(records: list[dict], kind: str, angle: float, key: str) -> tuple[np.ndarray, np.ndarray]:
    """(platform scales in increasing order, the record's ``key`` at each)."""
    rows = sorted(
        (r for r in records if r["kind"] == kind and r["object_angle_deg"] == angle),
        key=lambda r: r["platform_scale"],
    )
    return np.array([r["platform_scale"] for r in rows]), np.array([r[key] for r in rows])


def _rel(a: npt.ArrayLike, b: npt.ArrayLike) -> float:
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)) / np.abs(np.asarray(b))))


def _claim(text: str, holds: bool | np.bool_, summary: str, **numbers: Any) -> dict:
    return {"claim": text, "holds": bool(holds), "summary": summary, "numbers": numbers}


def _claims(records: list[dict], exact_records: list[dict], fixed: dict, grasp: str) -> dict:
    """Each statement of §4.2–4.3 checked on the ellipses of one grasp (semi-axes of the (x_o, y_o) ellipse;
    ``extents`` are its half-widths along the platform's heading x and lateral y; by the mirror symmetry the
    ellipses are aligned with x and y). Returns {id: {claim, holds, summary, numbers}}; the ids of the point
    grasp end with ``_point_grasp`` and its claims with "(point grasp)"."""
    fmt = lambda v: "[" + ", ".join(f"{x:.4g}" for x in np.ravel(v)) + "]"  # noqa: E731
    claims = {}
    speeds, kin90 = _series(records, "kinematic", 90.0, "axes")
    moving = speeds > 0
    minor, major = kin90[moving, 1], kin90[moving, 0]
    _, ext90 = _series(records, "kinematic", 90.0, "extents")
    claims["kinematic_90_minor_axis_unchanged"] = _claim(
        "Kinematic, object at 90°: the minor axis does not grow with the platform's maximum velocity (no lateral "
        "motion of the platform), while the platform still enlarges the other axis",
        _rel(minor, minor[0]) < UNCHANGED
        and major[-1] / major[0] > 1.2
        and np.all(ext90[moving, 1] == np.min(ext90[moving], axis=1)),
        f"minor (lateral y) semi-axis {fmt(minor)} m/s, major {fmt(major)} m/s for platform × {fmt(speeds[moving])}",
        platform_scale=speeds[moving],
        minor_axis=minor,
        major_axis=major,
    )
    _, kin0 = _series(records, "kinematic", 0.0, "axes")
    growth = kin0[moving][-1] / kin0[moving][0]
    claims["kinematic_0_grows_uniformly"] = _claim(
        "Kinematic, object at 0° (in front): the ellipsoid grows almost uniformly with the platform's velocity",
        min(growth) > 1.2 and max(growth) / min(growth) < UNIFORM,
        f"growth of (major, minor) from platform × {speeds[moving][0]:g} to × {speeds[-1]:g}: {fmt(growth)}",
        growth_major_minor=growth,
    )
    low = {a: _row(records, "kinematic", a, speeds[moving][0])["axes"] for a in ANGLES}
    diff = [_rel(low[a], fixed["kinematic"][k]["axes"]) for k, a in enumerate(ANGLES)]
    claims["kinematic_low_speed_is_fixed_dual_arm"] = _claim(
        "Kinematic: with a very low platform velocity the ellipsoid is almost that of a fixed dual-arm system, at "
        "0° and at 90°",
        max(diff) < CLOSE,
        f"relative difference of the semi-axes at platform × {speeds[moving][0]:g} (0°, 90°): {fmt(diff)}",
        relative_difference=diff,
    )
    for method, recs, fixed_key in (("paper", records, "dynamic"), ("exact", exact_records, "dynamic_exact")):
        label = METHODS[method]
        torques, _ = _series(recs, "dynamic", 0.0, "axes")
        top, bottom = torques[-1], torques[0]
        diff = [
            _rel(_row(recs, "dynamic", a, top)["axes"], fixed[fixed_key][k]["axes"])
            for k, a in enumerate(ANGLES)
        ]
        claims[f"dynamic_{method}_large_torque_is_fixed_dual_arm"] = _claim(
            f"Dynamic ({label}): with large wheel torques (200 N·m) the ellipsoid is that of a fixed dual-arm system, "
            "the same at 0° and 90°",
            max(diff) < CLOSE,
            f"relative difference of the semi-axes from the braked platform's (0°, 90°): {fmt(diff)}",
            relative_difference=diff,
        )
        _, ext = _series(recs, "dynamic", 90.0, "extents")
        lateral, heading = ext[:, 1], ext[:, 0]
        is_major = lateral >= heading * (1 - 1e-9)
        claims[f"dynamic_{method}_90_major_axis_unchanged"] = _claim(
            f"Dynamic ({label}), object at 90°: the major axis remains unchanged as the wheel torque decreases",
            _rel(lateral, lateral[-1]) < UNCHANGED and bool(np.all(is_major)) and heading[0] < heading[-1],
            f"lateral (y) semi-axis {fmt(lateral)}, heading (x) {fmt(heading)} m/s² for wheel torque × {fmt(torques)}; "
            f"the unchanged lateral axis is the major one at × {fmt(torques[is_major])}",
            platform_scale=torques,
            lateral_axis=lateral,
            heading_axis=heading,
            lateral_is_major=is_major,
        )
        shrink = _row(recs, "dynamic", 0.0, bottom)["extents"] / _row(recs, "dynamic", 0.0, top)["extents"]
        claims[f"dynamic_{method}_0_shrinks_uniformly"] = _claim(
            f"Dynamic ({label}), object at 0°: the ellipsoid shrinks rapidly and almost uniformly as the wheel torque "
            "decreases",
            max(shrink) < 0.9 and max(shrink) / min(shrink) < UNIFORM,
            f"shrink (heading x, lateral y) from × {top:g} to × {bottom:g}: {fmt(shrink)}",
            shrink_xy=shrink,
        )
    if grasp == "point":
        claims = {
            f"{key}_point_grasp": c | {"claim": c["claim"] + " (point grasp)"} for key, c in claims.items()
        }
    return claims


TYPOS = [
    "Eq. (26): the sphere (25) in normalised rates is q̄̇ = Ĵ⁺ v (Ĵ = J Y⁻¹ already contains the normalisation); the "
    "printed (Y Ĵ⁺ v)ᵀ(Y Ĵ⁺ v) applies Y a second time (the rates would be divided by their maxima squared), and its "
    "second line ends with a stray transpose. Correct: v_oᵀ (Ĵ⁺ Wᵀ)ᵀ(Ĵ⁺ Wᵀ) v_o = 1, i.e. v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o = 1 "
    "(tests/test_dynamics_ellipsoids.py::test_printed_eq26_is_a_typo).",
    "Eq. (35): μ_o = Q⁻¹ ξ + … contradicts the line above it in eq. (33), which has −Q⁻¹ ξ (from eq. 28); the sign "
    "must be minus. With the object moving, μ_o also needs the velocity terms P J⁺(Ẇᵀ v_o − J̇ ẋ) and Jᵀ W⁺ c_o "
    "that eq. (27)–(30) drop by assuming rest (tests/test_dynamics_ellipsoids.py::test_velocity_offset_mu_corrected_eq35).",
    "Eq. (34) names the matrix Λ, eq. (33) and (38) Λ_o (the same matrix).",
    "Eq. (28): q̈ stands for ẋ = (η̇, ¹q̈, ²q̈), the derivative of the reduced velocities of eq. (16), not of the "
    "generalized coordinates; likewise J in (27)–(35) is the Jacobian in the reduced velocities x of eq. (39).",
    "Eq. (31) and (32) are particular choices, not consequences of (27)–(30): the minimum-norm accelerations J⁺ Wᵀ a_o "
    "(no self-motion of the 8 − 6 = 2 redundant coordinates) and the minimum-norm grasp force W⁺(M_o a_o + g_o) "
    "(no internal force). So eq. (38) is the set of accelerations reached with those choices, a subset of what "
    "admissible torques can produce (the `exact` ellipsoid here).",
    "Outside (23)–(38): in eq. (15)–(16) the block P₁₃ = Sᵀ ᵛR₁ should be Sᵀ ᵛR₂, and the last diagonal block of Q "
    "is printed as 1 instead of I.",
]


def _report(settings: dict, claims: dict, records: list[dict], exact_records: list[dict]) -> str:
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
        "- Kinematic normalisation (Fig. 3): wheel speeds ≤ 1/r rad/s (Table 2) × platform_scale, joint rates ≤ 3.14 "
        "rad/s; platform_scale 0 is the fixed dual arm.",
        "- Dynamic normalisation (Fig. 4): wheel torques ≤ 200 N·m × platform_scale, joint torques ≤ 200, 100, 30 N·m "
        "(Table 1). No gravity (horizontal motion), at rest (μ_o = 0, eq. 40).",
        "- `dynamic` = the paper's eq. 31–38 (minimum-norm J⁺ in wheel/joint coordinates and W⁺, platform–arm "
        "interaction neglected as in §4.3); `dynamic_exact` = every object acceleration that torques within the "
        "limits produce, through the coupled closed-chain dynamics. The fixed dual arm: the platform braked.",
        "- The ellipse is the projection of the 3-D (x_o, y_o, angle_o) ellipsoid on the plane (x_o, y_o): object "
        "translational velocities / accelerations, the object's rotation free. `axes` are its semi-axes, major first; "
        "`extents` its half-widths along the platform's x (heading) and y (lateral) axes.",
        "",
        "## Claims",
        "",
        "Each row is evaluated for a rigid grasp and for a point (pivot) grasp, see the discussion. "
        "The four claims of the paper's discussion are rows 1, 2, 4–5 and 6–7 (kinematic 90° minor axis; kinematic 0° uniform growth; "
        "dynamic ≈ fixed dual arm at large wheel torque; dynamic 90° major axis unchanged); rows 3 and 8–9 are the "
        "paper's other statements.",
        "",
        "| # | claim | holds | numbers |",
        "|---|---|---|---|",
    ]
    order = [
        "kinematic_90_minor_axis_unchanged",
        "kinematic_0_grows_uniformly",
        "kinematic_low_speed_is_fixed_dual_arm",
        "dynamic_paper_large_torque_is_fixed_dual_arm",
        "dynamic_exact_large_torque_is_fixed_dual_arm",
        "dynamic_paper_90_major_axis_unchanged",
        "dynamic_exact_90_major_axis_unchanged",
        "dynamic_paper_0_shrinks_uniformly",
        "dynamic_exact_0_shrinks_uniformly",
    ]
    for suffix, heading in (("", "rigid grasp"), ("_point_grasp", "point grasp")):
        for k, key in enumerate(order, start=1):
            c = claims[key + suffix]
            lines.append(
                f"| {k} ({heading}) | {c['claim']} | {'yes' if c['holds'] else '**no**'} | {c['summary']} |"
            )
    lines += [
        "",
        f"Thresholds: 'almost uniformly' = the two factors within a ratio {UNIFORM}; 'the same / almost identical' = "
        f"semi-axes within {CLOSE:.0%}; 'unchanged' = relative change below {UNCHANGED:g}.",
        "",
        "## Discussion",
        "",
        "The first four points are about the rigid grasp, the last one about the point grasp.",
        "",
        "- Kinematics (claims 1–3 hold): at 90° both platform velocities (v, ω) move a point on the platform's lateral "
        "axis along the heading x only, so the lateral (minor) axis is exactly that of the fixed dual arm, while the "
        "major axis doubles at full speed. In front (0°) v moves the object along x and ω along y: both axes about "
        "double.",
        "- Dynamics at 90° (claim 4, rows 6–7): a lateral push on the object loads the platform sideways, where the "
        "wheels' no-slip constraint carries it without any wheel torque: the lateral axis does not depend on the "
        "wheel torque with either ellipsoid. In the exact ellipsoid it is the major axis at every torque, so the "
        "claim holds. With eq. 31–38 the lateral axis is unchanged too, but at 200 N·m it is a few percent shorter "
        "than the heading axis: it becomes the major one only once the wheel torque is well below its table value "
        "(row 6 lists the scales), so the claim holds only in part.",
        "- Large wheel torque (claim 3, rows 4–5): the exact ellipsoid at 200 N·m is within a few percent of the "
        "braked platform's at both angles. With eq. 31–38 it is not at 0°: the minimum-norm J⁺ gives the wheels a "
        "share of every heading acceleration, which unloads the arms, so the ellipse is larger than the fixed dual "
        "arm's along x, however large the wheel torque.",
        "- Dynamics at 0° (rows 8–9, not reproduced): with eq. 31–38 the heading (x) axis collapses with the wheel "
        "torque while the lateral axis keeps about 90 %: the yaw needed for a lateral acceleration costs little wheel "
        "torque. In the exact ellipsoid the lateral axis does not change at all (the two shoulder torques cancel "
        "each other's reaction on the platform through an internal force on the object) and the heading axis shrinks "
        "by a few percent only: from rest the 94 kg platform barely needs its wheels to let the arms accelerate a "
        "2 kg object. The paper's figure, its grasp geometry and the plane of its ellipses are not given, so part of "
        "the difference may lie in those choices.",
        "- Grasp: the paper's ellipses are 2-D, and both hands are at one point, so the grasp may be a pivot "
        "(`point_grasp`: forces only, W = [I₂ I₂], object (x_o, y_o)) rather than rigid. With it the paper's own "
        "eq. 31–38 reproduce claim 4 (at 90° the lateral axis is the major one at every torque and does not change), "
        "but at 0° the kinematic ellipse no longer grows uniformly (the heading axis grows by about 1.2, the lateral "
        "by 2: each arm's free wrist no longer has to turn with the object), the large-torque dynamic ellipse "
        "differs from the fixed dual arm's by about 11 %, and at 0° both dynamic axes shrink quickly but not "
        "uniformly. No single reading reproduces all the statements; the numbers of both are given.",
        "",
        "## Typos and hidden choices in eq. (23)–(38)",
        "",
        *[f"- {t}" for t in TYPOS],
    ]
    return "\n".join(lines)
