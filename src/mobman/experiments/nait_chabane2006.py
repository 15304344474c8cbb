"""Nait-Chabane, Hoppenot & Colle (2006), §4.2: redundancy resolution of a Manus arm on a differential
platform with manipulability criteria (eq. 30), figures 9–16.

Setting (§4.2.2): platform at q_p = 0 heading along X_W, arm at q_a = (π/2, π/3, −π/3), arm base at
(0.12, 0.12, 0.4) m; the end effector follows a straight line at 0.05 m/s along X_W (case 1, along the
platform) or along Y_W (case 2, across it). Four strategies: the pseudo-inverse alone (``none``), and eq. 30
u = J̄⁺ Ẋd − (I − J̄⁺J̄) W (∂P/∂q M)ᵀ minimising P = w_a5 (``arm_w5``, eccentricity of the arm Jacobian),
P = w5 (``system_w5``, of the reduced Jacobian J̄) or P = w̃5 (``system_w5_normalized``, of J̄_N = J̄ R with
R = diag(u_max), eq. 20–26).

The arm frame {A} is turned by −π/2 about the vertical with respect to the platform frame (eq. 8:
x1 = x_p + (x_a2 + a) cos θ_p − (b − x_a1) sin θ_p, …, x4 = φ + θ_p − π/2), as ``robots.manus_platform``
mounts it: with q_a1 = π/2 the arm points forward, along the platform's heading.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import numpy.typing as npt
from matplotlib.figure import Figure

from mobman import kinematics as K
from mobman import manipulability as mp
from mobman import viz
from mobman.control import criteria, laws, metrics, references, simulate
from mobman.control.simulation import SimulationResult
from mobman.experiments.report import Reproduction
from mobman.io import trajectories
from mobman.io.output import save_figure
from mobman.model import robots
from mobman.model.robot import MobileManipulator

NAME = "nait-chabane2006"
TITLE = (
    "Nait-Chabane, Hoppenot & Colle (2006) — Mobile arm for disabled people assistance: manipulability "
    "measure for redundancy solve (§4.2, figures 9–16)"
)

SPEED = 0.05
"""End-effector speed along the lines (m/s), as in the paper."""
DURATION = 60.0
"""Length of each run (s); the paper gives none (its case 2 reaches the singular arm after 20 s)."""
GAIN = 1.0
"""The null-space weighting W = GAIN · I of eq. 30 used for the figures (the paper gives none)."""
GAINS = (0.3, 1.0, 3.0)
"""Gains of the sensitivity study (one compiled, batched run per case and strategy)."""
WA5_GOOD = 0.9
"""The paper's threshold: arm manipulation ability is satisfying when w_a5 < 0.9 (§4.2.3)."""
V_THRESHOLD = metrics.V_THRESHOLD
"""|v| (m/s) below which the platform speed counts as zero for the graining points."""

CASES = {1: (1.0, 0.0, 0.0), 2: (0.0, 1.0, 0.0)}
STRATEGIES = {
    "none": None,
    "arm_w5": "arm",
    "system_w5": "system",
    "system_w5_normalized": "system_normalized",
}
MEASURES = ("arm_w5", "system_w5", "system_normalized_w5")
FIGURES = {(case, s): 9 + 4 * (case - 1) + i for case in CASES for i, s in enumerate(STRATEGIES)}
"""The paper's figure number of each (case, strategy): 9–12 for case 1, 13–16 for case 2."""


def manus_robot() -> MobileManipulator:
    """``manus_platform`` with the dimensions of §4.2.2 (arm base at (0.12, 0.12, 0.4) m, eq. 8)."""
    return robots.manus_platform(L2=0.12, L3=0.35, L4=0.35, a=0.12, b=0.12, c=0.4)


def initial_configuration() -> np.ndarray:
    """q = (x_p, y_p, θ_p, q_a1, q_a2, q_a3) = (0, 0, 0, π/2, π/3, −π/3) (§4.2.2)."""
    return np.array([0.0, 0.0, 0.0, math.pi / 2, math.pi / 3, -math.pi / 3])


