"""Korayem, Ghariblu & Basu, *Analysis of kinematic redundancy on mobile manipulators*: maximum allowable
load along the two case studies (Korayem eq. 34; paper: 20.188 kg for case 1, 37.147 kg for case 2).

The motions are those of :mod:`mobman.experiments.korayem_kinematics` (imported, not copied): the end effector
of ``korayem_planar`` follows the same straight line in 2 s, the redundancy fixed by the extra task of
case 1 (orientation α and elbow angle β, eq. 35–36) or case 2 (base point F, eq. 37). Along each motion the
joint torques are affine in the payload mass, τ = τ0 + m τ1 (:mod:`mobman.dynamics.load_capacity`), and the
largest m keeping both joint motors inside T⁻ ≤ τ ≤ T⁺, T± = ±k1 − k2 q̇ (k1 = 63.22 N·m, ω_nl = 3.5 rad/s,
k2 = k1/ω_nl) is the maximum allowable load.

The seed text of the paper gives no masses or inertias (its reference [11], where they would be, is not
available). :data:`PARAMETERS` are documented choices; the platform and wheel values do not influence the
result (only the joint actuators are limited, as in the paper, and the prescribed base motion fixes what the
arm feels of the platform), the link values do.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from mobman import dynamics as dyn
from mobman import viz
from mobman.dynamics.actuators import DCMotor
from mobman.dynamics.load_capacity import (
    LoadCapacity,
    capacity_from_torques,
    eta_dot_from_samples,
    max_load,
)
from mobman.experiments import korayem_kinematics as kinematics
from mobman.experiments.report import Reproduction
from mobman.io.output import save_figure
from mobman.model import robots
from mobman.model.arm import LinkInertial

NAME = "korayem-load"
TITLE = "Korayem, Ghariblu & Basu — maximum allowable load along the two redundancy-resolution case studies"

PAPER_MAX_LOAD_KG = {1: 20.188, 2: 37.147}
"""The paper's maximum allowable loads: case 1 (extra task α, β) and case 2 (extra task F)."""

STALL_TORQUE = 63.22
"""k1 = T_s (N·m) of both joint motors (paper)."""
NO_LOAD_SPEED = 3.5
"""ω_nl (rad/s) of both joint motors (paper)."""

PARAMETERS: dict[str, Any] = {
    "l0_m": 0.4,
    "l1_m": 0.5,
    "l2_m": 0.5,
    "link_mass_kg": 5.0,
    "link_inertia_kg_m2": 5.0 * 0.5**2 / 12,
    "link_com": "mid-length (uniform rod)",
    "payload": "point mass at the tool tip (end of link 2)",
    "platform_mass_kg": 40.0,
    "platform_inertia_z_kg_m2": 2.0,
    "wheel_mass_kg": 1.0,
    "wheel_I_w_kg_m2": 0.005,
    "wheel_I_m_kg_m2": 0.0025,
    "wheel_radius_m": 0.1,
    "half_track_m": 0.25,
    "joint_motor_k1_Nm": STALL_TORQUE,
    "joint_motor_omega_nl_rad_s": NO_LOAD_SPEED,
    "joint_motor_k2_Nm_s": STALL_TORQUE / NO_LOAD_SPEED,
    "wheel_actuators": "unlimited (the paper limits the joint actuators only)",
    "gravity": "vertical; the arm moves in the horizontal plane, so gravity loads no actuator",
    "time_law": kinematics.TIMING,
    "eta_dot": "second-order finite differences of the simulated quasi-velocities",
}
"""Documented choices (the paper's seed text has no inertial data): 5-kg uniform links of 0.5 m (I = m l²/12
about the centre of mass, vertical axis), a point payload at the tool tip, a 40-kg platform."""


def dynamic_model() -> dyn.DynamicModel:
    """``korayem_planar`` (l0 = 0.4, l1 = l2 = 0.5 m) with the inertials of :data:`PARAMETERS`."""
    p = PARAMETERS
    robot = robots.korayem_planar(l0=p["l0_m"], l1=p["l1_m"], l2=p["l2_m"])
    inertia = p["link_inertia_kg_m2"]
    links = [
        LinkInertial(p["link_mass_kg"], (length / 2, 0.0, 0.0), (0.0, inertia, inertia))
        for length in (p["l1_m"], p["l2_m"])
    ]
    return dyn.DynamicModel(
        robot.with_link_inertials(links),
        dyn.PlatformBody(p["platform_mass_kg"], p["platform_inertia_z_kg_m2"]),
        dyn.Wheel(p["wheel_mass_kg"], p["wheel_I_w_kg_m2"], p["wheel_I_m_kg_m2"]),
        payload=dyn.Payload(1.0),
    )


