"""Winner search (Eq. 4.2–4.4), control (Eq. 4.5) and updates (Eq. 4.7, 4.9) of the EKMs."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm import direct, indirect, maps
from ekm.config import EKMConfig
from ekm.kohonen import initial_weights, neighbourhood, winner


def weights(*rows):
    return jnp.asarray(rows, jnp.float32)


def test_winner_gives_direction_priority_over_distance():
    cfg = EKMConfig(neurons=2, priority=1)
    # Neuron 0 is nearer by Eq. 4.3 overall, but neuron 1 encodes the input's direction exactly.
    w = weights([0.30, 0.05], [0.0, 0.15], [2.0, 0.05], [-2.0, 0.05])
    u = jnp.asarray([0.0, 0.05])
    assert int(winner(w, u, EKMConfig(neurons=2, priority=4))) == 0  # plain nearest neighbour
    assert int(winner(w, u, cfg)) == 1  # |A(α)| = 1: the direction decides


def test_priority_set_takes_the_closest_angles_and_distance_decides_inside_it():
    cfg = EKMConfig(neurons=2, priority=2)
    w = weights([0.10, 0.15], [-0.12, 0.02], [0.5, 0.02], [3.0, 0.02])
    # A(0) = {0, 1} (|Δα| 0.10 and 0.12); neuron 2 is nearer in distance but outside A(α).
    assert int(winner(w, jnp.asarray([0.0, 0.02]), cfg)) == 1
    assert int(winner(w, jnp.asarray([0.0, 0.14]), cfg)) == 0


def test_winner_wraps_angles_across_pi():
    cfg = EKMConfig(neurons=2, priority=1)
    w = weights([-3.10, 0.05], [2.6, 0.05], [0.0, 0.05], [1.0, 0.05])
    assert int(winner(w, jnp.asarray([3.12, 0.05]), cfg)) == 0  # 3.12 and -3.10 are 0.06 rad apart


def test_initial_weights_form_a_regular_grid_over_the_sensory_space():
    cfg = EKMConfig(neurons=15)
    w = np.asarray(initial_weights(cfg))
    assert w.shape == (225, 2)
    assert np.allclose(np.unique(w[:, 1].round(6)), np.linspace(0, 0.16, 15).round(6))
    alphas = np.unique(w[:, 0].round(6))
    assert len(alphas) == 15 and np.allclose(np.diff(alphas), 2 * np.pi / 15, atol=1e-5)


def test_neighbourhood_is_a_gaussian_of_lattice_distance_wrapping_round_directions():
    cfg = EKMConfig(neurons=5)
    g = np.asarray(neighbourhood(cfg, 2 * 5 + 2, 1.0)).reshape(5, 5)
    assert g[2, 2] == pytest.approx(1.0)
    assert g[2, 3] == pytest.approx(np.exp(-0.5), rel=1e-6)
    g0 = np.asarray(neighbourhood(cfg, 0, 1.0)).reshape(5, 5)
    assert g0[4, 0] == pytest.approx(np.exp(-0.5), rel=1e-6)  # row 4 is next to row 0


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


def test_direct_update_pulls_outputs_towards_the_executed_command():
    cfg = EKMConfig(mapping="direct", neurons=3, priority=3)
    ekm = direct.init(cfg)
    v, c_p = jnp.asarray([-0.7, 0.05]), jnp.asarray([0.02, 0.09])
    for _ in range(300):
        ekm = direct.update(ekm, v, c_p, 0.5, 0.5, cfg)
    c, _ = maps.control(ekm, v, cfg)
    assert np.allclose(c, c_p, atol=1e-3)


def test_maps_dispatch_on_the_configured_mapping():
    for mapping, cls in (("direct", direct.DirectEKM), ("indirect", indirect.IndirectEKM)):
        cfg = EKMConfig(mapping=mapping, neurons=4)
        assert isinstance(maps.init(cfg), cls)


@pytest.mark.parametrize("bad", [dict(mapping="both"), dict(neurons=1), dict(priority=0), dict(gamma_d=-1.0),
                                 dict(d_scale=float("nan"))])
def test_config_refuses_bad_values(bad):
    with pytest.raises(ValueError):
        EKMConfig(**bad)


@pytest.mark.parametrize("chart", ["signed", "polar"])
@pytest.mark.parametrize("mapping", ["direct", "indirect"])
def test_untrained_maps_drive_straight_and_cannot_steer(mapping, chart):
    """The forward reflex only breaks the forward/backward symmetry; it does not reach targets. In the
    signed chart it drives straight back to targets behind, in the polar chart always forwards."""
    cfg = EKMConfig(mapping=mapping, chart=chart)
    ekm = maps.init(cfg)
    for alpha in (-2.5, -1.0, 0.0, 0.7, 3.0):
        left, right = np.asarray(maps.control(ekm, jnp.asarray([alpha, 0.08]), cfg)[0], dtype=float)
        assert left == pytest.approx(right, abs=1e-4)  # no turning, whatever the direction
        forwards = chart == "polar" or abs(alpha) < np.pi / 2
        assert (left > 0.0) if forwards else (left < 0.0)
