"""mobman.planning.batch: a batch of problems solved in one call gives each problem's single solve (final z,
status, iterations, error history), unbatched arguments broadcast, one problem read back as a PlanResult, and
the batch's shape errors."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import InputError
from mobman.experiments import tchon2002
from mobman.planning.algorithms import plan
from mobman.planning.batch import plan_batch

from planning_setting import Q0


@pytest.fixture(scope="module")
def problems():
    """Three starts, one target each (0.05 m apart), the paper's initial z, the pseudo-inverse planner."""
    z0 = tchon2002.initial_configuration()
    targets = np.asarray(tchon2002.TARGET) + np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, -0.05, 0.0]])
    return z0, targets, tchon2002.options("pinv", 1.0, tchon2002.QUICK_CAP)


def test_each_problem_of_a_batch_is_its_single_solve(setting, problems):
    z0, targets, options = problems
    batch = plan_batch(setting, z0, Q0, targets, options)
    assert batch.z.shape == (3, setting.n_z) and batch.success_rate == 1.0
    for k in range(3):
        single = plan(setting, z0, Q0[k], targets[k], options)
        assert batch.status[k] == single.status and int(batch.iterations[k]) == single.iterations
        np.testing.assert_allclose(batch.z[k], single.z, rtol=0, atol=1e-12)
        run = batch.run(setting, k)
        np.testing.assert_allclose(np.concatenate([run.lam, run.x]), single.z, rtol=0, atol=1e-12)
        # the error histories agree to the rounding of z (vmap orders some sums differently)
        np.testing.assert_allclose(run.errors, single.errors, rtol=1e-9, atol=1e-12)
        assert batch.final_errors[k] == run.errors[-1] <= tchon2002.TOL


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