def reference(robot: MobileManipulator, case: int, duration: float) -> references.Line:
    """The straight line from the initial end-effector position at SPEED along X_W (case 1) or Y_W (case 2)."""
    start = np.asarray(K.forward(robot, initial_configuration()))
    end = start + SPEED * duration * np.asarray(CASES[case])
    return references.Line(tuple(start), tuple(end), duration, timing="linear")


def simulate_strategy(
    robot: MobileManipulator, case: int, strategy: str, duration: float, dt: float
) -> SimulationResult:
    """One strategy in one case: a single run for ``none``, a batch over GAINS (one compiled call) otherwise."""
    which = STRATEGIES[strategy]
    law: laws.NaitChabane | list[laws.NaitChabane]
    if which is None:
        law = laws.NaitChabane(W=1.0)  # no criterion: u = J̄⁺ Ẋd
    else:
        criterion = criteria.Manipulability("eccentricity", which)
        law = [laws.NaitChabane(W=g, criterion=criterion) for g in GAINS]
    return simulate(
        robot,
        None,
        law,
        reference(robot, case, duration),
        initial_configuration(),
        duration,
        dt,
        measures=MEASURES,
    )


def graining_times(t: npt.ArrayLike, v: npt.ArrayLike, threshold: float = V_THRESHOLD) -> np.ndarray:
    """Times at which the platform speed v changes sign (samples with |v| ≤ threshold ignored): the times of
    the graining points counted by :func:`mobman.control.metrics.graining_points`."""
    t, v = np.asarray(t), np.asarray(v)
    keep = np.abs(v) > threshold
    signs, times = np.sign(v[keep]), t[keep]
    return times[1:][signs[1:] != signs[:-1]]


def summarize(
    case: int, strategy: str, gain: float | None, result: SimulationResult, robot: MobileManipulator
) -> dict:
    """One row of results.json."""
    s = metrics.summarize(result, robot, v_threshold=V_THRESHOLD)
    wa5 = result.measures["arm_w5"]
    return {
        "case": case,
        "strategy": strategy,
        "gain": gain,
        "graining_points": s["graining_points"],
        "graining_times": graining_times(result.t, result.eta[:, 0]),
        "wa5_initial": float(wa5[0]),
        "wa5_min": s["arm_w5_min"],
        "wa5_max": s["arm_w5_max"],
        "wa5_final": s["arm_w5_final"],
        "wa5_min_time": float(result.t[np.argmin(wa5)]),
        "wa5_first_above_0.99": float(result.t[np.argmax(wa5 > 0.99)]) if np.any(wa5 > 0.99) else None,
        "w5_initial": float(result.measures["system_w5"][0]),
        "w5_final": s["system_w5_final"],
        "w5n_initial": float(result.measures["system_normalized_w5"][0]),
        "w5n_final": s["system_normalized_w5_final"],
        "max_tracking_error": s["max_error"],
        "v_initial": s["v_initial"],
        "platform_path_length": s["platform_path_length"],
        "acceleration_variation": s["acceleration_variation"],
    }


_LABELS = {"arm_w5": "w_a5 (arm)", "system_w5": "w5 (system)", "system_normalized_w5": "w̃5 (normalised)"}
_SHOWN = {
    "none": ("arm_w5",),
    "arm_w5": ("arm_w5",),
    "system_w5": ("arm_w5", "system_w5"),
    "system_w5_normalized": ("arm_w5", "system_normalized_w5"),
}


def strategy_figure(
    robot: MobileManipulator, case: int, strategy: str, gain: float | None, result: SimulationResult
) -> Figure:
    """The paper's figure for (case, strategy): (a) measures versus time, (b) EE and platform paths."""
    fig = Figure(figsize=(11.5, 4.6))
    ax_a, ax_b = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.0, 1.1]})
    curves = {_LABELS[m]: result.measures[m] for m in _SHOWN[strategy]}
    viz.draw_curves(
        ax_a,
        result.t,
        curves,
        hlines=(WA5_GOOD, 1.0),
        events={"graining point": graining_times(result.t, result.eta[:, 0])},
    )
    ax_a.set_xlabel("t (s)")
    ax_a.set_ylabel("eccentricity")
    ax_a.set_title(f"({FIGURES[case, strategy]}a) measures")
    viz.plot_paths(robot, result.q, instants=4, reference=result.xi_star[:, :2], ax=ax_b)
    ax_b.set_title(f"({FIGURES[case, strategy]}b) end-effector and platform paths")
    w = "" if gain is None else f", W = {gain:g}"
    fig.suptitle(f"Figure {FIGURES[case, strategy]} — case {case}, strategy {strategy}{w}")
    fig.tight_layout()
    return fig


