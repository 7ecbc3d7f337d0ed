"""Schedules of online training: learning rate η, neighbourhood width σ and exploration noise.

Each decays exponentially from its start to its end value over a fraction of the run and then stays
at the end value: x(t) = x0 (x1/x0)^min(t/(f·T), 1). The thesis gives only "a constant learning rate"
(Eq. 4.7) and no widths. The defaults were chosen on the full ch. 6.1 protocol (15×15, 5 trials ×
100k steps, 50 test targets, Webots slip noise); with them the indirect map (signed chart,
``ekm.charts``) ends at E = 1.36, 1.18, 1.26 mm and T(25) = 7.85, 8.03, 7.90 steps/m for training seeds
0, 1, 2 (``python benchmarks/protocol_ch61.py --seed S``). Alternatives below: seed 0, signed chart, measured
before training's noise draws and arithmetic changed (docs/speed.md, fourth round), when the defaults gave
E = 1.29, 1.24, 1.36 mm and T(25) = 7.82, 7.88, 7.93.

- η 0.1 → 0.005 over the first 60 %: in map units |ũ|² ≤ 2, and η ≥ 0.5 makes Eq. 4.9 overshoot so that
  the lattice collapses; 0.1 learns within ~10k steps, the decay then averages out the noise.
- σ 3 → 0.3 lattice units over 60 %: wide at first so the whole 15×15 sheet unfolds from the few
  displacements the untrained map produces, then nearly winner-take-all, so the outermost neurons are
  no longer pulled in by their neighbours: they reach d = 0.157 m ahead of the robot and behind it
  (Fig. 6.2: 0.16 m). Ending at σ = 1 gives T(25) = 8.31 (E = 1.2 mm); at 0.5 T(25) = 7.97; at 0.2
  T(25) = 7.92 but 142 capped targets instead of 114. (In the polar chart σ = 1 left the neurons at
  0.13 m ahead and 0.07 m behind, and T(25) at 12.4–13.0.)
- exploration: Gaussian noise of constant std 0.2 c* (about 4 Khepera speed units) on each wheel's
  command, never decayed. The map learns the inverse of its own behaviour (Eq. 4.9 fits c_p to the
  displacement it produced), so the exploration is what shows it the rest of the motor space:
  0.1 c* gives T(25) = 8.05, 0.05 c* T(25) = 10.6, D(25) = 0.16 and E = 2.5 mm; decaying 0.5 c* → 0.05 c*
  over half the run is as good as the default (E = 1.3 mm, T(25) = 7.72) but has one more parameter.
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
