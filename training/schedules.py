"""Schedules of online training: learning rate η, neighbourhood width σ and exploration noise.

Each decays exponentially from its start to its end value over a fraction of the run and then stays
at the end value: x(t) = x0 (x1/x0)^min(t/(f·T), 1). The thesis gives only "a constant learning rate"
(Eq. 4.7) and no widths; these defaults were chosen by running the ch. 6.1 protocol (15×15, 4 trials ×
100k steps, 50 test targets; the tuning report on branch ``tune`` has the numbers):

- η 0.1 → 0.005 over the first 60 %: with |ũ|² ≤ 2, η ≥ 0.5 makes Eq. 4.9 overshoot and the map
  collapses; 0.1 learns within ~10k steps, the decay then averages out the 10 % actuator noise.
- σ 3 → 1 lattice units over 60 %: wide enough at first that the whole 15×15 sheet unfolds from the
  few displacements the untrained map produces; ending at 1 rather than 0.5 keeps neighbouring M_i
  alike, which made the per-trial spread of E three times smaller (E 2.4–3.2 mm vs 2.0–5.1 mm).
- exploration: constant 0.2 c* Gaussian noise on the command, never decayed. The map learns the inverse
  of its own behaviour (Eq. 4.9 fits c_p to the displacement it produced), so once exploration fades
  the only samples are those the current map asks for, and it drifts: with noise decaying to 0.05 c*
  E rose from ~5 mm at 20k steps to 15–65 mm at 100k (orbiting targets, backward collapse). A constant
  0.2 c* (≈ 4 speed units) keeps every part of the displacement space sampled; 0.1 c* gives a slightly
  better E but slower, more curved paths (T 17, D 0.31), 0.3 c* a worse E (5 mm).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import jax.numpy as jnp


@dataclass(frozen=True)
class Schedule:
    """Exponential decay from ``start`` to ``end`` over the first ``fraction`` of training."""

    start: float
    end: float
    fraction: float = 1.0

    def __post_init__(self):
        if not (self.start >= 0 and self.end >= 0 and 0 < self.fraction <= 1):
            raise ValueError(f"bad schedule {self}: need start, end >= 0 and 0 < fraction <= 1")

    def __call__(self, t, total):
        """Value at step ``t`` of ``total`` (works on traced JAX scalars)."""
        s = jnp.clip(t / (self.fraction * total), 0.0, 1.0)
        if self.end == 0.0 or self.start == 0.0:  # linear when one end is zero
            return self.start + (self.end - self.start) * s
        return self.start * (self.end / self.start) ** s


@dataclass(frozen=True)
class Schedules:
    """All training schedules. Defaults: see the module docstring and README."""

    eta: Schedule = Schedule(0.1, 0.005, 0.6)  # η of Eq. 4.7 and 4.9
    sigma: Schedule = Schedule(3.0, 1.0, 0.6)  # G(k, i) width, in lattice units
    explore: Schedule = Schedule(0.2, 0.2, 1.0)  # std of command noise, as a fraction of c*: constant

    def to_dict(self) -> dict:
        return asdict(self)