def ellipses_figure(
    robot: MobileManipulator, case: int, runs: dict[str, SimulationResult], instants: int = 6
) -> Figure:
    """Arm ellipses (rows x, y of J_a, Nait-Chabane Fig. 5a style) along the EE path for w5 and w̃5."""
    fig = Figure(figsize=(11.5, 4.6))
    axes = fig.subplots(1, 2)
    for ax, strategy in zip(axes, ("system_w5", "system_w5_normalized")):
        result = runs[strategy]
        idx = np.unique(np.linspace(0, len(result.t) - 1, instants).round().astype(int))
        jac = np.asarray(mp.arm_jacobian(robot, result.q[idx]))[:, :2, :]
        viz.plot_ellipses(
            result.xi[idx, :2],
            jac,
            scale=0.5,
            path=result.xi[:, :2],
            labels="arm ellipse (xy)",
            title=f"case {case}, {strategy}: arm ellipses",
            ax=ax,
        )
    fig.tight_layout()
    return fig


def run(out: Path, quick: bool = False) -> Reproduction:
    """Both cases × four strategies (three gains each for the criteria); figures 9–16 into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    robot = manus_robot()
    dt = 1 / 32 if quick else 1 / 64  # binary fractions: k · dt is exact, the reference ends exactly at t = T
    entries, figures, motions = [], [], []
    for case in CASES:
        chosen: dict[str, SimulationResult] = {}
        for strategy in STRATEGIES:
            result = simulate_strategy(robot, case, strategy, DURATION, dt)
            runs: list[tuple[float | None, SimulationResult]]
            if STRATEGIES[strategy] is None:
                runs = [(None, result)]
            else:
                runs = [(g, result.run(i)) for i, g in enumerate(GAINS)]
            for gain, r in runs:
                entries.append(summarize(case, strategy, gain, r, robot))
                if gain is None or gain == GAIN:
                    chosen[strategy] = r
                    label = strategy if gain is None else f"{strategy}, W = {gain:g}"
                    motions.append(
                        trajectories.Motion.of(f"case {case}: {label}", robot, r.t, r.q, manus_robot)
                    )
                    fig = strategy_figure(robot, case, strategy, gain, r)
                    path = out / f"fig{FIGURES[case, strategy]}_case{case}_{strategy}.png"
                    save_figure(fig, path, dpi=100)
                    figures.append(path)
        path = out / f"ellipses_case{case}.png"
        save_figure(ellipses_figure(robot, case, chosen), path, dpi=100)
        figures.append(path)
        path = out / f"manus_3d_case{case}_normalized.png"
        figure = viz.plot_paths_3d(
            robot,
            chosen["system_w5_normalized"].q,
            instants=4,
            title=f"case {case}, system_w5_normalized, W = {GAIN:g}",
        )
        save_figure(figure, path, dpi=100)
        figures.append(path)
    trajectories.write(out, motions)
    return Reproduction(NAME, TITLE, entries, report(entries, dt), figures)


def _entry(entries: list[dict], case: int, strategy: str, gain: float | None) -> dict:
    gain = None if STRATEGIES[strategy] is None else gain
    return next(e for e in entries if e["case"] == case and e["strategy"] == strategy and e["gain"] == gain)


def claims(entries: list[dict], gain: float) -> list[tuple[str, bool, str]]:
    """The paper's claims (§4.2.2–4.2.3, conclusion) evaluated on the runs with null-space gain ``gain``:
    (statement, holds, evidence)."""

    def e(case: int, strategy: str) -> dict:
        return _entry(entries, case, strategy, gain)

    out = []
    n1 = e(1, "none")
    out.append(
        (
            "Case 1, no optimisation (Fig. 9): w_a5 improves at first, then deteriorates to 1 (arm extended)",
            n1["wa5_min"] < n1["wa5_initial"] - 0.02 and n1["wa5_final"] >= 0.99,
            f"w_a5 {n1['wa5_initial']:.3f} → min {n1['wa5_min']:.3f} at {n1['wa5_min_time']:.0f} s → "
            f"{n1['wa5_final']:.3f} at {DURATION:.0f} s",
        )
    )
    n2 = e(2, "none")
    out.append(
        (
            "Case 2, no optimisation (Fig. 13): the arm reaches a singular configuration (paper: after 20 s)",
            n2["wa5_first_above_0.99"] is not None,
            f"w_a5 min {n2['wa5_min']:.3f} at {n2['wa5_min_time']:.0f} s, first > 0.99 at "
            + (f"{n2['wa5_first_above_0.99']:.1f} s" if n2["wa5_first_above_0.99"] is not None else "never")
            + f", final {n2['wa5_final']:.4f}",
        )
    )
    a1, a2 = e(1, "arm_w5"), e(2, "arm_w5")
    out.append(
        (
            "Optimising w_a5 (Fig. 10, 14): w_a5 improves, stabilises near its minimum and stays below 0.9",
            all(a["wa5_max"] < WA5_GOOD and a["wa5_final"] - a["wa5_min"] < 0.01 for a in (a1, a2)),
            "; ".join(
                f"case {a['case']}: max {a['wa5_max']:.3f}, min {a['wa5_min']:.3f}, final {a['wa5_final']:.3f}"
                for a in (a1, a2)
            ),
        )
    )
    out.append(
        (
            "Case 1, w_a5 (Fig. 10): the platform first moves back a short distance, then forward",
            a1["v_initial"] < 0 and a1["graining_points"] == 1,
            f"v_initial {a1['v_initial']:+.3f} m/s, {a1['graining_points']} graining point(s)",
        )
    )
    out.append(
        (
            "Case 2, w_a5 (Fig. 14): the platform moves back first; two graining points",
            a2["v_initial"] < 0 and a2["graining_points"] == 2,
            f"v_initial {a2['v_initial']:+.3f} m/s, {a2['graining_points']} graining point(s)",
        )
    )
    s1, s2 = e(1, "system_w5"), e(2, "system_w5")
    out.append(
        (
            "Optimising w5 (Fig. 11, 15): w5 improves while the arm goes to its extended posture (w_a5 → 1)",
            all(s["w5_final"] < s["w5_initial"] and s["wa5_final"] > 0.99 for s in (s1, s2)),
            "; ".join(
                f"case {s['case']}: w5 {s['w5_initial']:.3f} → {s['w5_final']:.3f}, w_a5 final {s['wa5_final']:.4f}"
                for s in (s1, s2)
            ),
        )
    )
    out.append(
        (
            "Case 1, w5 (Fig. 11): the platform moves back a little at the beginning",
            s1["v_initial"] < 0,
            f"v_initial {s1['v_initial']:+.3f} m/s, {s1['graining_points']} graining point(s)",
        )
    )
    out.append(
        (
            "Case 2, w5 (Fig. 15b): only one graining point",
            s2["graining_points"] == 1,
            f"{s2['graining_points']} graining point(s), v_initial {s2['v_initial']:+.3f} m/s",
        )
    )
    m1, m2 = e(1, "system_w5_normalized"), e(2, "system_w5_normalized")
    out.append(
        (
            "Optimising w̃5 (Fig. 12, 16): the arm stays far from its singular posture (w_a5 < 0.9)",
            all(m["wa5_max"] < WA5_GOOD for m in (m1, m2)),
            "; ".join(
                f"case {m['case']}: w_a5 max {m['wa5_max']:.3f}, final {m['wa5_final']:.3f}" for m in (m1, m2)
            ),
        )
    )
    out.append(
        (
            "Optimising w̃5 (§4.2.3): smooth platform paths with at most a weak graining at the beginning",
            all(
                m["graining_points"] <= 1 and all(t < 0.25 * DURATION for t in m["graining_times"])
                for m in (m1, m2)
            ),
            "; ".join(
                f"case {m['case']}: {m['graining_points']} at t = "
                + (", ".join(f"{t:.1f}" for t in m["graining_times"]) or "—")
                + " s"
                for m in (m1, m2)
            ),
        )
    )
    out.append(
        (
            "Conclusion: w̃5 needs fewer platform manoeuvres than w_a5 (case 2: one instead of two)",
            m2["graining_points"] < a2["graining_points"],
            f"case 2 graining points: w_a5 {a2['graining_points']}, w5 {s2['graining_points']}, "
            f"w̃5 {m2['graining_points']}",
        )
    )
    return out


def report(entries: list[dict], dt: float) -> str:
    """Settings, the claims table (with their sensitivity to W), the metrics table and the paper's typos."""
    chosen = claims(entries, GAIN)
    by_gain = {g: claims(entries, g) for g in GAINS}
    lines = [
        "## Settings",
        "",
        "- Robot: `manus_platform(L2=0.12, L3=0.35, L4=0.35, a=0.12, b=0.12, c=0.4)`, its arm frame turned by "
        "−π/2 about the vertical (eq. 8: with q_a1 = π/2 the arm points along the platform heading). "
        "L3 = L4 = 0.35 m are a choice (the paper gives no link lengths). Velocity "
        "limits u_max = (0.33 m/s, 0.55 rad/s, π/3, π/3, π/3 rad/s) for w̃5.",
        f"- q_p = 0, q_a = (π/2, π/3, −π/3): end effector at (0.47, 0.24, 0.40) m; initial w_a5 = "
        f"{entries[0]['wa5_initial']:.3f}, w5 = {entries[0]['w5_initial']:.3f}, w̃5 = {entries[0]['w5n_initial']:.3f}.",
        f"- Lines at {SPEED} m/s along X_W (case 1) and Y_W (case 2) during {DURATION:.0f} s (not stated in the paper).",
        f"- Law: eq. 30, open loop as in the paper, W = {GAIN:g} · I (chosen; sensitivity below with W ∈ "
        f"{{{', '.join(f'{g:g}' for g in GAINS)}}}); `none` is the pseudo-inverse u = J̄⁺ Ẋd. Step dt = {dt:g} s, "
        "Lie-group RK4.",
        f"- Graining point: a sign change of the platform speed v, ignoring |v| ≤ {V_THRESHOLD:g} m/s.",
        "",
        f"## Paper claims (W = {GAIN:g}; last column: at which gains the claim holds)",
        "",
        "| claim | holds | evidence | holds for W |",
        "|---|---|---|---|",
    ]
    for i, (text, holds, evidence) in enumerate(chosen):
        gains = ", ".join(f"{g:g}" for g in GAINS if by_gain[g][i][1]) or "none"
        lines.append(f"| {text} | {'yes' if holds else '**no**'} | {evidence} | {gains} |")
    lines += [
        "",
        "## Runs",
        "",
        "| case | strategy | W | graining points | v_initial (m/s) | w_a5 min / max / final | w5 final | w̃5 final "
        "| max tracking error (m) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for e in entries:
        gain = "—" if e["gain"] is None else f"{e['gain']:g}"
        lines.append(
            f"| {e['case']} | {e['strategy']} | {gain} | "
            f"{e['graining_points']} | {e['v_initial']:+.4f} | {e['wa5_min']:.3f} / {e['wa5_max']:.3f} / "
            f"{e['wa5_final']:.3f} | {e['w5_final']:.3f} | {e['w5n_final']:.3f} | {e['max_tracking_error']:.1e} |"
        )
    lines += [
        "",
        "## Notes",
        "",
        "- Claims that fail, and why, are discussed in docs/control.md; they depend on unstated "
        "settings (link lengths, duration, W) — the last column of the claims table shows how much.",
        "- Typos in the paper: §4.2.2 writes the pseudo-inverse solution as u = J̄(q) Ẋd (it is J̄⁺ Ẋd); the "
        "discussion cites a figure 17 that does not exist (figures 12 and 16 are meant); the conclusion's "
        "“w and w5 … two graining points, w5 … one” must read w_a5 (two, case 2) and w̃5 (one).",
    ]
    return "\n".join(lines)
