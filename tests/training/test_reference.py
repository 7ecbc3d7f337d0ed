"""The jitted JAX training step equals the plain NumPy reference (docs/design.md §7: same result to 1e-5)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from robots.kinematics import egocentric
from robots.params import KHEPERA
from training import reference
from training.online import TrainConfig, draw_noise, start, train_step

STEPS = 60


@pytest.mark.parametrize("mapping, chart", [("direct", "signed"), ("indirect", "signed"), ("indirect", "polar")])
def test_jax_training_steps_equal_the_numpy_reference(mapping, chart):
    cfg = EKMConfig(mapping=mapping, neurons=7, priority=7, chart=chart)
    tcfg = TrainConfig(steps=200)
    s = start(jax.random.PRNGKey(3), cfg, tcfg)
    # A trained-looking map: random outputs so that the winner, Eq. 4.5 and both branches all matter.
    k1, k2, k3 = jax.random.split(jax.random.PRNGKey(4), 3)
    out_shape = s.ekm[1].shape
    w = s.ekm.w + jax.random.normal(k1, s.ekm.w.shape) * jnp.asarray([0.3, 0.02])
    w = w.at[:, 1].set(jnp.abs(w[:, 1]))
    s = s._replace(ekm=type(s.ekm)(w, 0.1 * jax.random.normal(k2, out_shape)))
    draws = draw_noise(jax.random.PRNGKey(5), STEPS)
    step = jax.jit(lambda s, d, t: train_step(s, d, t, cfg, tcfg, KHEPERA))

    ref = [np.asarray(a, float) for a in (s.ekm.w, s.ekm[1], s.robot.pose, s.robot.wheels, s.target)] + [0]
    behind = 0
    for t in range(STEPS):
        behind += abs(float(egocentric(s.robot.pose, s.target)[0])) > np.pi / 2
        d = tuple(np.asarray(x[t], np.float32) for x in draws)
        s = step(s, tuple(jnp.asarray(x) for x in d), jnp.float32(t))
        ref = list(reference.train_step(mapping, *ref, d, float(t), cfg, tcfg))
        # Compare every step, then continue both from the JAX state so float32/float64 rounding of a
        # speed command exactly at a rounding boundary cannot make the two drift apart.
        np.testing.assert_allclose(np.asarray(s.ekm.w), ref[0], atol=1e-5, rtol=0)
        np.testing.assert_allclose(np.asarray(s.ekm[1]), ref[1], atol=1e-5, rtol=0)
        np.testing.assert_allclose(np.asarray(s.robot.pose), ref[2], atol=1e-5, rtol=0)
        np.testing.assert_allclose(np.asarray(s.robot.wheels), ref[3], atol=1e-5, rtol=0)
        np.testing.assert_allclose(np.asarray(s.target), ref[4], atol=1e-5, rtol=0)
        assert int(s.age) == ref[5]
        ref = [np.asarray(a, float) for a in (s.ekm.w, s.ekm[1], s.robot.pose, s.robot.wheels, s.target)] + [int(s.age)]
    assert 0 < behind < STEPS  # targets ahead and behind: both halves of the signed chart were used
