"""The ``niches`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import R, T, Layout, Retry, wall


def layout(rng, level: float) -> Layout:
    """Dead-end niches of known walls along the arena's long sides, two (level 0) to five (level 1), each
    ``g`` wide between its walls' surfaces -- 9-12 cm at level 0 down to 7-10 cm at level 1, under two robot
    diameters -- and 10-18 cm deep (12 cm deeper at level 1). The goal is at the back of one niche, 1.5 cm
    clear of its back wall; the start on the far side of the arena. The way into the niche is a passage barely
    wider than the robot with walls on both sides, closed at its end: a robot pushed off at its mouth must
    come back to it, and nothing past the goal draws it in."""
    n = int(np.clip(round(2 + 3 * level + rng.uniform(-0.5, 0.5)), 2, 5))
    w = rng.uniform(1.0, 1.3) + 0.4 * level
    h = rng.uniform(0.8, 1.0)
    slots = np.sort(rng.choice(np.arange(0.15, w - 0.2, 0.2), size=n, replace=False))
    sides = rng.integers(2, size=n)  # 0: the bottom side, 1: the top
    walls, niches = [], []
    for x0, side in zip(slots, sides):
        g = rng.uniform(0.09, 0.12) - 0.02 * level
        depth = rng.uniform(0.1, 0.18) + 0.12 * level
        x0 = float(x0 + rng.uniform(0.0, 0.05))
        x1 = x0 + g + T
        y0, y1 = (0.0, depth) if side == 0 else (h, h - depth)
        walls += [wall((x0, y0), (x0, y1)), wall((x1, y0), (x1, y1))]
        niches.append(((x0 + x1) / 2, side, depth))
    k = int(rng.integers(n))
    xg, side, depth = niches[k]
    back = T / 2 + R + 0.015
    goal = np.array([xg, back if side == 0 else h - back])
    far = [x for x in (0.1, w - 0.1) if abs(x - xg) > 0.5]
    if not far:
        raise Retry
    start = np.array([float(rng.choice(far)), h / 2 + rng.uniform(-0.1, 0.1)])
    doc = {"size": [w, h], "walls": walls, "start": [*start, rng.uniform(-np.pi, np.pi)], "goal": list(goal),
           "wall_thickness": T}
    return Layout(doc)


FAMILY = Family("niches", layout, "dead-end niches 7-12 cm wide along the walls, the goal at the back of one")
