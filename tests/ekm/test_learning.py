"""A trained map that goes on learning (ekm.learning): one update by hand (Eq. 4.7, 4.9), the rates of each rule."""

import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from ekm.indirect import IndirectEKM
from ekm.learning import Adaptation, adapt, fresh_trace, rates, recent_error

CFG = EKMConfig(neurons=2)  # 4 neurons; d_scale 0.16 m; the signed chart
W = np.array([[0.0, 0.10], [0.0, 0.05], [1.0, 0.10], [-1.0, 0.10]], np.float32)  # (α_i rad, d_i m)
M = np.array([[[0.1, 0.05], [-0.1, 0.05]], [[0.2, 0.0], [0.0, 0.2]], [[0.0, 0.1], [0.1, 0.0]],
              [[0.3, 0.3], [0.3, 0.3]]], np.float32)


def test_one_update_moves_the_winner_s_m_towards_the_command_by_what_eq_4_9_gives():
    v, c = np.array([0.1, 0.11]), np.array([0.05, 0.04])  # displacement (α rad, d m) and the command that made it
    # By hand: the winner is neuron 0 (nearest in angle with neuron 1, nearer in distance). In the signed chart
    # ṽ = (α/π, d/0.16) ahead; the model predicts M_0 ṽ; Eq. 4.9 moves M_0 by η (c - M_0 ṽ) ṽᵀ, Eq. 4.7 w_0 by
    # η (v - w_0). σ = 0.05 lattice units leaves the other neurons as they are (G = e^-200).
    v_t = np.array([0.1 / np.pi, 0.11 / 0.16])
    prediction = M[0] @ v_t  # = (0.0375581, 0.0311919) m/s
    expected_M0 = M[0] + 0.5 * np.outer(c - prediction, v_t)
    expected_w0 = W[0] + 0.5 * (v - W[0])
    rule = Adaptation(rule="constant", eta=0.5, sigma=0.05)
    new, trace = adapt(IndirectEKM(jnp.asarray(W), jnp.asarray(M)), jnp.asarray(v, jnp.float32),
                       jnp.asarray(c, jnp.float32), fresh_trace(), rule, CFG)
    np.testing.assert_allclose(np.asarray(new.M[0]), expected_M0, atol=1e-7)
    np.testing.assert_allclose(np.asarray(new.w[0]), expected_w0, atol=1e-7)
    np.testing.assert_allclose(np.asarray(new.M[1:]), M[1:], atol=1e-9)
    # the prediction error it remembers: |c - M_0 ṽ| / c* = |(0.0124419, 0.0088081)| / 0.16 = 0.0952652
    assert int(trace.updates) == 1
    assert float(recent_error(trace, rule)) == pytest.approx(np.hypot(0.0124419, 0.0088081) / 0.16, rel=1e-4)


def test_the_error_rule_rises_from_its_resting_rates_to_its_highest_between_floor_and_full():
    rule = Adaptation(rule="error", eta=0.005, sigma=0.3, eta_max=0.1, sigma_max=1.0, floor=0.04, full=0.1)
    for error, (eta, sigma) in ((0.0, (0.005, 0.3)), (0.04, (0.005, 0.3)), (0.07, (0.0525, 0.65)),
                                (0.1, (0.1, 1.0)), (0.5, (0.1, 1.0))):
        got = rates(rule, jnp.float32(error))
        assert (float(got[0]), float(got[1])) == pytest.approx((eta, sigma), rel=1e-5)
    constant = Adaptation(rule="constant", eta=0.1, sigma=1.0)
    assert tuple(map(float, rates(constant, jnp.float32(0.9)))) == pytest.approx((0.1, 1.0))


def test_rates_zero_are_frozen_and_bad_rules_are_refused():
    assert Adaptation(rule="constant", eta=0.0).frozen and Adaptation(eta=0.0, eta_max=0.0).frozen
    assert not Adaptation().frozen and not Adaptation(eta=0.0).frozen
    for bad in ({"rule": "sometimes"}, {"eta": -0.1}, {"sigma": 0.0}, {"full": 0.01, "floor": 0.02},
                {"memory": 0.5}):
        with pytest.raises(ValueError):
            Adaptation(**bad)
