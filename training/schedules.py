"""Schedules of online training: learning rate η, neighbourhood width σ and exploration noise.

Each decays exponentially from its start to its end value over a fraction of the run and then stays
at the end value: x(t) = x0 (x1/x0)^min(t/(f·T), 1). The thesis gives only "a constant learning rate"
(Eq. 4.7) and no widths. The defaults were chosen on the full ch. 6.1 protocol (15×15, 5 trials ×
100k steps, 50 test targets, Webots slip noise, signed chart), against the alternatives below, by the
test's E, T(25) and capped targets:

- η 0.1 → 0.005 over the first 60 %: in map units |ũ|² ≤ 2, and η ≥ 0.5 makes Eq. 4.9 overshoot so that
  the lattice collapses; 0.1 learns early in the run, the decay then averages out the noise.
- σ 3 → 0.3 lattice units over 60 %: wide at first so the whole 15×15 sheet unfolds from the few
  displacements the untrained map produces, then nearly winner-take-all, so the outermost neurons are
  no longer pulled in by their neighbours: they reach almost a full step length ahead of the robot and
  behind it (Fig. 6.2: 0.16 m). Ending at σ = 1 or 0.5, the map reaches targets more slowly (a larger
  T(25)); at 0.2 about as fast, but with more capped targets. (In the polar chart σ = 1 left the neurons
  well short of a step length, behind most of all, and the map reached targets much more slowly.)
- exploration: Gaussian noise of constant std 0.2 c* (about 4 Khepera speed units) on each wheel's
  command, never decayed. The map learns the inverse of its own behaviour (Eq. 4.9 fits c_p to the
  displacement it produced), so the exploration is what shows it the rest of the motor space: with
  less noise (0.1 c*, 0.05 c*) the map reaches targets more slowly, at 0.05 c* less precisely too;
  decaying 0.5 c* → 0.05 c* over half the run is as good as the default but has one more parameter.
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
    sigma: Schedule = Schedule(3.0, 0.3, 0.6)  # G(k, i) width, in lattice units
    explore: Schedule = Schedule(0.2, 0.2, 1.0)  # std of command noise, as a fraction of c*: constant

    def to_dict(self) -> dict:
        return asdict(self)
