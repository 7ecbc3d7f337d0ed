"""Learning that does not stop: how a trained map goes on learning (thesis ch. 4.3; docs/design.md §10).

"After the EKM has converged, the same online training can still be performed, and it mainly fine tunes
the indirect mapping" (ch. 4.3). The step is training's own — winner k for the displacement v the
executed command c produced, Δw_i = η G(k, i)(v − w_i) (Eq. 4.7), ΔM_i = η G(k, i)(c − M_i ṽ) ṽᵀ
(Eq. 4.9) — with rates that training's decaying schedules (``training.schedules``) cannot give a map
whose training has ended. :class:`Adaptation` says which:

- ``rule="constant"``: η = ``eta`` and σ = ``sigma`` always — by default the end of training's schedules,
  η = 0.005, σ = 0.3, the thesis's fine tuning as written;
- ``rule="error"`` (the default): the rates rise with the map's recent *prediction error* — how far the
  command the winner's model gives for the displacement made, M_k ṽ (direct: c_k), is from the command
  that made it, relative to c* (Eq. 4.8's error):

      ē ← ē + (e − ē) / memory,     s = clip((ē − floor) / (full − floor), 0, 1),
      η = eta + s (eta_max − eta),  σ = sigma + s (sigma_max − sigma).

  A map that predicts as well as the robot's noise allows learns as slowly as the final rule; a changed
  robot raises the error, and the wider, faster updates move the whole map towards the new robot
  (a wheel's gain changes every neuron's M alike) until the error falls back to the noise floor.

  A map learning while it drives (:func:`adapt_beyond_noise`, :mod:`robots.controllers.learner`) puts in
  place of ē the error beyond the robot's noise, √(max(ē² − n̄², 0)), n̄ estimated from consecutive ticks of
  one command (:class:`Noise`): a robot that slips more than the map's (the slippery floor: ē ≈ 0.05–0.07
  against the Khepera's 0.03, all of it slip) errs by its noise alone and learns at the resting rates, where
  a changed one (a weak motor: ē ≈ 0.08, n̄ ≈ 0.03) still learns fast.

The defaults were chosen on the arena fine-tuning of the named robots with tuning seeds
(``docs/reproduce/adaptation.md``, which gives the measurements and the command that makes them).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm import maps
from ekm.config import EKMConfig
from ekm.kohonen import neighbourhood, winner

RULES = ("error", "constant")  # the default first


@dataclass(frozen=True)
class Adaptation:
    """The rates of a map that keeps learning (see the module docstring). Rates 0 (``eta = eta_max = 0``)
    leave the map exactly as it is."""

    rule: str = "error"
    eta: float = 0.005  # η with a map that predicts as well as the noise allows (training's final η)
    sigma: float = 0.3  # σ likewise, lattice units (training's final σ)
    eta_max: float = 0.1  # rule=error: η at a prediction error of ``full`` and above
    sigma_max: float = 1.0  # rule=error: σ likewise
    floor: float = 0.04  # rule=error: relative prediction error ē at which the rates begin to rise
    full: float = 0.1  # rule=error: ē at which they reach eta_max, sigma_max
    memory: float = 50.0  # rule=error: learning steps over which ē averages the error

    def __post_init__(self):
        if self.rule not in RULES:
            raise ValueError(f"rule must be one of {', '.join(RULES)}, got {self.rule!r}")
        for name in ("eta", "eta_max", "floor"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        for name in ("sigma", "sigma_max", "memory"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not self.full > self.floor:
            raise ValueError(f"full must be > floor, got {self.full} <= {self.floor}")
        if self.memory < 1:
            raise ValueError(f"memory must be >= 1 step, got {self.memory}")

    @property
    def frozen(self) -> bool:
        """Whether every update is a zero one (rates 0): the map then never changes."""
        return self.eta == 0 and (self.rule == "constant" or self.eta_max == 0)

    def with_rate(self, eta: float) -> "Adaptation":
        """The same rule with its rates scaled so that the resting η is ``eta`` (0: frozen)."""
        if self.eta == 0:
            return replace(self, eta=eta, eta_max=eta if eta == 0 else self.eta_max)
        return replace(self, eta=eta, eta_max=self.eta_max * eta / self.eta)

    def to_dict(self) -> dict:
        return asdict(self)


class Trace(NamedTuple):
    """What a learning map remembers between updates: ē, the recent relative prediction error, and how many
    updates it has made."""

    error: jax.Array
    updates: jax.Array


def fresh_trace() -> Trace:
    return Trace(jnp.zeros((), jnp.float32), jnp.zeros((), jnp.int32))


class Noise(NamedTuple):
    """What a map learning while it drives remembers of the robot's noise (:func:`adapt_beyond_noise`): the
    running mean ``level`` of |e_t − e_{t−1}| / √2 over ``pairs`` of consecutive updates made with the same
    command, e being the relative prediction error vector (c − M_k ṽ) / c*; the ``last`` update's e; its
    ``updates``. A changed robot (a wheel's gain, its wheel base) errs alike on two consecutive ticks of the
    same command, and the difference cancels it; slip, drawn afresh every tick, does not cancel — the
    difference of two independent draws is √2 times one — so ``level`` estimates the part of the mean error
    that is noise."""

    level: jax.Array
    pairs: jax.Array
    last: jax.Array
    updates: jax.Array


def fresh_noise() -> Noise:
    return Noise(jnp.zeros((), jnp.float32), jnp.zeros((), jnp.int32), jnp.zeros(2, jnp.float32),
                 jnp.zeros((), jnp.int32))


def prediction(ekm, v, k, cfg: EKMConfig):
    """The command ``(2,)`` neuron ``k``'s model gives for displacement ``v``: M_k ṽ (Eq. 4.1; direct: c_k)."""
    from ekm import indirect
    from ekm.charts import model_input

    if isinstance(ekm, indirect.IndirectEKM):
        return indirect.apply(ekm.M[k], model_input(v, ekm.w[k], cfg))
    return ekm.c[k]


def rates(rule: Adaptation, error):
    """η and σ for a recent relative prediction error ``error`` (see the module docstring)."""
    if rule.rule == "constant":
        return jnp.float32(rule.eta), jnp.float32(rule.sigma)
    s = jnp.clip((error - rule.floor) / (rule.full - rule.floor), 0.0, 1.0)
    return rule.eta + s * (rule.eta_max - rule.eta), rule.sigma + s * (rule.sigma_max - rule.sigma)


def adapt(ekm, v, c, trace: Trace, rule: Adaptation, cfg: EKMConfig):
    """One update of a trained map from the executed command ``c`` ``(2,)`` (m/s) and the displacement ``v`` =
    (α, d) it produced (ch. 4.3 steps 4–6 with :func:`rates`); returns ``(ekm, trace)``."""
    k, ev = _error(ekm, v, c, cfg)
    trace = _traced(trace, jnp.linalg.norm(ev), rule)
    eta, sigma = rates(rule, recent_error(trace, rule))
    return maps.learn(ekm, v, c, eta, neighbourhood(cfg, k, sigma), cfg), trace


def adapt_beyond_noise(ekm, v, c, trace: Trace, noise: "Noise", paired, rule: Adaptation, cfg: EKMConfig):
    """:func:`adapt` with the rates driven by the error beyond the robot's noise (:func:`excess_error`);
    ``paired``: the update before this one was made on the tick just before, with the same command, so that
    the difference of their error vectors is noise (see :class:`Noise`). Returns ``(ekm, trace, noise)``."""
    k, ev = _error(ekm, v, c, cfg)
    trace = _traced(trace, jnp.linalg.norm(ev), rule)
    paired = jnp.asarray(paired) & (noise.updates > 0)
    d = jnp.linalg.norm(ev - noise.last) / jnp.sqrt(2.0)
    noise = Noise(jnp.where(paired, noise.level + (d - noise.level) / rule.memory, noise.level).astype(jnp.float32),
                  noise.pairs + paired.astype(jnp.int32), ev.astype(jnp.float32), noise.updates + 1)
    eta, sigma = rates(rule, excess_error(trace, noise, rule))
    return maps.learn(ekm, v, c, eta, neighbourhood(cfg, k, sigma), cfg), trace, noise


def _error(ekm, v, c, cfg: EKMConfig):
    """The winner ``k`` for ``v`` and the relative prediction error vector (c − M_k ṽ) / c* of its model."""
    k = winner(ekm.w, v, cfg)
    return k, (c - prediction(ekm, v, k, cfg)) / cfg.c_max


def _traced(trace: Trace, e, rule: Adaptation) -> Trace:
    return Trace((trace.error + (e - trace.error) / rule.memory).astype(jnp.float32), trace.updates + 1)


def excess_error(trace: Trace, noise: Noise, rule: Adaptation):
    """The recent error beyond the noise: √(max(ē² − n̄², 0)), ē of :func:`recent_error` and n̄ the running
    mean of :class:`Noise` (corrected alike for having started at 0); 0 before the first pair — the noise not
    yet measured, nothing is known to be beyond it (a single tick of the slippery floor errs by up to 0.12,
    which ē alone would take for a changed robot and learn at the highest rates). Were
    error and noise independent and their norms' means their root mean squares, this would be the error of
    the map's model alone (a bias b and noise n: E|b + n|² = |b|² + E|n|²); it is that approximately."""
    e = recent_error(trace, rule)
    weight = 1.0 - jnp.power(1.0 - 1.0 / rule.memory, noise.pairs.astype(jnp.float32))
    n = jnp.where(noise.pairs > 0, noise.level / jnp.maximum(weight, 1e-12), 0.0)
    return jnp.where(noise.pairs > 0, jnp.sqrt(jnp.maximum(e * e - n * n, 0.0)), 0.0)


def recent_error(trace: Trace, rule: Adaptation):
    """ē of the module docstring: the running mean of the relative prediction error, corrected for having
    started at 0 (over its first updates it is their mean, not a fraction of it)."""
    weight = 1.0 - jnp.power(1.0 - 1.0 / rule.memory, trace.updates.astype(jnp.float32))
    return jnp.where(trace.updates > 0, trace.error / jnp.maximum(weight, 1e-12), 0.0)
