"""The indirect mapping (ekm.indirect): control by Eq. 4.5 — M_k u_p inside the limits, M_k w_k beyond them, by
hand at exactly c* — and the update of Eq. 4.7 and 4.9."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm import indirect
from ekm.config import EKMConfig
from ekm.kohonen import forward_prior, neighbourhood, winner


def weights(*rows):
    return jnp.asarray(rows, jnp.float32)


def test_eq_4_5_uses_m_k_u_p_inside_the_limits_and_m_k_w_k_beyond_them():
    cfg = EKMConfig(neurons=2, priority=1)
    w = weights([0.0, 0.08], [1.5, 0.08], [3.0, 0.08], [-1.5, 0.08])
    M = jnp.zeros((4, 2, 2)).at[0].set(jnp.asarray([[0.0, 0.1], [0.0, 0.1]]))  # c = 0.1 · d/d_scale per wheel
    ekm = indirect.IndirectEKM(w, M)
    c, k = indirect.control(ekm, jnp.asarray([0.0, 0.16]), cfg)  # d/d_scale = 1 → c = 0.1 ≤ c*
    assert int(k) == 0 and np.allclose(c, [0.1, 0.1])
    c, k = indirect.control(ekm, jnp.asarray([0.0, 0.48]), cfg)  # M_k u_p = 0.3 > c* = 0.16
    assert int(k) == 0
    assert np.allclose(c, [0.05, 0.05])  # M_k w_k: w_k = (0, 0.08) → 0.1 · 0.5, not 0.16 saturation


def test_eq_4_5_fallback_applies_when_a_single_wheel_exceeds_c_star():
    cfg = EKMConfig(neurons=2, priority=1)
    w = weights([0.0, 0.08], [1.5, 0.08], [3.0, 0.08], [-1.5, 0.08])
    M = jnp.zeros((4, 2, 2)).at[0].set(jnp.asarray([[0.0, 0.05], [0.0, 0.2]]))
    c, _ = indirect.control(indirect.IndirectEKM(w, M), jnp.asarray([0.0, 0.16]), cfg)
    assert np.allclose(c, [0.025, 0.1])  # right wheel 0.2 > c*: both wheels from M_k w_k


def test_eq_4_5_at_exactly_c_star_uses_m_k_u_p():
    cfg = EKMConfig(neurons=2, priority=1)
    w = jnp.asarray([[0.0, 0.08], [1.5, 0.08], [3.0, 0.08], [-1.5, 0.08]], jnp.float32)
    M = jnp.zeros((4, 2, 2)).at[0].set(forward_prior(cfg))  # c = c* · d/d_scale per wheel
    c, k = indirect.control(indirect.IndirectEKM(w, M), jnp.asarray([0.0, 0.16], jnp.float32), cfg)
    assert int(k) == 0
    np.testing.assert_array_equal(np.asarray(c), np.float32([0.16, 0.16]))  # |c| = c*: allowed, not M_k w_k


@pytest.mark.parametrize("chart, alpha", [("polar", 0.4), ("polar", 2.8), ("signed", 0.4), ("signed", 2.8)])
def test_indirect_update_follows_eq_4_7_and_4_9(chart, alpha):
    cfg = EKMConfig(neurons=3, priority=3, chart=chart)
    ekm = indirect.init(cfg)
    ekm = ekm._replace(M=0.05 * jax.random.normal(jax.random.PRNGKey(1), ekm.M.shape))
    v, c_p, eta, sigma = jnp.asarray([alpha, 0.1]), jnp.asarray([0.05, 0.12]), 0.3, 0.8
    new = indirect.update(ekm, v, c_p, eta, sigma, cfg)
    k = int(winner(ekm.w, v, cfg))
    g = np.asarray(neighbourhood(cfg, k, sigma))
    w, M = np.asarray(ekm.w), np.asarray(ekm.M)
    if chart == "polar":  # (α, d), α unwrapped next to each α_i
        v_loc = np.stack([(w[:, 0] + (alpha - w[:, 0] + np.pi) % (2 * np.pi) - np.pi) / np.pi,
                          np.full(9, 0.1 / cfg.d_scale)], axis=1)
    elif alpha < np.pi / 2:  # signed, ahead: (α, d)
        v_loc = np.tile([alpha / np.pi, 0.1 / cfg.d_scale], (9, 1))
    else:  # signed, behind: (α - π, -d)
        v_loc = np.tile([(alpha - np.pi) / np.pi, -0.1 / cfg.d_scale], (9, 1))
    for i in range(9):
        dM = eta * g[i] * np.outer(np.asarray(c_p) - M[i] @ v_loc[i], v_loc[i])
        assert np.allclose(np.asarray(new.M[i]), M[i] + dM, atol=1e-6)
    assert np.allclose(np.asarray(new.w[:, 1]), w[:, 1] + eta * g * (0.1 - w[:, 1]), atol=1e-6)
    # After many presentations of the same (v, c_p) the winner maps v to c_p (ch. 4.3: c_p = M_k v).
    for _ in range(300):
        ekm = indirect.update(ekm, v, c_p, 0.5, 0.5, cfg)
    c, k2 = indirect.control(ekm, v, cfg)
    assert np.allclose(np.asarray(ekm.w[k2]), v, atol=1e-3)
    assert np.allclose(c, c_p, atol=1e-3)
