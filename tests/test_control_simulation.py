"""mobman.control.simulation: the integrators, closed-loop runs of the laws, batches, progress chunks, the
recorded measures and the summary of a run, and the simulation's errors.

The runs share one compiled simulation where possible (same robot, task, law structure, reference type and
number of steps; gains and references are traced), which keeps the file fast.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import InputError, ModelError, SingularConfigurationError, kinematics
from mobman.control import criteria, laws, metrics, references, simulate
from mobman.control.simulation import _step
from mobman.engine import batched as batching
from mobman.model import robots
from mobman.model.tasks import Position

ROBOT = robots.bayle_planar()
TASK = Position("xy")
Q0 = np.array([0.0, 0.0, 0.0, 0.6, 1.2])
DT, DURATION = 0.01, 2.0
W5 = criteria.Manipulability("eccentricity", "system", power=2)


def bayle(W=2.0, k=0.5, **options):
    return laws.BaylePseudoInverse(W=W, k=k, criterion=W5, **options)


# --- integrators -------------------------------------------------------------------------------------


@pytest.mark.parametrize("integrator", ["lie", "rk4"])
def test_integrators_have_order_four(integrator):
    def control(q, t):
        return jnp.array(
            [1.0 + 0.5 * jnp.sin(q[3] + t), jnp.cos(2 * t) + 0.3 * q[0], jnp.sin(q[2]), q[1] - q[4]]
        ), {}

    step = jax.jit(lambda q, t, h: _step(ROBOT, integrator, control, q, t, h)[0])
    q0 = jnp.array([0.1, 0.2, 0.3, 0.4, 0.5])
    errors = []
    for h in (0.2, 0.1):
        fine = jax.lax.fori_loop(0, 64, lambda i, q, h=h: step(q, i * h / 64, h / 64), q0)
        errors.append(float(jnp.linalg.norm(step(q0, 0.0, h) - fine)))
    assert errors[0] / errors[1] > 25  # local error O(h⁵): ratio 32


def test_hold_integrator_moves_on_exact_arcs_at_the_held_control():
    """Zero-order hold: over each step the platform follows the arc of constant (v, ω) from the recorded η."""
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, -0.2], 1.0)
    res = simulate(ROBOT, TASK, bayle(W=2.0, k=0.5), line, Q0, 1.0, 0.05, integrator="hold")
    q, eta, h = res.q, res.eta, 0.05
    x, y, th = q[:-1, 0], q[:-1, 1], q[:-1, 2]
    v, w = eta[:-1, 0], eta[:-1, 1]
    arc = np.where(np.abs(w) > 1e-12, v / np.where(np.abs(w) > 1e-12, w, 1.0), 0.0)
    x_next = np.where(np.abs(w) > 1e-12, x + arc * (np.sin(th + w * h) - np.sin(th)), x + v * h * np.cos(th))
    y_next = np.where(np.abs(w) > 1e-12, y - arc * (np.cos(th + w * h) - np.cos(th)), y + v * h * np.sin(th))
    np.testing.assert_allclose(q[1:, 0], x_next, atol=1e-12)
    np.testing.assert_allclose(q[1:, 1], y_next, atol=1e-12)
    np.testing.assert_allclose(q[1:, 2:], q[:-1, 2:] + h * eta[:-1, 1:], atol=1e-12)


def test_hold_integrator_converges_to_the_continuous_loop_at_first_order():
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, -0.2], 0.8)
    law = bayle(W=2.0, k=0.5)
    exact = simulate(ROBOT, TASK, law, line, Q0, 0.8, 0.001, integrator="rk4").q[-1]
    errors = [
        np.linalg.norm(simulate(ROBOT, TASK, law, line, Q0, 0.8, h, integrator="hold").q[-1] - exact)
        for h in (0.04, 0.02)
    ]
    assert 1.7 < errors[0] / errors[1] < 2.3  # global error O(h)


# --- closed-loop simulation ------------------------------------------------------------------------


@pytest.fixture(scope="module")
def runs():
    """Three runs in one batched call (gains differ): tracking, pure self-motion, tracking with k = 0."""
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0 + [0.3, -0.2], xi0 + [0.5, 0.1], DURATION)
    batch = [
        bayle(W=np.array([2.0, 3.0]), k=0.5),
        bayle(W=np.array([1e-9, 1e-9]), k=2.0),
        bayle(W=2.0 * np.ones(2), k=0.0),
    ]
    track = simulate(ROBOT, TASK, batch, line, Q0, DURATION, DT, measures=("system_w5", "arm_w5"))
    still = references.Line(xi0, xi0, DURATION)
    rest = simulate(ROBOT, TASK, batch, still, Q0, DURATION, DT)
    return track, rest


def test_error_dynamics_decay_rate(runs):
    track, _ = runs
    for i, rates in ((0, (2.0, 3.0)), (2, (2.0, 2.0))):
        for c, rate in enumerate(rates):
            e = np.abs(track.error[i, :, c])
            fit = np.polyfit(track.t[:150], np.log(e[:150]), 1)[0]
            assert abs(-fit - rate) / rate < 0.01
    assert track.error.shape == (3, 201, 2) and track.t[-1] == pytest.approx(DURATION)


def test_recorded_xi_is_the_forward_kinematics_of_the_recorded_path(runs):
    """ξ is recorded inside the compiled run (from the law's own evaluation), not recomputed afterwards."""
    for result in runs:
        np.testing.assert_allclose(result.xi, kinematics.forward(ROBOT, result.q, TASK), rtol=0, atol=1e-13)
        np.testing.assert_allclose(result.error, result.xi_star - result.xi, rtol=0, atol=0)


def test_self_motion_keeps_the_task_and_decreases_the_criterion(runs):
    _, rest = runs
    xi = rest.xi[1]
    assert np.max(np.linalg.norm(np.diff(xi, axis=0), axis=-1)) <= 1e-9
    p = rest.info["P"][1]
    assert p[-1] < p[0] - 0.1  # the self-motion does something
    assert np.all(np.diff(p) <= 1e-12)
    # continuous time: Ṗ = ∇ᵀP S η ≤ 0 at every sample
    grads = jax.vmap(lambda q: W5.gradient(ROBOT, q, TASK))(rest.q[1])
    q_dot = np.einsum("nij,nj->ni", np.asarray(kinematics.S(ROBOT, rest.q[1])), rest.eta[1])
    assert np.all(np.einsum("ni,ni->n", grads, q_dot) <= 1e-12)
    # with k = 0 nothing moves
    assert np.allclose(rest.q[2], Q0, atol=1e-12)


def test_platform_never_slips(runs):
    for result in runs:
        q, eta, mid = result.q, result.eta, result.info["q_mid"]
        q_dot = np.einsum("bnij,bnj->bni", np.asarray(kinematics.S(ROBOT, q)), eta)
        theta = q[..., 2]
        assert np.max(np.abs(q_dot[..., 0] * np.sin(theta) - q_dot[..., 1] * np.cos(theta))) <= 1e-12
        # the discrete path: every step is two arcs q → q_mid → q_next, each chord along the mean heading
        for a, b in ((q[:, :-1], mid[:, :-1]), (mid[:, :-1], q[:, 1:])):
            heading = 0.5 * (a[..., 2] + b[..., 2])
            d = b - a
            assert np.max(np.abs(d[..., 0] * np.sin(heading) - d[..., 1] * np.cos(heading))) <= 1e-12


def test_rk4_chords_slip_but_velocities_do_not():
    law = laws.BaylePseudoInverse(W=2.0)
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    ref = references.Ellipse(xi0 - [0.5, 0.0], (0.5, 0.4), 4.0)
    res = simulate(ROBOT, TASK, law, ref, Q0, DURATION, DT, integrator="rk4")
    d, heading = np.diff(res.q, axis=0), 0.5 * (res.q[1:, 2] + res.q[:-1, 2])
    slip = np.abs(d[:, 0] * np.sin(heading) - d[:, 1] * np.cos(heading))
    assert slip.max() > 1e-11  # RK4 chords are not arcs
    assert "q_mid" not in res.info


def test_batched_runs_equal_single_runs(runs):
    track, _ = runs
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0 + [0.3, -0.2], xi0 + [0.5, 0.1], DURATION)
    single = simulate(ROBOT, TASK, bayle(W=np.array([2.0, 3.0]), k=0.5), line, Q0, DURATION, DT)
    assert np.allclose(single.q, track.q[0], atol=1e-12)
    q0s = np.stack([Q0, Q0 + [0.1, 0, 0.2, 0, 0.1]])
    batch = simulate(ROBOT, TASK, bayle(W=np.array([2.0, 3.0]), k=0.5), line, q0s, DURATION, DT)
    assert batch.q.shape == (2, 201, 5) and np.allclose(batch.q[0], single.q, atol=1e-12)
    assert not np.allclose(batch.q[1], single.q)


