"""Known values of the Kohonen core shared by the EKMs (ekm.kohonen, ekm.charts, ekm.indirect, ekm.direct;
issue 12, item 5): angle wrapping, the initial lattice, G(k, i), map units, the priority set A(α) at a
tie, Eq. 4.5 at exactly c*, and one update of each mapping worked out by hand."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from ekm import direct, indirect
from ekm.charts import model_input, polar, signed
from ekm.config import EKMConfig
from ekm.kohonen import (forward_prior, initial_weights, neighbourhood, relative, scaled, units, update_inputs,
                         winner, wrap, wrap_near)

PI = math.pi


@pytest.mark.parametrize("a, want", [(0.3, 0.3), (PI, PI), (-PI, PI), (1.5 * PI, -0.5 * PI), (-1.5 * PI, 0.5 * PI),
                                     (2.0 * PI + 0.25, 0.25), (-4.0 * PI - 0.25, -0.25), (0.9 * PI, 0.9 * PI)])
def test_wrap_maps_angles_to_minus_pi_exclusive_pi_inclusive(a, want):
    assert float(wrap(jnp.float32(a))) == pytest.approx(want, abs=1e-5)


@pytest.mark.parametrize("a, want", [(0.3, 0.3), (1.5 * PI, -0.5 * PI), (-1.5 * PI, 0.5 * PI), (2.0 * PI + 0.25, 0.25),
                                     (-4.0 * PI - 0.25, -0.25), (0.9 * PI, 0.9 * PI), (-0.9 * PI, -0.9 * PI),
                                     (5.0 * PI + 0.5, -PI + 0.5), (7.0, 7.0 - 2.0 * PI)])
def test_wrap_near_rounds_to_the_nearest_turn(a, want):
    assert float(wrap_near(jnp.float32(a))) == pytest.approx(want, abs=1e-5)


def test_wrap_near_keeps_plus_and_minus_pi_as_they_are():
    assert abs(float(wrap_near(jnp.float32(PI)))) == pytest.approx(PI, abs=1e-6)
    assert abs(float(wrap_near(jnp.float32(-PI)))) == pytest.approx(PI, abs=1e-6)


def test_initial_weights_are_sector_centres_by_row_and_distances_by_column():
    cfg = EKMConfig(neurons=3)
    w = np.asarray(initial_weights(cfg))
    # Neuron i at lattice (i // 3, i % 3): row = direction, centre of sector i // 3 of three (-2π/3, 0, 2π/3);
    # column = distance 0, 0.08, 0.16 m.
    want = [[a, d] for a in (-2 * PI / 3, 0.0, 2 * PI / 3) for d in (0.0, 0.08, 0.16)]
    np.testing.assert_allclose(w, want, atol=1e-6)
    w4 = np.asarray(initial_weights(EKMConfig(neurons=4, d_scale=0.2)))
    np.testing.assert_allclose(w4[::4, 0], [-0.75 * PI, -0.25 * PI, 0.25 * PI, 0.75 * PI], atol=1e-6)
    np.testing.assert_allclose(w4[:4, 1], [0.0, 0.2 / 3, 0.4 / 3, 0.2], atol=1e-6)


def test_forward_prior_drives_both_wheels_with_the_distance_only():
    np.testing.assert_array_equal(np.asarray(forward_prior(EKMConfig(c_max=0.12))), np.float32([[0, 0.12], [0, 0.12]]))


def test_neighbourhood_values_for_a_wide_gaussian():
    cfg = EKMConfig(neurons=4)
    g = np.asarray(neighbourhood(cfg, 1 * 4 + 1, 2.0)).reshape(4, 4)  # winner at row 1, column 1; 2σ² = 8
    for r in range(4):
        for c in range(4):
            dr = min(abs(r - 1), 4 - abs(r - 1))  # rows (directions) wrap round
            assert g[r, c] == pytest.approx(math.exp(-(dr * dr + (c - 1) ** 2) / 8.0), rel=1e-6), (r, c)
    g0 = np.asarray(neighbourhood(cfg, 3, 0.5)).reshape(4, 4)  # row 0, column 3; columns do not wrap
    assert g0[0, 0] == pytest.approx(math.exp(-9 / 0.5), rel=1e-5)
    assert g0[3, 3] == pytest.approx(math.exp(-1 / 0.5), rel=1e-6)


def test_map_units_are_half_turns_and_step_lengths():
    cfg = EKMConfig(d_scale=0.2)
    np.testing.assert_allclose(np.asarray(units(cfg)), [PI, 0.2], rtol=1e-6)
    np.testing.assert_allclose(np.asarray(scaled(jnp.asarray([PI / 2, 0.1]), cfg)), [0.5, 0.5], rtol=1e-6)
    w = jnp.asarray([[3.0, 0.05], [-1.0, 0.2]])
    got = np.asarray(relative(jnp.asarray([-3.0, 0.1]), w, cfg))
    np.testing.assert_allclose(got, [[(2 * PI - 6.0) / PI, 0.25], [-2.0 / PI, -0.5]], atol=1e-6)  # angle wrapped


def test_priority_keeps_both_neurons_tied_at_the_edge_of_a():
    """Eq. 4.4 with |A(α)| = 1 and two neurons exactly as far in angle on either side: both are in A(α),
    and the distance decides between them."""
    cfg = EKMConfig(neurons=2, priority=1)
    w = jnp.asarray([[0.5, 0.15], [-0.5, 0.02], [2.0, 0.02], [-2.5, 0.02]], jnp.float32)
    u = jnp.asarray([0.0, 0.02], jnp.float32)
    d = np.abs(np.asarray(relative(u, w, cfg))[:, 0])
    assert d[0] == d[1]  # an exact tie in float32
    assert int(winner(w, u, cfg)) == 1
    assert int(winner(w, jnp.asarray([0.0, 0.15], jnp.float32), cfg)) == 0


def test_without_a_priority_set_the_nearest_neuron_by_eq_4_3_wins():
    cfg = EKMConfig(neurons=2, gamma_alpha=1.0, gamma_d=4.0)
    w = jnp.asarray([[0.3 * PI, 0.0], [0.0, 0.16 * 0.6], [PI, 0.0], [-0.5 * PI, 0.0]], jnp.float32)
    # D² = γ_α (Δα/π)² + γ_d (Δd/d_scale)²: neuron 0: 0.09; neuron 1: 4 · 0.36 = 1.44.
    assert int(winner(w, jnp.asarray([0.0, 0.0]), cfg)) == 0
    cfg_d = EKMConfig(neurons=2, gamma_alpha=20.0, gamma_d=1.0)  # neuron 0: 1.8; neuron 1: 0.36
    assert int(winner(w, jnp.asarray([0.0, 0.0]), cfg_d)) == 1


def test_eq_4_5_at_exactly_c_star_uses_m_k_u_p():
    cfg = EKMConfig(neurons=2, priority=1)
    w = jnp.asarray([[0.0, 0.08], [1.5, 0.08], [3.0, 0.08], [-1.5, 0.08]], jnp.float32)
    M = jnp.zeros((4, 2, 2)).at[0].set(forward_prior(cfg))  # c = c* · d/d_scale per wheel
    c, k = indirect.control(indirect.IndirectEKM(w, M), jnp.asarray([0.0, 0.16], jnp.float32), cfg)
    assert int(k) == 0
    np.testing.assert_array_equal(np.asarray(c), np.float32([0.16, 0.16]))  # |c| = c*: allowed, not M_k w_k


def test_charts_known_values():
    cfg = EKMConfig(d_scale=0.2)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([0.25 * PI, 0.1]), cfg)), [0.25, 0.5], atol=1e-6)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([0.75 * PI, 0.1]), cfg)), [-0.25, -0.5], atol=1e-6)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([-0.75 * PI, 0.1]), cfg)), [0.25, -0.5], atol=1e-6)
    w = jnp.asarray([[3.0, 0.1]])
    np.testing.assert_allclose(np.asarray(polar(jnp.asarray([-3.0, 0.1]), w, cfg)), [[(2 * PI - 3.0) / PI, 0.5]],
                               atol=1e-6)
    np.testing.assert_allclose(np.asarray(model_input(jnp.asarray([-3.0, 0.1]), w, EKMConfig(d_scale=0.2, chart="polar"))),
                               [[(2 * PI - 3.0) / PI, 0.5]], atol=1e-6)
    # the signed chart's input is one row, the same for every neuron
    np.testing.assert_allclose(np.asarray(model_input(jnp.asarray([0.75 * PI, 0.1]), w, cfg)), [-0.25, -0.5], atol=1e-6)


def test_update_inputs_moves_each_weight_by_eta_g_towards_v_across_the_seam():
    cfg = EKMConfig(neurons=2)
    w = jnp.asarray([[3.0, 0.1], [-1.0, 0.0], [0.0, 0.16], [1.0, 0.05]], jnp.float32)
    g = jnp.asarray([1.0, 0.5, 0.0, 0.25], jnp.float32)
    new = np.asarray(update_inputs(w, jnp.asarray([-3.0, 0.02]), g, 0.4, cfg))
    step = 2 * PI - 6.0  # from 3.0 to -3.0 the short way, across ±π
    want = [[3.0 + 0.4 * step, 0.1 + 0.4 * -0.08], [-1.0 + 0.2 * -2.0, 0.0 + 0.2 * 0.02], [0.0, 0.16],
            [1.0 + 0.1 * (2 * PI - 4.0), 0.05 + 0.1 * -0.03]]  # -4 rad is +2.28 the short way
    want[0][0] = (want[0][0] + PI) % (2 * PI) - PI  # re-wrapped
    np.testing.assert_allclose(new, want, atol=1e-5)


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


def test_untrained_maps_start_from_the_forward_prior():
    cfg = EKMConfig(neurons=3, forward_init=0.5)
    m = indirect.init(cfg)
    np.testing.assert_allclose(np.asarray(m.M), np.broadcast_to(0.5 * np.float32([[0, 0.16], [0, 0.16]]), (9, 2, 2)))
    d = direct.init(cfg)
    # c_i = 0.5 M_fwd w̃_i (signed chart): both wheels 0.08 · d_i / d_scale ahead, minus that behind.
    dist = np.asarray(d.w)[:, 1] / cfg.d_scale
    behind = np.abs(np.asarray(d.w)[:, 0]) > PI / 2
    want = 0.08 * np.where(behind, -dist, dist)
    np.testing.assert_allclose(np.asarray(d.c), np.stack([want, want], axis=1), atol=1e-6)