LINK_MASS_FACTORS = (0.5, 2.0)
"""Sensitivity: link masses (and inertias, uniform rods) scaled by these factors."""


def link_mass_sensitivity(
    capacity: LoadCapacity, factors: tuple[float, ...] = LINK_MASS_FACTORS
) -> dict[float, float]:
    """Maximum load (kg) with every link mass and inertia scaled by each factor, from the same τ0, τ1.

    Exact without recomputing the dynamics: the joint rows of the reduced equations involve the arm's bodies
    only (the platform's bodies do not move with the joints, and the base motion is prescribed), so with no
    payload the joint torques scale with the links' mass, τ0_joints → factor · τ0_joints, while τ1 is
    unchanged. The wheel columns are not rescaled (the wheels are unlimited).
    """
    joints = [i for i, name in enumerate(capacity.names) if name in joint_motors()]
    result = {}
    for factor in factors:
        tau0 = capacity.tau0.copy()
        tau0[:, joints] *= factor
        result[factor * PARAMETERS["link_mass_kg"]] = capacity_from_torques(
            capacity.names, capacity.t, tau0, capacity.tau1, capacity.speed, joint_motors()
        ).max_load
    return result


def joint_motors() -> dict[str, DCMotor]:
    """Both joint actuators: DC motors k1 = 63.22 N·m, ω_nl = 3.5 rad/s (eq. 34); the wheels are unlimited."""
    motor = DCMotor(STALL_TORQUE, NO_LOAD_SPEED)
    return {"theta1": motor, "theta2": motor}


def case_capacity(model: dyn.DynamicModel, case: kinematics.Model, dt: float) -> LoadCapacity:
    """The maximum allowable load along the augmented-Jacobian motion of ``case`` (Korayem model 1 or 2)."""
    run = kinematics.run_model(model.robot, case, dt)
    return max_load(model, run.t, run.q, run.eta, eta_dot_from_samples(run.t, run.eta), joint_motors())


def profile_figure(capacities: dict[int, LoadCapacity]) -> Figure:
    """The allowable load at each instant of the trajectory (its minimum is the maximum allowable load)."""
    t = next(iter(capacities.values())).t
    curves = {f"case {k}": np.minimum(c.profile, 500.0) for k, c in capacities.items()}
    return viz.plot_timeseries(
        t,
        {"allowable load (kg, clipped at 500)": curves},
        title="Korayem: allowable load along the trajectory",
    )


def summarize(number: int, case: kinematics.Model, capacity: LoadCapacity) -> dict:
    at_load = capacity.torques(capacity.max_load)
    wheels = [i for i, n in enumerate(capacity.names) if n.startswith("wheel")]
    return {
        "case": number,
        "extra_task": list(case.extra.names),
        **capacity.summary(),
        "paper_max_load_kg": PAPER_MAX_LOAD_KG[number],
        "relative_difference": capacity.max_load / PAPER_MAX_LOAD_KG[number] - 1.0,
        "peak_joint_speed_rad_s": float(np.max(np.abs(capacity.speed[:, 2:]))),
        "peak_joint_torque_at_max_load_Nm": float(np.max(np.abs(at_load[:, 2:]))),
        "peak_wheel_torque_at_max_load_Nm": float(np.max(np.abs(at_load[:, wheels]))),
        "max_load_kg_by_link_mass": {
            PARAMETERS["link_mass_kg"]: capacity.max_load,
            **link_mass_sensitivity(capacity),
        },
    }