@pytest.mark.parametrize("integrator", ["lie", "hold"])
def test_progress_chunks_continue_the_run_exactly(integrator):
    """A run cut into chunks of 50 steps (not a multiple of the 12-step inner blocks of the compiled scan, so
    each chunk ends inside a block) continues from the exact state: the same samples as one call."""
    from mobman.control.simulation import _block_steps

    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, 0.2], DURATION)
    assert 50 % _block_steps(ROBOT, line)
    fractions = []
    chunked = simulate(
        ROBOT,
        TASK,
        bayle(),
        line,
        Q0,
        DURATION,
        DT,
        integrator=integrator,
        progress=fractions.append,
        chunk=50,
    )
    whole = simulate(ROBOT, TASK, bayle(), line, Q0, DURATION, DT, integrator=integrator)
    assert fractions == [50 / 201, 100 / 201, 150 / 201, 200 / 201, 1.0]
    np.testing.assert_allclose(chunked.q, whole.q, rtol=0, atol=1e-13)
    np.testing.assert_allclose(chunked.eta, whole.eta, rtol=0, atol=1e-12)


@pytest.mark.parametrize("batch", ["one run", "initial configurations", "laws"])
def test_calls_of_a_few_samples_continue_every_run_exactly(batch, monkeypatch):
    """A run computed in compiled calls of at most 32 samples (so that Ctrl-C is answered between calls) equals
    the run computed in one call: one run, a batch of initial configurations, and a batch of laws from one
    q0, where each law continues from its own state."""
    from mobman.control import simulation

    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, 0.2], 0.5)
    law = bayle(W=np.array([2.0, 3.0]) if batch == "laws" else 2.0)
    q0 = np.stack([Q0, Q0 + [0.1, 0, 0.2, 0, 0.1]]) if batch == "initial configurations" else Q0
    monkeypatch.setattr(simulation, "MIN_SCAN_STEPS", 1)
    monkeypatch.setattr(simulation, "SCAN_SAMPLES", 10**9)
    whole = simulate(ROBOT, TASK, law, line, q0, 0.5, DT)
    monkeypatch.setattr(simulation, "SCAN_SAMPLES", 32)
    calls = simulate(ROBOT, TASK, law, line, q0, 0.5, DT)
    np.testing.assert_allclose(calls.q, whole.q, rtol=0, atol=1e-13)
    if batch != "one run":
        assert not np.allclose(whole.q[0], whole.q[1])


