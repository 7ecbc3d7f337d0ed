"""Schedules of online training: learning rate η, neighbourhood width σ and exploration noise.

Each decays exponentially from its start to its end value over a fraction of the run and then stays
at the end value: x(t) = x0 (x1/x0)^min(t/(f·T), 1). The thesis gives only "a constant learning rate"
(Eq. 4.7) and no widths; these defaults were chosen by running the ch. 6.1 protocol (README).
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
    sigma: Schedule = Schedule(3.0, 0.5, 0.6)  # G(k, i) width, in lattice units
    explore: Schedule = Schedule(0.5, 0.05, 0.5)  # std of command noise, as a fraction of c*

    def to_dict(self) -> dict:
        return asdict(self)
