"""The coordinates in which a neuron's linear control model c_p = M ũ_p (Eq. 4.1/4.5/4.9) reads a target.

The thesis writes the model on the polar input u_p = (α, d) itself. That is right for targets ahead:
a circular arc to the point (α, d) turns the heading by 2α and has chord d, so its wheel speeds are
v ∓ ω b/2 with ω = 2α/T and v = d α / (T sin α) — linear in d at fixed α, nearly linear in α, and
zero for a target dead ahead as d → 0. Behind the robot it is wrong: there α ≈ ±π, so as d → 0 the
model still commands c ≈ M (±π, 0) ≠ 0, and the forward arc to a point just behind is a near-full
circle. A map trained on it reaches targets behind by dithering and turning round (measured:
``chart="polar"``; README).

The **signed** chart (the default) keeps the thesis's polar coordinates for targets ahead and measures
targets behind from the robot's back, with the distance counted negative:

    ũ = (α, d)            if |α| ≤ π/2,
    ũ = (α ∓ π, -d)       otherwise (α - π for α > π/2, α + π for α < -π/2).

A target behind is then reached by the reversing arc — the mirror image of the forward one — and
the command for a target dead behind vanishes with d, as for one dead ahead. The chart jumps at the
robot's sides (|α| = π/2), where the forward and the reversing arc are equally long; the jump does
not tear a neuron's model apart. Just behind a side, ũ is minus the ũ of the mirrored point just
ahead of it, so a linear model commands minus that point's command; and the one-step inverse above
is odd, f(-α, -d) = -f(α, d), so minus the forward arc to the point ahead is the reversing arc to the
point behind. Both charts are in map units: angles in half-turns (/π) and distances in step lengths
(/d_scale) (see :class:`ekm.config.EKMConfig`).
"""

from __future__ import annotations

import jax.numpy as jnp

from ekm.config import EKMConfig
from ekm.kohonen import relative, scaled


def polar(u, w, cfg: EKMConfig):
    """The thesis's ũ = (α/π, d/d_scale), with α unwrapped next to each neuron weight ``w`` ``(..., 2)``.

    A neuron at α_i = 3.0 rad thus sees an input at α = -3.1 rad as 3.18 rad, so its linear model is
    not torn apart at the ±π seam.
    """
    return scaled(w, cfg) + relative(u, w, cfg)


def signed(u, cfg: EKMConfig):
    """ũ = (α'/π, d'/d_scale): α' = α - π·round(α/π) ∈ [-π/2, π/2], d' = d ahead and -d behind."""
    turns = jnp.round(u[..., 0] / jnp.pi)  # 0 ahead, ±1 behind
    return jnp.stack([u[..., 0] / jnp.pi - turns, u[..., 1] * (1.0 - 2.0 * jnp.abs(turns)) / cfg.d_scale], axis=-1)


def model_input(u, w, cfg: EKMConfig):
    """ũ of input ``u`` = (α, d) for the linear model of each neuron weight in ``w`` ``(..., 2)``, in
    ``cfg.chart``; the result broadcasts against ``w``. The polar chart's depends on each weight and has the
    shape of ``w``; the signed chart's does not and keeps the shape of ``u`` — broadcast to every neuron,
    XLA would write it out in a kernel of its own every training step."""
    if cfg.chart == "polar":
        return polar(u, w, cfg)
    return signed(u, cfg)
