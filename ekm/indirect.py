"""Indirect-mapping EKM (thesis ch. 4.2–4.3): neurons hold control-parameter matrices M_i.

Each neuron maps its locally linear region of the sensory space to wheel commands through
c_p = M_k ũ_p (Eq. 4.1/4.5), so the motor space is sampled continuously rather than at N² points.
ũ_p is the target in the coordinates of ``cfg.chart`` (:mod:`ekm.charts`).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.config import EKMConfig
from ekm.charts import model_input
from ekm.kohonen import forward_prior, initial_weights, neighbourhood, update_inputs, winner


class IndirectEKM(NamedTuple):
    """Map state pytree. ``w`` ``(N², 2)``: input weights (α_i rad, d_i m); ``M`` ``(N², 2, 2)``:
    control parameters acting on the target in map units and ``cfg.chart`` coordinates (:mod:`ekm.charts`)."""

    w: jax.Array
    M: jax.Array


def init(cfg: EKMConfig) -> IndirectEKM:
    """An untrained map: input weights on the regular grid (ch. 6.1), M_i = ``cfg.forward_init`` · M_fwd.

    The untrained robot drives straight ahead — in the signed chart straight back to targets behind —
    and cannot steer (:func:`ekm.kohonen.forward_prior`): the inaccurate start of ch. 4.3 ("Initially,
    the EKM has not been trained and the motor control vectors c_p generated are inaccurate"); the
    command noise of training (``training.schedules``) does the exploring.
    """
    M = jnp.broadcast_to(cfg.forward_init * forward_prior(cfg), (cfg.size, 2, 2))
    return IndirectEKM(w=initial_weights(cfg), M=M)


def control(ekm: IndirectEKM, u, cfg: EKMConfig):
    """Motor control of ch. 4.2 for target input ``u`` = (α, d): returns ``(c_p, k)``.

    k is the winner (Eq. 4.2–4.4); c_p = M_k ũ_p if -c* ≤ M_k ũ_p ≤ c*, else M_k w̃_k (Eq. 4.5) — the
    wheels are *not* simply saturated, which would only drive a badly aligned robot straight ahead.
    """
    k = winner(ekm.w, u, cfg)
    return command(ekm, u, k, cfg), k


def command(ekm: IndirectEKM, u, k, cfg: EKMConfig):
    """Eq. 4.5 for neuron ``k``: c = M_k ũ_p if every wheel is within ±c*, else M_k w̃_k.

    :func:`control` calls it for the winner of ``u``; the neural fields (Eq. 5.5) for the winner of
    their activity, which need not be the neuron nearest ``u``.
    """
    Mk, wk = ekm.M[k], ekm.w[k]
    c_u = apply(Mk, model_input(u, wk, cfg))
    c_w = apply(Mk, model_input(wk, wk, cfg))
    feasible = jnp.all(jnp.abs(c_u) <= cfg.c_max)
    return jnp.where(feasible, c_u, c_w)


def apply(M, u):
    """M u for control matrices ``M`` ``(..., 2, 2)`` and inputs ``u`` ``(..., 2)``: the command of Eq. 4.1.

    Written out as two products and a sum: as a ``dot`` (``M @ u``, ``einsum``) XLA's CPU back-end runs it as
    a batched 2×2 matrix product, a kernel of its own that costs more than the arithmetic around it. The
    sum rounds differently from the dot in the last bit.
    """
    return M[..., 0] * u[..., None, 0] + M[..., 1] * u[..., None, 1]


def update(ekm: IndirectEKM, v, c_p, eta, sigma, cfg: EKMConfig) -> IndirectEKM:
    """One self-organising step (ch. 4.3) from the executed command ``c_p`` and displacement ``v``:
    k = winner for v (step 4), then :func:`learn` with the neighbourhood G(k, ·) of width ``sigma``."""
    k = winner(ekm.w, v, cfg)
    return learn(ekm, v, c_p, eta, neighbourhood(cfg, k, sigma), cfg)


def learn(ekm: IndirectEKM, v, c_p, eta, g, cfg: EKMConfig) -> IndirectEKM:
    """Steps 5–6 of ch. 4.3 for neighbourhood weights ``g`` ``(N²,)``: Δw_i = η g_i (v - w_i) (Eq. 4.7);
    ΔM_i = η g_i (c_p - M_i ṽ) ṽᵀ (Eq. 4.9, gradient descent on Eq. 4.8), ṽ local to each neuron.
    (``benchmarks/perf/profile_training.py`` times it with stand-ins for the winner and G.)"""
    v_loc = model_input(v, ekm.w, cfg)  # (N², 2), or (2,) in the signed chart (the same for every neuron)
    err = c_p[None, :] - apply(ekm.M, v_loc)
    M = ekm.M + (eta * g)[:, None, None] * err[:, :, None] * v_loc[..., None, :]
    return IndirectEKM(w=update_inputs(ekm.w, v, g, eta, cfg), M=M)
