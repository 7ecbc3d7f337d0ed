"""Angles: the one wrap to (−π, π] that every heading, bearing and angle difference of the package goes through.

:func:`wrap` takes a Python float, a NumPy array or a JAX array alike: Python's ``%`` is NumPy's and JAX's
``mod`` (the result takes the divisor's sign), so ``π − (π − a) mod 2π`` gives the same bits whichever
the caller holds, and ``wrap(π) = π``, ``wrap(−π) = π``. :func:`wrap_once` and :func:`wrap_near` are two
cheaper forms of it for JAX code whose inputs are known to lie in a narrower range (the winner search and
the neural fields evaluate them for every neuron every tick).
"""

from __future__ import annotations

import math

PI = math.pi
TURN = 2.0 * math.pi


def wrap(a):
    """``a`` (rad) wrapped to (−π, π]: ``π − (π − a) mod 2π``."""
    return PI - (PI - a) % TURN


def wrap_once(a):
    """:func:`wrap` of a JAX array ``a`` in [−2π, 2π] — the difference of two wrapped angles, or a wrapped angle
    plus at most one turn — bit for bit, without the ``mod``.

    ``mod(x, 2π)`` of x = π − a ∈ [−π, 3π] is x, x − 2π or x + 2π, and each is what ``mod`` returns
    (x − 2π is exact for x ≥ 2π; x + 2π is the same rounded sum ``mod`` adds). XLA's CPU ``mod`` is much
    slower than this select. The turn is selected rather than added as a constant so that XLA cannot
    fold it into π − a (that would round differently).
    """
    import jax.numpy as jnp

    x = PI - a
    return PI - (x - jnp.where(x >= TURN, TURN, jnp.where(x < 0.0, -TURN, 0.0)))


def wrap_near(a):
    """A JAX array ``a`` wrapped to [−π, π] by rounding — equal to :func:`wrap` except that −π may stay −π.
    For angle differences that are then squared or taken in absolute value, where that sign does not matter; on
    the CPU it is cheaper than :func:`wrap`'s ``mod``."""
    import jax.numpy as jnp

    return a - TURN * jnp.round(a / TURN)
