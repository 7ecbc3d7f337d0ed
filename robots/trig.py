"""Sine and cosine of many headings at once, vectorised for XLA's CPU back-end.

XLA's CPU ``sin`` and ``cos`` cost far more an element than the arithmetic around them. Training's
kinematics evaluate both for every one of the 64 sub-steps of a control period, in every trial of every
step (:func:`robots.kinematics.advance_pose`), so they would be the largest kernels of a training step.
:func:`sincos` evaluates them with the Cephes single-precision polynomials (S. L. Moshier,
``sinf.c``/``cosf.c``) in plain arithmetic, which XLA fuses and vectorises: the pair costs a fraction of
XLA's.
"""

from __future__ import annotations

import numpy as np

# Cody–Waite reduction: π/4 as the sum of three floats, so that a - jπ/4 keeps its accuracy up to LIMIT.
_PI4 = (0.78515625, 2.4187564849853515625e-4, 3.77489497744594108e-8)
_SIN = (-1.9515295891e-4, 8.3321608736e-3, -1.6666654611e-1)  # sin z = z + z³ P(z²), |z| ≤ π/4
_COS = (2.443315711809948e-5, -1.388731625493765e-3, 4.166664568298827e-2)  # cos z = 1 - z²/2 + z⁴ Q(z²)
LIMIT = 8192.0  # Cephes' bound for |a|; training's headings stay within a few turns of zero


def sincos(a, xp=np):
    """``(sin a, cos a)``. NumPy arrays get NumPy's own functions (the float64 references and the pymunk
    world); ``jax.numpy`` arrays the polynomials, within 1e-7 of the float64 values for |a| ≤ :data:`LIMIT`
    (``tests/robots/test_trig.py``). NaN and ±∞ give NaN, as ``sin`` and ``cos`` do.

    ``|a|`` is reduced to ``z = |a| - jπ/4`` with j even, ``|z| ≤ π/4``; j/2 mod 4 says which of ±sin z,
    ±cos z each result is, and sin is odd in a.
    """
    if xp is np:
        return np.sin(a), np.cos(a)
    dtype = a.dtype
    c = [np.asarray(x, dtype) for x in (*_PI4, *_SIN, *_COS)]
    pi4a, pi4b, pi4c, s2, s1, s0, c2, c1, c0 = c
    mag = xp.abs(a)
    j = (mag * np.asarray(4.0 / np.pi, dtype)).astype(xp.int32)
    j = j + (j & 1)
    y = j.astype(dtype)
    z = ((mag - y * pi4a) - y * pi4b) - y * pi4c
    zz = z * z
    ps = z + z * zz * (s0 + zz * (s1 + zz * s2))
    pc = 1.0 - 0.5 * zz + zz * zz * (c0 + zz * (c1 + zz * c2))
    octant = j & 7  # 0, 2, 4 or 6: |a| is near 0, π/2, π or 3π/2 (mod 2π)
    swap = (octant & 2) != 0
    s = xp.where(swap, pc, ps)
    co = xp.where(swap, ps, pc)
    s = xp.where(octant >= 4, -s, s)
    co = xp.where((octant == 2) | (octant == 4), -co, co)
    return xp.where(a < 0, -s, s), co
