"""mobman.planning.batch: a batch of problems gives each problem's single solve (final z, status, iterations,
error history), converged or not, also when lanes take the next problems as theirs stop, over several calls
and cores; unbatched arguments broadcast, one problem read back as a PlanResult, and the batch's shape
errors."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import InputError
from mobman.experiments import tchon2002
from mobman.planning import batch as batch_module
from mobman.planning.algorithms import plan
from mobman.planning.batch import plan_batch

from planning_setting import Q0


@pytest.fixture(scope="module")
def problems():
    """Three starts, one target each (0.05 m apart), the paper's initial z, the pseudo-inverse planner."""
    z0 = tchon2002.initial_configuration()
    targets = np.asarray(tchon2002.TARGET) + np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, -0.05, 0.0]])
    return z0, targets, tchon2002.options("pinv", 1.0, tchon2002.QUICK_CAP)


def _assert_single_solves(setting, batch, z0, q0, targets, options):
    """Each problem of ``batch`` is its one-at-a-time solve: status, iterations, z, error history."""
    for k in range(len(batch.status)):
        single = plan(setting, z0, q0[k], targets[k], options)
        assert batch.status[k] == single.status and int(batch.iterations[k]) == single.iterations
        np.testing.assert_allclose(batch.z[k], single.z, rtol=0, atol=1e-12)
        run = batch.run(setting, k)
        np.testing.assert_allclose(np.concatenate([run.lam, run.x]), single.z, rtol=0, atol=1e-12)
        # the error histories agree to the rounding of z (vmap orders some sums differently)
        np.testing.assert_allclose(run.errors, single.errors, rtol=1e-9, atol=1e-12)
        assert batch.final_errors[k] == run.errors[-1]


def test_each_problem_of_a_batch_is_its_single_solve(setting, problems):
    z0, targets, options = problems
    batch = plan_batch(setting, z0, Q0, targets, options)
    assert batch.z.shape == (3, setting.n_z) and batch.success_rate == 1.0
    assert np.all(batch.final_errors <= tchon2002.TOL)
    _assert_single_solves(setting, batch, z0, Q0, targets, options)


def test_problems_that_do_not_converge_are_their_single_solves(setting, problems):
    """The adjoint with Δθ = 0.1 stops at the cap on every start (tests/test_experiments_tchon2002.py): the
    batch reports each run's cap, final error and history, as one-at-a-time solves do."""
    z0, targets, _ = problems
    options = tchon2002.options("adjoint", 0.1, tchon2002.QUICK_CAP)
    batch = plan_batch(setting, z0, Q0, targets, options)
    assert batch.status == ["max_iterations"] * 3 and np.all(batch.iterations == tchon2002.QUICK_CAP)
    assert np.all(batch.final_errors > 1e-3)
    _assert_single_solves(setting, batch, z0, Q0, targets, options)


def test_lanes_take_the_next_problems_across_calls_and_cores(setting, problems, monkeypatch):
    """Five problems dealt to two loops of two lanes, three iterations per compiled call: lanes are refilled
    as problems stop at different iterations, the loops resume from call to call, and each result is still
    its single solve."""
    z0, targets, options = problems
    monkeypatch.setattr(batch_module, "BLOCK", 2)
    monkeypatch.setattr(batch_module, "ROUNDS", 3)
    monkeypatch.setattr(batch_module, "WORKERS", 2)
    q0 = np.concatenate([Q0, Q0[:2]])
    more = np.concatenate([targets, targets[1:] + np.array([0.0, 0.0, 0.1])])
    batch = plan_batch(setting, z0, q0, more, options)
    assert batch.success_rate == 1.0 and len(set(batch.iterations.tolist())) > 1
    assert batch.iterations.max() > batch_module.ROUNDS  # the loops went on over several calls
    _assert_single_solves(setting, batch, z0, q0, more, options)


def test_unbatched_arguments_broadcast(setting, problems):
    z0, targets, options = problems
    one_target = plan_batch(setting, z0, Q0, targets[0], options)
    repeated = plan_batch(setting, z0, Q0, np.broadcast_to(targets[0], (3, 3)), options)
    np.testing.assert_array_equal(one_target.z, repeated.z)
    assert one_target.status == repeated.status


def test_batch_shape_errors(setting, problems):
    z0, targets, options = problems
    with pytest.raises(InputError, match="batch sizes of z0, q0, y_d differ"):
        plan_batch(setting, z0, Q0, targets[:2], options)
    with pytest.raises(InputError, match="non-empty batch"):
        plan_batch(setting, z0, Q0[:0], targets[0], options)
    with pytest.raises(InputError, match="q0 must be one problem"):
        plan_batch(setting, z0, Q0[None], targets[0], options)
