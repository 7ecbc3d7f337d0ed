"""Indirect-mapping EKM (thesis ch. 4.2–4.3): neurons hold control-parameter matrices M_i.

Each neuron maps its locally linear region of the sensory space to wheel commands through
c_p = M_k ũ_p (Eq. 4.1/4.5), so the motor space is sampled continuously rather than at N² points.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.config import EKMConfig
from ekm.kohonen import forward_prior, initial_weights, neighbourhood, relative, scaled, update_inputs, winner


class IndirectEKM(NamedTuple):
    """Map state pytree. ``w`` ``(N², 2)``: input weights (α_i rad, d_i m); ``M`` ``(N², 2, 2)``:
    control parameters acting on the normalised input ũ = (α, d/d_scale)."""

    w: jax.Array
    M: jax.Array


def init(cfg: EKMConfig) -> IndirectEKM:
    """An untrained map: input weights on the regular grid (ch. 6.1), M_i = ``cfg.forward_init`` · M_fwd.

    The untrained robot drives straight ahead and cannot steer (:func:`ekm.kohonen.forward_prior`) —
    the inaccurate start of ch. 4.3 ("Initially, the EKM has not been trained and the motor control
    vectors c_p generated are inaccurate"); the command noise of training (``training.schedules``)
    does the exploring.
    """
    M = jnp.broadcast_to(cfg.forward_init * forward_prior(cfg), (cfg.size, 2, 2))
    return IndirectEKM(w=initial_weights(cfg), M=M)


def local_input(u, w, cfg: EKMConfig):
    """ũ expressed next to each w_i: ``scaled(w_i) + (u - w_i)`` with the angle difference wrapped.

    A neuron at α_i = 3.0 rad thus sees an input at α = -3.1 rad as 3.18 rad, so its linear model
    is not torn apart at the ±π seam.
    """
    return scaled(w, cfg) + relative(u, w, cfg)


def control(ekm: IndirectEKM, u, cfg: EKMConfig):
    """Motor control of ch. 4.2 for target input ``u`` = (α, d): returns ``(c_p, k)``.

    k is the winner (Eq. 4.2–4.4); c_p = M_k u_p if -c* ≤ M_k u_p ≤ c*, else M_k w_k (Eq. 4.5) — the
    wheels are *not* simply saturated, which would only drive a badly aligned robot straight ahead.
    """
    k = winner(ekm.w, u, cfg)
    Mk, wk = ekm.M[k], ekm.w[k]
    c_u = Mk @ local_input(u, wk, cfg)
    c_w = Mk @ scaled(wk, cfg)
    feasible = jnp.all(jnp.abs(c_u) <= cfg.c_max)
    return jnp.where(feasible, c_u, c_w), k


def update(ekm: IndirectEKM, v, c_p, eta, sigma, cfg: EKMConfig) -> IndirectEKM:
    """One self-organising step (ch. 4.3) from the executed command ``c_p`` and displacement ``v``.

    k = winner for v (step 4); Δw_i = η G(k,i)(v - w_i) (Eq. 4.7);
    ΔM_i = η G(k,i)(c_p - M_i ṽ) ṽᵀ (Eq. 4.9, gradient descent on Eq. 4.8), ṽ local to each neuron.
    """
    k = winner(ekm.w, v, cfg)
    g = neighbourhood(cfg, k, sigma)
    v_loc = local_input(v, ekm.w, cfg)  # (N², 2)
    err = c_p[None, :] - jnp.einsum("nij,nj->ni", ekm.M, v_loc)
    M = ekm.M + (eta * g)[:, None, None] * err[:, :, None] * v_loc[:, None, :]
    return IndirectEKM(w=update_inputs(ekm.w, v, g, eta, cfg), M=M)
