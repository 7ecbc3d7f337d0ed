"""Hyper-parameters of an EKM, in one frozen (hashable, jit-static) dataclass."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

CHARTS = ("signed", "polar")  # coordinates of the indirect maps' linear model (``ekm.charts``), default first


@dataclass(frozen=True)
class EKMConfig:
    """Shape and winner-search parameters of an N×N Extended Kohonen Map (thesis ch. 4; docs/design.md §3).

    The sensory input is u_p = (α, d): direction (rad, wrapped to (-π, π]) and distance (m) of the target
    in the robot's frame. Inside the map both components are measured in units that make them of order
    one — α in half-turns (α/π) and d in step lengths (d/d_scale, the furthest one 1.024 s step can move,
    ~0.16 m, thesis ch. 6.1): the winner distance (Eq. 4.3) acts on (α/π, d/d_scale), and so do the linear
    control model c_p = M ũ_p (Eq. 4.1/4.5) and its gradient step (Eq. 4.9), in the coordinates of
    ``chart`` (:mod:`ekm.charts`). This is a choice of units (the thesis gives none); it keeps Eq. 4.9
    stable for any η ≤ 1, since |ũ|² ≤ 2.
    """

    mapping: str = "indirect"  # "direct" (ch. 4.1) or "indirect" (ch. 4.2)
    neurons: int = 15  # N: the lattice is N × N (15 × 15 in the thesis, ch. 6.1)
    gamma_alpha: float = 1.0  # γ_α of Eq. 4.3 (on α/π)
    gamma_d: float = 1.0  # γ_d of Eq. 4.3 (on d / d_scale)
    priority: int | None = None  # |A(α)| of Eq. 4.4: neurons of most similar angle that compete (None: N)
    d_scale: float = 0.16  # m; also the top of the initial distance grid (ch. 6.1: 0.16 m per step)
    c_max: float = 0.16  # c*: largest realisable wheel command, m/s (Eq. 4.5)
    # Initial outputs as a fraction of the reflex M_fwd (``ekm.kohonen.forward_prior``): the untrained
    # robot drives straight (ahead, or back to targets behind in the signed chart), at half speed one step
    # length from the target, and cannot steer. 0 gives M_i = 0 (c_i = 0); in the polar chart that lets
    # training settle on backward motion at random.
    forward_init: float = 0.5
    # Coordinates of the target for the linear model c_p = M ũ_p (Eq. 4.1/4.5/4.9), ``ekm.charts``:
    # "signed" — the thesis's (α, d) ahead, measured from the robot's back with d negative behind, so the
    # map reverses straight onto targets behind; "polar" — (α, d) as the thesis writes it, which reaches
    # them by dithering and turning round, more slowly and less precisely.
    chart: str = "signed"

    def __post_init__(self):
        if self.mapping not in ("direct", "indirect"):
            raise ValueError(f"mapping must be 'direct' or 'indirect', got {self.mapping!r}")
        if self.chart not in CHARTS:
            raise ValueError(f"chart must be one of {', '.join(CHARTS)}, got {self.chart!r}")
        if self.neurons < 2:
            raise ValueError(f"neurons must be >= 2, got {self.neurons}")
        if self.priority is not None and not 1 <= self.priority <= self.neurons**2:
            raise ValueError(f"priority must be in 1..{self.neurons**2}, got {self.priority}")
        if not (math.isfinite(self.forward_init) and self.forward_init >= 0):
            raise ValueError(f"forward_init must be a finite number >= 0, got {self.forward_init}")
        for name in ("gamma_alpha", "gamma_d", "d_scale", "c_max"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a positive finite number, got {v}")

    @property
    def a_size(self) -> int:
        """|A(α)|: ``priority``, or one lattice row (N neurons) by default."""
        return self.neurons if self.priority is None else self.priority

    @property
    def size(self) -> int:
        """Number of neurons, N²."""
        return self.neurons * self.neurons

    def to_dict(self) -> dict:
        return asdict(self)