def test_a_batch_of_initial_configurations_is_shared_between_threads(monkeypatch):
    """Nine runs on three workers (shares of 5, the second moved back to start at run 4): every run as when
    simulated alone, with progress chunks."""
    monkeypatch.setattr(batching, "WORKERS", 3)
    shares, take = [], batching._take
    monkeypatch.setattr(
        batching, "_take", lambda x, start, size: shares.append((start, size)) or take(x, start, size)
    )
    xi0 = np.asarray(kinematics.forward(ROBOT, Q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, 0.2], DURATION)
    offsets = np.linspace(-0.2, 0.2, 9)[:, None] * np.array([1.0, 0.5, 0.3, 0.2, 0.1])
    law = bayle(W=2.0, k=0.5)
    batch = simulate(ROBOT, TASK, law, line, Q0 + offsets, DURATION, DT, progress=lambda f: None, chunk=60)
    assert batch.q.shape == (9, 201, 5)
    assert sorted(shares) == [(0, 5)] * 4 + [(4, 5)] * 4  # two shares in each of 4 chunks
    for i in (0, 4, 8):
        alone = simulate(ROBOT, TASK, law, line, Q0 + offsets[i], DURATION, DT)
        np.testing.assert_allclose(batch.q[i], alone.q, atol=1e-12)
        np.testing.assert_allclose(batch.eta[i], alone.eta, atol=1e-10)