def run(out: Path, quick: bool = False) -> Reproduction:
    """Both case studies (``quick``: coarser time step); torque figures and the load profile into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    dt = 0.01 if quick else 0.002
    model = dynamic_model()
    cases, capacities, figures = [], {}, []
    for case in kinematics.models():
        capacity = case_capacity(model, case, dt)
        capacities[case.number] = capacity
        cases.append(summarize(case.number, case, capacity))
        path = out / f"case{case.number}_torques.png"
        title = f"Korayem case {case.number}: joint torques vs DC-motor envelopes"
        save_figure(viz.plot_torques(capacity, title), path, dpi=110)
        figures.append(path)
    path = out / "allowable_load.png"
    save_figure(profile_figure(capacities), path, dpi=110)
    figures.append(path)
    results = {
        "parameters": {**PARAMETERS, "dt_s": dt},
        "cases": cases,
        "case2_exceeds_case1": cases[1]["max_load_kg"] > cases[0]["max_load_kg"],
        "paper_case2_exceeds_case1": PAPER_MAX_LOAD_KG[2] > PAPER_MAX_LOAD_KG[1],
    }
    return Reproduction(NAME, TITLE, results, report(results), figures)


def report(results: dict) -> str:
    """The markdown report: parameters chosen, capacities next to the paper's, the comparison."""
    p = results["parameters"]
    c1, c2 = results["cases"]
    lines = [
        "## Settings",
        "",
        f"- Robot `korayem_planar` l0 = {p['l0_m']} m, l1 = l2 = {p['l1_m']} m; motions of `korayem-kinematics` "
        f"(augmented-Jacobian law, {p['time_law']} time law over 2 s, dt = {p['dt_s']} s); η̇ by finite differences.",
        f"- Joint motors (paper, eq. 34): k1 = {STALL_TORQUE} N·m, ω_nl = {NO_LOAD_SPEED} rad/s, "
        f"k2 = {p['joint_motor_k2_Nm_s']:.4f} N·m·s/rad; T± = ±k1 − k2 q̇. Wheels: {p['wheel_actuators']}.",
        "- **Inertial data are our choice** (the paper's text gives none; its reference [11] is unavailable): "
        f"links {p['link_mass_kg']} kg uniform rods (I = {p['link_inertia_kg_m2']:.5f} kg m² about the centre of "
        f"mass), payload a point mass at the tool tip; platform {p['platform_mass_kg']} kg, I_z = "
        f"{p['platform_inertia_z_kg_m2']} kg m², wheels {p['wheel_mass_kg']} kg (these do not affect the joint "
        "torques: the base motion is prescribed and the wheels are not limited). The arm moves in the horizontal "
        "plane, so gravity loads no actuator: the load is limited by inertia only.",
        "- Method: τ = τ0 + m τ1 exactly (reduced inverse dynamics without load, plus the unit payload's share); "
        "m_max = min over samples and actuators of the envelope margin divided by τ1.",
        "",
        "## Results",
        "",
        "| case | extra task | max load (kg) | paper (kg) | limiting actuator | limiting time (s) "
        "| peak joint speed (rad/s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in (c1, c2):
        lines.append(
            f"| {c['case']} | {', '.join(c['extra_task'])} | {c['max_load_kg']:.3f} | "
            f"{c['paper_max_load_kg']} | {c['limiting_actuator']} | {c['limiting_time']:.3f} | "
            f"{c['peak_joint_speed_rad_s']:.3f} |"
        )
    same_order = results["case2_exceeds_case1"] == results["paper_case2_exceeds_case1"]
    by_mass1, by_mass2 = c1["max_load_kg_by_link_mass"], c2["max_load_kg_by_link_mass"]
    lines += [
        "",
        "## Comparison with the paper",
        "",
        f"- Case 2 carries {'more' if results['case2_exceeds_case1'] else 'less'} than case 1 "
        f"({c2['max_load_kg']:.3f} kg vs {c1['max_load_kg']:.3f} kg): "
        + (
            "**the paper's ordering is reproduced** (37.147 kg > 20.188 kg)."
            if same_order
            else "**the paper's ordering (37.147 kg > 20.188 kg) is not reproduced**."
        ),
        f"- The values differ from the paper's (case 1 {100 * c1['relative_difference']:+.0f} %, case 2 "
        f"{100 * c2['relative_difference']:+.0f} %). They cannot be expected to agree: the link masses and inertias, "
        "the payload's shape, the time law along the straight lines (the paper's is not stated; a constant-speed "
        "law would demand infinite accelerations at the ends) and the model 1 initial base (inconsistent in the "
        "paper, see `korayem-kinematics`) are all unknown or corrected. The capacity scales with them: only the "
        "comparison between the cases is a meaningful check.",
        "- Sensitivity to the unknown link mass (both links, uniform rods; exact rescaling of τ0): "
        + "; ".join(
            f"{m:g} kg → case 1 {by_mass1[m]:.3f} kg, case 2 {by_mass2[m]:.3f} kg" for m in sorted(by_mass1)
        )
        + ". Case 2 carries more than case 1 for "
        + (
            "every link mass tried."
            if all(by_mass2[m] > by_mass1[m] for m in by_mass1)
            else "only some of them."
        ),
        "- Peak wheel torques at the maximum load (not limited): case 1 "
        f"{c1['peak_wheel_torque_at_max_load_Nm']:.2f} N·m, "
        f"case 2 {c2['peak_wheel_torque_at_max_load_Nm']:.2f} N·m.",
    ]
    return "\n".join(lines)


__all__ = [
    "LINK_MASS_FACTORS",
    "NAME",
    "PAPER_MAX_LOAD_KG",
    "PARAMETERS",
    "TITLE",
    "case_capacity",
    "dynamic_model",
    "joint_motors",
    "link_mass_sensitivity",
    "profile_figure",
    "run",
]
