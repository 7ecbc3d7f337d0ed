"""robots.trig.sincos: the vectorised polynomials against float64 NumPy, edges included."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.trig import LIMIT, sincos


def _both(a):
    s, c = jax.jit(lambda a: sincos(a, jnp))(jnp.asarray(a, jnp.float32))
    return np.asarray(s, np.float64), np.asarray(c, np.float64)


@pytest.mark.parametrize("span", [2 * np.pi, 20.0, LIMIT])
def test_sincos_is_within_1e7_of_float64_over_its_range(span):
    a = np.linspace(-span, span, 2_000_001, dtype=np.float32)
    s, c = _both(a)
    exact = a.astype(np.float64)
    assert np.max(np.abs(s - np.sin(exact))) < 1e-7
    assert np.max(np.abs(c - np.cos(exact))) < 1e-7


def test_sincos_at_the_octant_edges_and_signs():
    """Multiples of π/4 (where the reduction switches polynomial and sign), both signs, and -0."""
    k = np.arange(-64, 65)
    a = np.concatenate([k * np.pi / 4, np.nextafter((k * np.pi / 4).astype(np.float32), np.float32(np.inf)),
                        np.nextafter((k * np.pi / 4).astype(np.float32), np.float32(-np.inf)), [-0.0, 0.0]])
    a = a.astype(np.float32)
    s, c = _both(a)
    exact = a.astype(np.float64)
    np.testing.assert_allclose(s, np.sin(exact), rtol=0, atol=1e-7)
    np.testing.assert_allclose(c, np.cos(exact), rtol=0, atol=1e-7)
    assert np.all(s[a > 0][np.abs(a[a > 0]) < np.pi] >= 0) and np.all(c[np.abs(a) < np.pi / 2] > 0)


def test_sincos_of_nan_and_infinity_is_nan_and_numpy_keeps_numpy():
    s, c = _both([np.nan, np.inf, -np.inf])
    assert np.all(np.isnan(s)) and np.all(np.isnan(c))
    a = np.linspace(-4, 4, 9)
    s, c = sincos(a)
    assert s.dtype == np.float64 and np.array_equal(s, np.sin(a)) and np.array_equal(c, np.cos(a))
