"""The Kohonen part shared by every EKM: lattice, initial grid, winner search and input-weight update.

Neuron ``i`` sits at lattice position ``(i // N, i % N)``: the row indexes direction α, the column
distance d. Rows wrap around (direction is an angle), so the lattice is a cylinder.
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp

from ekm.angles import wrap_once
from ekm.config import EKMConfig


def initial_weights(cfg: EKMConfig):
    """Input weights w_i = (α_i, d_i) ``(N², 2)`` on a regular grid over the sensory space (ch. 6.1).

    α covers the circle in N equal sectors (centres), d covers [0, d_scale] in N equal steps.
    """
    n = cfg.neurons
    alpha = -jnp.pi + (jnp.arange(n) + 0.5) * (2.0 * jnp.pi / n)
    d = jnp.linspace(0.0, cfg.d_scale, n)
    aa, dd = jnp.meshgrid(alpha, d, indexing="ij")
    return jnp.stack([aa.ravel(), dd.ravel()], axis=-1).astype(jnp.float32)


def forward_prior(cfg: EKMConfig):
    """M_fwd ``(2, 2)``: the untrained map's reflex, c = M_fwd ũ — both wheels at the same speed, in
    proportion to the (chart's) distance, c* at one step length d_scale; no steering at all. In the
    signed chart (:mod:`ekm.charts`) that is straight ahead to targets ahead and straight back to
    targets behind; in the polar chart always straight ahead.

    Scaled by ``cfg.forward_init`` it is the initial M_i of every neuron (and, through c_i = M_fwd w̃_i,
    the initial outputs of a direct map). It only breaks the forward/backward symmetry of the task — a
    forward and a backward arc reach the same displacement — and gives the untrained robot no way to
    reach a target: it cannot turn. In the signed chart, whose coordinates already say which way to
    drive, it hardly matters (``forward_init`` = 0 learns about as well). In the polar chart a map with
    no preferred direction of travel (M_i = 0) settled on either, trial by trial, and learned worse. A
    prior that also steered (the linearised one-step inverse) was rejected: untrained, it already
    stopped within millimetres of the targets, so it would be a hand-made controller, not a start.
    """
    return jnp.asarray([[0.0, cfg.c_max], [0.0, cfg.c_max]], dtype=jnp.float32)


def neighbourhood(cfg: EKMConfig, k, sigma):
    """G(k, i) of Eq. 4.7: a Gaussian of the lattice distance from winner ``k``, width ``sigma`` (N²,)."""
    n = cfg.neurons
    r, c = jnp.divmod(jnp.arange(n * n), n)
    kr, kc = jnp.divmod(k, n)
    dr = jnp.abs(r - kr)
    dr = jnp.minimum(dr, n - dr)
    dc = c - kc
    return jnp.exp(-(dr * dr + dc * dc).astype(jnp.float32) / (2.0 * sigma * sigma))


def units(cfg: EKMConfig):
    """(π, d_scale): one map unit of each input component, in (rad, m) (see :class:`EKMConfig`)."""
    return jnp.asarray([jnp.pi, cfg.d_scale], dtype=jnp.float32)


def scaled(u, cfg: EKMConfig):
    """ũ = (α/π, d/d_scale): the input in the map's units (see :class:`EKMConfig`)."""
    return u / units(cfg)


def relative(u, w, cfg: EKMConfig):
    """u - w_i for every neuron ``(N², 2)`` in map units, with the angle difference wrapped. Both angles
    must lie in [-π, π] (:func:`wrap_once`); inputs and weights always do (map files are checked).

    Built from its two components: writing the wrapped angle into a copy of the difference (``.at[].set``)
    gives the same values through a scatter, a costly kernel of its own in every training step."""
    return jnp.stack(_relative_parts(u, w, cfg), axis=-1)


def _relative_parts(u, w, cfg: EKMConfig):
    """The two columns of :func:`relative`, (α - α_i)/π wrapped and (d - d_i)/d_scale, each ``(N²,)``."""
    unit = units(cfg)
    return wrap_once(u[..., 0] - w[..., 0]) / unit[0], (u[..., 1] - w[..., 1]) / unit[1]


def winner(w, u, cfg: EKMConfig):
    """Winning neuron k for input ``u`` = (α, d) (Eq. 4.2–4.4).

    Direction has priority: only the ``cfg.a_size`` neurons whose angles are closest to α (the set
    A(α) of Eq. 4.4) compete, and among them the weighted distance of Eq. 4.3,
    D² = γ_α (α - α_i)² + γ_d (d - d_i)², angles wrapped, is minimised.

    Searched nearest first: the neuron of least D² not yet ruled out wins if it is in A(α), i.e. fewer
    than ``a_size`` neurons lie strictly nearer in angle. If it is not, neither is any neuron at least as
    far in angle, and all of those are ruled out. The first one found in A(α) is
    :func:`winner_by_partition`'s winner, ties included, and in training it is usually the first one
    tried. Ordering all N² angles for A(α) instead (a ``TopK`` kernel) would be the costliest part of a
    training step.

    The loop ends: each pass rules out at least its candidate, and the neuron nearest in angle is in
    A(α). It also ends when every neuron left is at D² = ∞ (an overflowing input), where the definition's
    ``argmin`` gives the first neuron, as ``argmin`` of the all-∞ rest does; a NaN input ends it at once.
    """
    dalpha, dist2 = _distances(w, u, cfg)
    if cfg.a_size >= cfg.size:
        return jnp.argmin(dist2)
    return _nearest_in_a(dalpha, dist2, cfg.a_size)


def _distances(w, u, cfg: EKMConfig):
    """|α - α_i| and D² of Eq. 4.3 for every neuron, in map units, angles wrapped. From the components of
    :func:`relative`, not its stacked array: XLA would write that array out in a kernel of its own, twice
    a training step."""
    dalpha, dd = _relative_parts(u, w, cfg)
    return jnp.abs(dalpha), cfg.gamma_alpha * dalpha ** 2 + cfg.gamma_d * dd ** 2


@partial(jax.jit, static_argnames="a_size")
def _nearest_in_a(dalpha, dist2, a_size: int):
    """The search of :func:`winner` over |α - α_i| ``dalpha`` and D² ``dist2``. Jitted so that called
    eagerly its loop is traced once, not at every call (inside a jitted caller it is inlined)."""

    def found(k, d2):
        return (jnp.sum(dalpha < dalpha[k]) < a_size) | (d2 == jnp.inf)

    def rule_out(carry):  # every neuron at least as far in angle as k is out; those nearer were never out
        k, _ = carry
        left = jnp.where(dalpha >= dalpha[k], jnp.inf, dist2)
        k = jnp.argmin(left)
        return k, found(k, jnp.min(left))

    # D² of the candidate as the minimum, not gathered at its index: XLA takes it from the argmin's own
    # reduction, one kernel fewer per check
    k = jnp.argmin(dist2)
    return jax.lax.while_loop(lambda carry: ~carry[1], rule_out, (k, found(k, jnp.min(dist2))))[0]


def winner_by_partition(w, u, cfg: EKMConfig):
    """:func:`winner` by its definition: A(α) from a partition of all |α - α_i|, then the least D² in it.
    The reference the search is tested against; ties at A(α)'s boundary are kept (Eq. 4.4 holds for them)."""
    dalpha, dist2 = _distances(w, u, cfg)
    in_a = dalpha <= jnp.partition(dalpha, cfg.a_size - 1)[cfg.a_size - 1]
    return jnp.argmin(jnp.where(in_a, dist2, jnp.inf))


def update_inputs(w, v, g, eta, cfg: EKMConfig):
    """Eq. 4.7: Δw_i = η G(k, i) (v - w_i), angle difference wrapped, α_i re-wrapped."""
    diff = relative(v, w, cfg) * units(cfg)  # back to (rad, m)
    w = w + (eta * g)[:, None] * diff
    return jnp.stack([wrap_once(w[:, 0]), w[:, 1]], axis=-1)
