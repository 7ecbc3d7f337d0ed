"""Direct-mapping EKM (thesis ch. 4.1): neuron i outputs a fixed wheel command c_i.

All inputs that make neuron k win get the same command c_p = c_k, so the motor space is sampled at
only N² points — the imprecision the indirect map (``ekm.indirect``) removes.
"""

from __future__ import annotations

from typing import NamedTuple

import jax

from ekm.config import EKMConfig
from ekm.charts import model_input
from ekm.kohonen import forward_prior, initial_weights, neighbourhood, update_inputs, winner


class DirectEKM(NamedTuple):
    """Map state pytree. ``w`` ``(N², 2)``: input weights (α_i rad, d_i m); ``c`` ``(N², 2)``: wheel commands (m/s)."""

    w: jax.Array
    c: jax.Array


def init(cfg: EKMConfig) -> DirectEKM:
    """An untrained map: input weights on the regular grid (ch. 6.1), outputs c_i = ``cfg.forward_init`` ·
    M_fwd w̃_i — the same start as the indirect map (:func:`ekm.kohonen.forward_prior`, w̃_i in
    ``cfg.chart`` coordinates): no steering, straight ahead (and, in the signed chart, straight back for
    the neurons behind)."""
    w = initial_weights(cfg)
    return DirectEKM(w=w, c=model_input(w, w, cfg) @ (cfg.forward_init * forward_prior(cfg)).T)


def control(ekm: DirectEKM, u, cfg: EKMConfig):
    """c_p = c_k for the winner k of ``u`` (ch. 4.1, Eq. 4.2–4.4); returns ``(c_p, k)``."""
    k = winner(ekm.w, u, cfg)
    return ekm.c[k], k


def update(ekm: DirectEKM, v, c_p, eta, sigma, cfg: EKMConfig) -> DirectEKM:
    """Self-organising step (ch. 4.3 with direct outputs): k = winner for v, Eq. 4.7 for w_i and
    Δc_i = η G(k,i)(c_p - c_i)."""
    k = winner(ekm.w, v, cfg)
    return learn(ekm, v, c_p, eta, neighbourhood(cfg, k, sigma), cfg)


def learn(ekm: DirectEKM, v, c_p, eta, g, cfg: EKMConfig) -> DirectEKM:
    """The update for neighbourhood weights ``g`` ``(N²,)``: Eq. 4.7 for w_i and Δc_i = η g_i (c_p - c_i)."""
    c = ekm.c + (eta * g)[:, None] * (c_p[None, :] - ekm.c)
    return DirectEKM(w=update_inputs(ekm.w, v, g, eta, cfg), c=c)
