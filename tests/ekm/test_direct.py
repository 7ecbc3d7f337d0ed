"""The direct mapping (ekm.direct): one update worked out by hand, and outputs pulled towards the executed
command."""

import jax.numpy as jnp
import numpy as np

from ekm import direct, maps
from ekm.config import EKMConfig


def test_one_direct_update_by_hand():
    cfg = EKMConfig(mapping="direct", neurons=2, priority=4)
    ekm = direct.DirectEKM(w=jnp.asarray([[0.0, 0.1], [1.0, 0.1], [3.0, 0.1], [-1.0, 0.1]], jnp.float32),
                           c=jnp.asarray([[0.1, 0.1], [0.0, 0.05], [0.02, 0.0], [0.0, 0.0]], jnp.float32))
    v, c_p = jnp.asarray([0.0, 0.1], jnp.float32), jnp.asarray([0.04, 0.12], jnp.float32)
    new = direct.update(ekm, v, c_p, 0.5, 1.0, cfg)  # winner 0 (row 0, column 0)
    g = np.exp(-np.array([0, 1, 1, 2]) / 2.0)  # lattice distances² 0, 1 (column), 1 (row), 2
    want = np.asarray(ekm.c) + 0.5 * g[:, None] * (np.asarray(c_p) - np.asarray(ekm.c))
    np.testing.assert_allclose(np.asarray(new.c), want, atol=1e-6)
    c, k = direct.control(new, v, cfg)
    assert int(k) == 0 and np.allclose(np.asarray(c), [0.07, 0.11], atol=1e-6)


def test_direct_update_pulls_outputs_towards_the_executed_command():
    cfg = EKMConfig(mapping="direct", neurons=3, priority=3)
    ekm = direct.init(cfg)
    v, c_p = jnp.asarray([-0.7, 0.05]), jnp.asarray([0.02, 0.09])
    for _ in range(300):
        ekm = direct.update(ekm, v, c_p, 0.5, 0.5, cfg)
    c, _ = maps.control(ekm, v, cfg)
    assert np.allclose(c, c_p, atol=1e-3)
