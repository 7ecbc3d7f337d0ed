"""More known answers for the ch. 6.1 test (evaluation.protocol), each written against a mutant that the
known-answer suite let through (docs/mutation.md)."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from evaluation.protocol import EPSILONS, drive_test
from robots.params import KHEPERA

PARAMS = dataclasses.replace(KHEPERA, actuator_noise=0.0)


def test_a_target_exactly_eps_away_is_not_closer_than_eps():
    """"Closer than ε" is strict (P(ε), Eq. 6.2): a robot at rest with the target exactly 25 mm ahead (in
    float32, hypot(0.025, 0) == 0.025 exactly) has not reached it within 25 mm, but has within any larger ε.
    Kills ``hit0 = d0 <= eps``."""
    e25 = float(np.float32(EPSILONS[2]))
    rec = drive_test(lambda u: jnp.zeros(2), jnp.asarray([[e25, 0.0]], jnp.float32), jnp.zeros(3),
                     jax.random.PRNGKey(0), cap=2, params=PARAMS)
    assert rec.hit.tolist() == [[False, False, False]]
    assert rec.steps.tolist() == [0] and rec.capped.tolist() == [False]  # it stopped at once and never moved
    assert float(rec.error[0]) == e25


def test_trace_paths_has_one_row_per_target_when_targets_and_cap_differ():
    """xy is (targets, cap · n, 2); the default test has 50 targets and a cap of 50, which hides a reshape on
    the wrong axis. Kills ``xy.reshape(xy.shape[1], -1, 2)``."""
    from ekm import maps
    from ekm.config import EKMConfig
    from evaluation.protocol import evaluate, trace_paths

    cfg = EKMConfig(neurons=2)
    stack = jax.tree.map(lambda a: a[None], maps.init(cfg))
    n = KHEPERA.substeps(KHEPERA.target_period)
    pts, _, xy, first = trace_paths(stack, cfg, (1.0, 1.0), targets=3, cap=5)
    assert pts.shape == (3, 2) and xy.shape == (3, 5 * n, 2) and first.error.shape == (3,)
    rec = evaluate(stack, cfg, (1.0, 1.0), targets=3, cap=5)
    np.testing.assert_allclose(np.asarray(first.error), np.asarray(rec.error)[0], atol=1e-6)
    # The last sub-step of each target's row is where the robot stood when the next target was presented.
    np.testing.assert_allclose(np.linalg.norm(np.asarray(xy[:, -1]) - np.asarray(pts), axis=-1),
                               np.asarray(first.error), atol=1e-5)
