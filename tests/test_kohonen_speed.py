"""The fast paths of the Kohonen core (ekm.kohonen) give what their definitions give, to the bit.

`wrap_once` is `wrap` without the ``mod`` for angles in [-2π, 2π]; `winner` searches nearest first where
`winner_by_partition` builds A(α) (Eq. 4.4) from a partition of all angles.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from ekm.data import load_default_map
from ekm.kohonen import initial_weights, winner, winner_by_partition, wrap, wrap_once

TWO_PI = np.float32(2 * np.pi)


def test_wrap_once_equals_wrap_to_the_bit_on_minus_two_pi_to_two_pi():
    rng = np.random.default_rng(0)
    edges = np.array([0.0, -0.0, np.pi, -np.pi, TWO_PI, -TWO_PI, 1e-30, -1e-30, 1e-45, 3 * np.pi / 2], np.float32)
    near = np.concatenate([np.nextafter(edges, np.float32(np.inf)), np.nextafter(edges, np.float32(-np.inf))])
    a = np.concatenate([edges, near, rng.uniform(-TWO_PI, TWO_PI, 1_000_000).astype(np.float32),
                        rng.uniform(-1e-3, 1e-3, 10_000).astype(np.float32)])
    a = a[np.abs(a) <= TWO_PI]
    fast, slow = jax.jit(wrap_once)(a), jax.jit(wrap)(a)
    np.testing.assert_array_equal(np.asarray(fast).view(np.int32), np.asarray(slow).view(np.int32))


def random_inputs(rng, n: int, scale: float):
    """``n`` inputs (α, d): uniform directions, distances up to ``scale``, a few exactly on a neuron's weight,
    a few far beyond the map and a few overflowing D² (d = 1e30)."""
    u = np.stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0, scale, n)], axis=-1).astype(np.float32)
    u[::17, 1] = 1e30
    u[::13, 1] = 5.0
    return u


def weights(kind: str, cfg: EKMConfig, rng):
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
    w = jnp.asarray(weights(kind, cfg, rng))
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
    for u in ([np.nan, 0.1], [0.3, np.nan], [np.nan, np.nan]):
        k = int(jax.jit(lambda x: winner(w, x, cfg))(jnp.asarray(u, jnp.float32)))
        assert 0 <= k < cfg.size


def test_the_search_called_eagerly_is_traced_once_not_at_every_call():
    from ekm.kohonen import _nearest_in_a

    cfg = EKMConfig(neurons=7, priority=5)  # a size no other test uses, so the count starts here
    w = initial_weights(cfg)
    before = _nearest_in_a._cache_size()
    for a in np.linspace(-3, 3, 20):
        winner(w, jnp.asarray([a, 0.05], jnp.float32), cfg)
    assert _nearest_in_a._cache_size() == before + 1