def test_measures_and_metrics(runs):
    track, _ = runs
    from mobman import manipulability as mp

    w5 = mp.measures(mp.system_jacobian(ROBOT, track.q[0], TASK))["eccentricity"]
    assert np.allclose(track.measures["system_w5"][0], w5)
    m = metrics.summarize(track.run(0), ROBOT, transient=1.0)
    err = np.linalg.norm(track.error[0], axis=-1)
    assert m["max_error"] == pytest.approx(err[100:].max())
    assert m["system_w5_min"] == pytest.approx(float(np.min(w5)))
    assert m["platform_path_length"] == pytest.approx(
        np.sum(np.linalg.norm(np.diff(track.q[0, :, :2], axis=0), axis=1))
    )
    assert m["control_effort"] == pytest.approx(np.sum(track.eta[0] ** 2) * DT)


def test_damping_near_a_singularity():
    q0 = np.array([0.0, 0.0, 0.0, np.pi / 2, 0.0])  # stretched arm across the heading: rank J̄ = 1
    xi0 = np.asarray(kinematics.forward(ROBOT, q0, TASK))
    line = references.Line(xi0, xi0 + [0.3, 0.0], DURATION)
    damped = bayle(W=np.array([2.0, 3.0]), k=0.5, damping=0.1, damping_threshold=0.05)
    res = simulate(ROBOT, TASK, damped, line, q0, DURATION, DT)
    assert res.damped[0] and np.all(np.isfinite(res.q))
    assert np.max(np.linalg.norm(res.error, axis=-1)) < 0.02  # DLS: small, bounded error near the singularity


def test_non_finite_runs_are_reported():
    bad = references.FunctionReference(
        lambda t: jnp.stack([jnp.sqrt(0.02 - t), t])
    )  # ξ̇* infinite at t = 0.02
    with pytest.raises(SingularConfigurationError, match="t = 0.02 s"):
        simulate(ROBOT, TASK, laws.BaylePseudoInverse(W=2.0), bad, Q0, 0.05, DT, integrator="rk4")


def test_simulate_input_errors():
    law = laws.BaylePseudoInverse(W=1.0)
    line = references.Line((0.0, 0.0), (1.0, 0.0), 1.0)
    with pytest.raises(InputError, match="dt"):
        simulate(ROBOT, TASK, law, line, Q0, 1.0, 0.0)
    with pytest.raises(InputError, match="coordinates"):
        simulate(ROBOT, TASK, law, line, Q0[:3], 1.0, 0.1)
    with pytest.raises(ModelError, match="reference"):
        simulate(ROBOT, TASK, law, references.Line((0.0,), (1.0,), 1.0), Q0, 1.0, 0.1)
    with pytest.raises(InputError, match="measures"):
        simulate(ROBOT, TASK, law, line, Q0, 0.02, 0.01, measures=("platform_w5",))
    with pytest.raises(InputError, match="integrator"):
        simulate(ROBOT, TASK, law, line, Q0, 1.0, 0.1, integrator="euler")
