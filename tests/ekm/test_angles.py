"""The one angle wrap (ekm.angles): (−π, π], the same bits for a Python float, a NumPy array and a JAX array, and
its two cheaper JAX forms — wrap_once gives wrap's bits on [−2π, 2π], wrap_near wrap's value but for the sign of
±π."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.angles import wrap, wrap_near, wrap_once

PI = math.pi
TWO_PI = np.float32(2 * np.pi)


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


def test_wrap_once_equals_wrap_to_the_bit_on_minus_two_pi_to_two_pi():
    rng = np.random.default_rng(0)
    edges = np.array([0.0, -0.0, np.pi, -np.pi, TWO_PI, -TWO_PI, 1e-30, -1e-30, 1e-45, 3 * np.pi / 2], np.float32)
    near = np.concatenate([np.nextafter(edges, np.float32(np.inf)), np.nextafter(edges, np.float32(-np.inf))])
    a = np.concatenate([edges, near, rng.uniform(-TWO_PI, TWO_PI, 1_000_000).astype(np.float32),
                        rng.uniform(-1e-3, 1e-3, 10_000).astype(np.float32)])
    a = a[np.abs(a) <= TWO_PI]
    fast, slow = jax.jit(wrap_once)(a), jax.jit(wrap)(a)
    np.testing.assert_array_equal(np.asarray(fast).view(np.int32), np.asarray(slow).view(np.int32))


def test_wrap_gives_the_same_bits_for_a_float_a_numpy_array_and_a_jax_array():
    a = np.random.default_rng(1).uniform(-20.0, 20.0, 10_000)
    a[:4] = (PI, -PI, 0.0, 3 * PI)
    as_floats = np.array([wrap(float(x)) for x in a])
    np.testing.assert_array_equal(as_floats.view(np.int64), wrap(a).view(np.int64))
    assert wrap(PI) == PI and wrap(-PI) == PI and wrap(3 * PI) == PI
    a32 = a.astype(np.float32)
    np.testing.assert_array_equal(wrap(a32).view(np.int32), np.asarray(jax.jit(wrap)(a32)).view(np.int32))
