"""A trained map that goes on learning (ekm.learning): one update by hand (Eq. 4.7, 4.9), the rates of each rule."""

import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from ekm.indirect import IndirectEKM
from ekm.learning import (Adaptation, Noise, Trace, adapt, adapt_beyond_noise, excess_error, fresh_noise, fresh_trace,
                          rates, recent_error)

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


def test_the_noise_is_the_difference_of_the_errors_of_consecutive_ticks_of_one_command():
    # Rates 0 keep the map as it is; memory 1 makes each running mean the last value. Neuron 0 wins both
    # displacements (α 0.1 rad; d 0.11 and 0.09 m, both nearer 0.10 than 0.05). By hand, as in the test above:
    # v1 = (0.1, 0.11): c - M_0 ṽ1 = (0.0124419, 0.0088081) m/s;
    # v2 = (0.1, 0.09): ṽ2 = (0.1/π, 0.5625), M_0 ṽ2 = (0.0313081, 0.0249419), c - M_0 ṽ2 = (0.0186919, 0.0150581).
    # Their difference is (0.00625, 0.00625) m/s, |.| / √2 / c* = 0.00625 / 0.16 = 0.0390625 — the noise; the
    # recent error is the last one, |(0.0186919, 0.0150581)| / 0.16 = 0.1500180, and the error beyond the noise
    # √(0.1500180² − 0.0390625²) = 0.1448427.
    rule = Adaptation(rule="constant", eta=0.0, sigma=0.05, memory=1.0)
    ekm = IndirectEKM(jnp.asarray(W), jnp.asarray(M))
    c = jnp.asarray([0.05, 0.04], jnp.float32)
    ekm1, trace, noise = adapt_beyond_noise(ekm, jnp.asarray([0.1, 0.11], jnp.float32), c, fresh_trace(),
                                            fresh_noise(), True, rule, CFG)  # no update before: nothing to pair
    # the noise not yet measured, nothing is known to be beyond it
    assert int(noise.pairs) == 0 and float(excess_error(trace, noise, rule)) == 0.0
    v2 = jnp.asarray([0.1, 0.09], jnp.float32)
    _, trace2, noise2 = adapt_beyond_noise(ekm1, v2, c, trace, noise, True, rule, CFG)
    assert int(noise2.pairs) == 1 and float(noise2.level) == pytest.approx(0.0390625, rel=1e-4)
    assert float(recent_error(trace2, rule)) == pytest.approx(0.1500180, rel=1e-4)
    assert float(excess_error(trace2, noise2, rule)) == pytest.approx(0.1448427, rel=1e-4)
    # not paired (another command, or a tick between): the noise is not measured, and nothing is beyond it
    _, trace3, noise3 = adapt_beyond_noise(ekm1, v2, c, trace, noise, False, rule, CFG)
    assert int(noise3.pairs) == 0 and float(excess_error(trace3, noise3, rule)) == 0.0
    assert float(recent_error(trace3, rule)) == pytest.approx(0.1500180, rel=1e-4)
    # the same displacement twice: no noise, all of the error is beyond it
    _, trace4, noise4 = adapt_beyond_noise(ekm1, jnp.asarray([0.1, 0.11], jnp.float32), c, trace, noise, True,
                                           rule, CFG)
    assert float(noise4.level) == pytest.approx(0.0, abs=1e-7)
    assert float(excess_error(trace4, noise4, rule)) == pytest.approx(0.0952758, rel=1e-4)


def test_the_error_rule_s_rates_follow_the_error_beyond_the_noise():
    # ē = 0.1 and a noise of 0.08: √(0.01 − 0.0064) = 0.06 beyond it, a third of the way from floor 0.04 to
    # full 0.1: η = 0.005 + 0.095 / 3 = 0.0366667, σ = 0.3 + 0.7 / 3 = 0.5333333. A noise as large as the
    # error leaves the resting rates; so does the slip of a robot that errs by its noise alone.
    rule = Adaptation(memory=1.0)
    trace = Trace(jnp.float32(0.1), jnp.int32(1))
    for level, expected in ((0.08, (0.0366667, 0.5333333)), (0.1, (0.005, 0.3)), (0.2, (0.005, 0.3))):
        noise = Noise(jnp.float32(level), jnp.int32(1), jnp.zeros(2, jnp.float32), jnp.int32(1))
        got = rates(rule, excess_error(trace, noise, rule))
        assert (float(got[0]), float(got[1])) == pytest.approx(expected, rel=1e-5)
