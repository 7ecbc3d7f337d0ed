"""The Kohonen core shared by the EKMs (ekm.kohonen): the initial lattice, G(k, i), map units,
the winner search with the priority set A(α) (Eq. 4.2–4.4) and the input update — known values worked out by
hand (issue 12, item 5) — and the fast paths, which give what their definitions give, to the bit."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from ekm.data import load_default_map
from ekm.kohonen import (forward_prior, initial_weights, neighbourhood, relative, scaled, units, update_inputs, winner,
                         winner_by_partition)

PI = math.pi


# -------------------------------------------------------------------- angles, lattice, neighbourhood, units

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


def test_initial_weights_form_a_regular_grid_over_the_sensory_space():
    cfg = EKMConfig(neurons=15)
    w = np.asarray(initial_weights(cfg))
    assert w.shape == (225, 2)
    assert np.allclose(np.unique(w[:, 1].round(6)), np.linspace(0, 0.16, 15).round(6))
    alphas = np.unique(w[:, 0].round(6))
    assert len(alphas) == 15 and np.allclose(np.diff(alphas), 2 * np.pi / 15, atol=1e-5)


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


def test_neighbourhood_is_a_gaussian_of_lattice_distance_wrapping_round_directions():
    cfg = EKMConfig(neurons=5)
    g = np.asarray(neighbourhood(cfg, 2 * 5 + 2, 1.0)).reshape(5, 5)
    assert g[2, 2] == pytest.approx(1.0)
    assert g[2, 3] == pytest.approx(np.exp(-0.5), rel=1e-6)
    g0 = np.asarray(neighbourhood(cfg, 0, 1.0)).reshape(5, 5)
    assert g0[4, 0] == pytest.approx(np.exp(-0.5), rel=1e-6)  # row 4 is next to row 0


def test_map_units_are_half_turns_and_step_lengths():
    cfg = EKMConfig(d_scale=0.2)
    np.testing.assert_allclose(np.asarray(units(cfg)), [PI, 0.2], rtol=1e-6)
    np.testing.assert_allclose(np.asarray(scaled(jnp.asarray([PI / 2, 0.1]), cfg)), [0.5, 0.5], rtol=1e-6)
    w = jnp.asarray([[3.0, 0.05], [-1.0, 0.2]])
    got = np.asarray(relative(jnp.asarray([-3.0, 0.1]), w, cfg))
    np.testing.assert_allclose(got, [[(2 * PI - 6.0) / PI, 0.25], [-2.0 / PI, -0.5]], atol=1e-6)  # angle wrapped


# --------------------------------------------------------------------------------- the winner (Eq. 4.2-4.4)

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


def test_priority_of_all_but_one_neuron_leaves_out_the_furthest_in_angle():
    """Eq. 4.4 with |A(α)| = N² - 1 = 3: the neuron furthest in angle does not compete, even though by Eq. 4.3
    it is the nearest. u = (0, 0.02 m); |Δα|/π = 0.095, 0.127, 0.159, 0.318; (Δd/d_scale)² = 0.766, 0.766,
    0.766, 0 — D² = 0.775, 0.782, 0.791, 0.101. Kills ``jnp.partition(dalpha, cfg.a_size + 1)`` (an index
    past the end when |A(α)| = N² - 1)."""
    w = jnp.asarray([[0.3, 0.16], [-0.4, 0.16], [0.5, 0.16], [1.0, 0.02]], jnp.float32)
    u = jnp.asarray([0.0, 0.02], jnp.float32)
    assert int(winner(w, u, EKMConfig(neurons=2, priority=3))) == 0
    assert int(winner(w, u, EKMConfig(neurons=2, priority=4))) == 3  # everyone competes: Eq. 4.3 alone
    assert int(winner(w, u, EKMConfig(neurons=2, priority=2))) == 0


# ----------------------------------------------------------------------------------------- the input update

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


# ----------------------------------------------------------------------------------------------- fast paths

# `winner` searches nearest first where `winner_by_partition` builds A(α) (Eq. 4.4) from a partition of all
# angles: it gives what the definition gives, to the bit.

def random_inputs(rng, n: int, scale: float):
    """``n`` inputs (α, d): uniform directions, distances up to ``scale``, a few exactly on a neuron's weight,
    a few far beyond the map and a few overflowing D² (d = 1e30)."""
    u = np.stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0, scale, n)], axis=-1).astype(np.float32)
    u[::17, 1] = 1e30
    u[::13, 1] = 5.0
    return u


def weights_of(kind: str, cfg: EKMConfig, rng):
    if kind == "grid":  # exact ties everywhere: a row of N neurons shares each angle
        return np.asarray(initial_weights(cfg))
    if kind == "coarse":  # angles on a coarse grid, distances random: ties at A(α)'s boundary
        alpha = rng.integers(-6, 7, cfg.size) * np.float32(np.pi / 6)
        return np.stack([alpha, rng.uniform(0, 0.2, cfg.size)], -1).astype(np.float32)
    return np.stack([rng.uniform(-np.pi, np.pi, cfg.size), rng.uniform(0, 0.2, cfg.size)], -1).astype(np.float32)


@pytest.mark.parametrize("neurons, priority", [(15, None), (15, 1), (15, 2), (15, 50), (15, 224), (15, 225), (4, 3), (2, 1)])
@pytest.mark.parametrize("kind", ["grid", "coarse", "random"])
def test_the_nearest_first_search_finds_the_winner_of_the_definition(neurons, priority, kind):
    cfg = EKMConfig(neurons=neurons, priority=priority)
    rng = np.random.default_rng(neurons * 1000 + (priority or 0) * 10 + len(kind))
    w = jnp.asarray(weights_of(kind, cfg, rng))
    u = random_inputs(rng, 2000, 0.3)
    u[::11] = np.asarray(w)[rng.integers(cfg.size, size=len(u[::11]))]  # on a neuron's weight: ties in D²
    fast = jax.jit(jax.vmap(lambda x: winner(w, x, cfg)))(u)
    slow = jax.jit(jax.vmap(lambda x: winner_by_partition(w, x, cfg)))(u)
    np.testing.assert_array_equal(np.asarray(fast), np.asarray(slow))


@pytest.mark.parametrize("chart", ["signed", "polar"])
def test_the_search_finds_the_definitions_winner_on_the_shipped_maps(chart):
    maps = load_default_map(chart)
    rng = np.random.default_rng(1)
    u = random_inputs(rng, 3000, 1.2)
    fast, slow = (jax.jit(jax.vmap(jax.vmap(lambda w, x: f(w, x, maps.cfg), in_axes=(None, 0)), in_axes=(0, None)))
                  for f in (winner, winner_by_partition))
    np.testing.assert_array_equal(np.asarray(fast(maps.ekm.w, u)), np.asarray(slow(maps.ekm.w, u)))


def test_neurons_whose_distance_overflows_do_not_end_the_search_early():
    """Only the neurons beyond reach overflow D² (= ∞): the nearest neuron by D² (0) is outside A(α) (|A| = 1),
    and the search must go on to the one nearest in angle (1), not stop because some D² is infinite."""
    cfg = EKMConfig(neurons=2, priority=1)
    w = jnp.asarray([[0.5, 0.1], [0.0, 0.5], [3.0, 1e30], [3.0, 1e30]], jnp.float32)
    u = jnp.asarray([0.0, 0.1], jnp.float32)
    assert int(winner_by_partition(w, u, cfg)) == 1
    assert int(winner(w, u, cfg)) == int(jax.jit(winner, static_argnames="cfg")(w, u, cfg)) == 1


def test_the_search_ends_on_a_nan_input():
    cfg = EKMConfig()
    w = initial_weights(cfg)
    search = jax.jit(lambda x: winner(w, x, cfg))  # compiled once for the three inputs
    for u in ([np.nan, 0.1], [0.3, np.nan], [np.nan, np.nan]):
        k = int(search(jnp.asarray(u, jnp.float32)))
        assert 0 <= k < cfg.size


def test_the_search_called_eagerly_is_traced_once_not_at_every_call():
    from ekm.kohonen import _nearest_in_a

    cfg = EKMConfig(neurons=7, priority=5)  # a size no other test uses, so the count starts here
    w = initial_weights(cfg)
    before = _nearest_in_a._cache_size()
    for a in np.linspace(-3, 3, 20):
        winner(w, jnp.asarray([a, 0.05], jnp.float32), cfg)
    assert _nearest_in_a._cache_size() == before + 1
