"""Benchmark: TIAGo's QP law (docs/examples/tiago_limits.toml) closed on MuJoCo, 100 Hz control on 1 kHz physics
(``mobman.physics.run_on_physics``), against real time and against the kinematic run of the same spec.

    python benchmarks/physics.py            # the spec's 5 s
    python benchmarks/physics.py --smoke    # 0.5 s (CI)

The robot is TIAGo with its URDF inertials and effort limits (``DynamicModel.from_urdf``), on wheels with
friction 1. Rows: the whole run (model built, law and physics) as simulated seconds per wall second (the
realtime factor), and where its time goes: one evaluation of the law (its compiled one-configuration program,
``compiled_control``) per control step, one ``mj_step`` per physics step (ten per control step), building
and compiling the MuJoCo model (once per run), and the rest (reading the measured state, writing the
commands, the record), each as a share of the run and as the realtime factor it alone would allow; the parts
are timed apart from the run, in interleaved rounds (the best of each). The end point is compared with the kinematic run of the
same law at the same control rate (``integrator="hold"``). No timing is asserted; the numbers depend on the
machine and on what else runs on it. The run sets its CPU affinity to one core first (the target is
stated for one core; JAX's threads, started later, follow it).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import mujoco
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.control import simulate, spec
from mobman.dynamics import DynamicModel
from mobman.io.real_robots import urdf_model
from mobman.physics import run_on_physics, set_configuration, to_mjspec
from mobman.physics.loop import compiled_control

from timing import best_time

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_limits.toml"
CONTROL_DT = 0.01
"""The control period (s): 100 Hz."""
TIMESTEP = 1e-3
"""MuJoCo's step (s): 1 kHz."""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=None, help="simulated seconds (default the spec's)")
    parser.add_argument("--smoke", action="store_true", help="a short run for CI")
    args = parser.parse_args(argv)
    if hasattr(os, "sched_setaffinity"):  # on one core, as the target is stated; XLA's threads follow it
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    parsed = spec.load(SPEC)
    duration = 0.5 if args.smoke else (args.duration or parsed.duration)
    model = urdf_model("tiago")
    dynamics = DynamicModel.from_urdf(model)
    robot, task, law, reference = dynamics.robot, parsed.task, parsed.law, parsed.reference
    limits = model.torque_limits()

    def run():
        return run_on_physics(
            dynamics,
            law,
            reference,
            parsed.q0,
            duration,
            CONTROL_DT,
            task=task,
            timestep=TIMESTEP,
            torque_limits=limits,
        )

    result = run()  # compiles the law's program
    if result.stopped is not None:
        print(f"error: the physics run stopped: {result.stopped}", file=sys.stderr)
        return 1
    steps = len(result.t) - 1
    substeps = round(CONTROL_DT / TIMESTEP)
    control = compiled_control(robot, task, law, reference)  # the run's program (cached)

    def build():  # the MuJoCo model, built and compiled once per run
        return to_mjspec(dynamics, torque_limits=limits, timestep=TIMESTEP).compile()

    mj_model = build()
    data = mujoco.MjData(mj_model)

    def laws():  # the law alone, at the run's measured configurations
        for q, t in zip(result.q[:-1], result.t[:-1]):
            control(q, t)

    def physics():  # MuJoCo alone: the same model, as many steps, the robot holding still
        set_configuration(mj_model, data, robot, parsed.q0)
        for _ in range(steps * substeps):
            mujoco.mj_step(mj_model, data)

    # interleaved rounds, the best of each: a machine busy with other work slows every part alike
    times = {part: [] for part in (run, build, laws, physics)}
    for _ in range(1 if args.smoke else 3):
        for part, best in times.items():
            best.append(best_time(part, 1))
    t_run, t_build, t_law, t_step = (min(times[part]) for part in (run, build, laws, physics))
    t_law, t_step = t_law / steps, t_step / (steps * substeps)

    kinematic = simulate(robot, task, law, reference, parsed.q0, duration, CONTROL_DT, integrator="hold")
    end_physics, end_kinematic = result.q[-1], np.asarray(kinematic.q[-1])
    tool = [np.asarray(task.value(robot, q, robot.frames(q)))[:3] for q in (end_physics, end_kinematic)]

    print(
        f"TIAGo, QP law of {SPEC.name}, {duration:g} s at {1 / CONTROL_DT:g} Hz control on "
        f"{1 / TIMESTEP:g} Hz physics (MuJoCo {mujoco.__version__})"
    )
    print(f"{'part':46s} {'ms / simulated s':>17s} {'share':>7s} {'realtime factor':>16s}")
    parts = [
        ("whole run (build, law, physics)", t_run),
        (f"law: {steps} evaluations, compiled program", t_law * steps),
        (f"MuJoCo: {steps * substeps} mj_step", t_step * steps * substeps),
        ("model built and compiled (once per run)", t_build),
        ("the rest (state read, commands, record)", t_run - t_build - (t_law + t_step * substeps) * steps),
    ]
    for name, seconds in parts:
        if seconds <= 0:  # the parts were timed apart from the run: under load they may exceed it
            print(f"{name:46s} {'—':>17s}")
            continue
        print(
            f"{name:46s} {1e3 * seconds / duration:17.1f} {seconds / t_run:7.1%} {duration / seconds:16.1f}"
        )
    print(
        f"law per control step {1e6 * t_law:.0f} µs, mj_step per physics step {1e6 * t_step:.1f} µs "
        f"(law / mj_step: {t_law / t_step:.0f})"
    )
    print(
        f"end point against the kinematic run: tool {1e3 * np.linalg.norm(tool[0] - tool[1]):.2f} mm, "
        f"platform {1e3 * np.linalg.norm(end_physics[:2] - end_kinematic[:2]):.2f} mm; "
        f"median lateral slip {1e3 * np.median(np.abs(result.slip)):.3f} mm/s"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
