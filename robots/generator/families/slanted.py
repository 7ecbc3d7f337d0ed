"""The ``slanted`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import T, Layout, Retry, box, wall
from robots.generator.shapes import _segment_gap


def layout(rng, level: float) -> Layout:
    """Known baffle walls slanted off the axes, alternately from the bottom and the top side, two (level 0)
    to five (level 1), 30-45 cm apart at their bases; each tip leans up to 25 cm sideways and leaves an opening
    of 20 cm (level 0) down to 12 cm (level 1) to the opposite side; neighbouring baffles keep 12 cm apart.
    At higher levels one or two unforeseen boxes, turned at any angle, stand between baffles. Start before the
    first baffle, goal after the last: the route zig-zags through every opening at the baffles' angles."""
    n = int(np.clip(round(2 + 3 * level + rng.uniform(-0.5, 0.5)), 2, 5))
    h = rng.uniform(0.8, 1.0)
    opening = 0.2 - 0.08 * level + rng.uniform(-0.02, 0.02)
    x, walls, bases = rng.uniform(0.3, 0.4), [], []
    first = int(rng.integers(2))
    for k in range(n):
        bottom = (k + first) % 2 == 0
        lean = rng.uniform(-0.25, 0.25)
        tip_y = h - opening - T / 2 if bottom else opening + T / 2
        a, b = np.array([x, 0.0 if bottom else h]), np.array([x + lean, tip_y])
        if walls and _segment_gap(np.array(walls[-1][:2]), np.array(walls[-1][2:]), a, b) < 0.12 + T:
            raise Retry
        if not 0.1 < b[0] < 3.0:
            raise Retry
        walls.append(wall(a, b))
        bases.append(x)
        x += rng.uniform(0.3, 0.45)
    w = max(x + rng.uniform(0.0, 0.1), max(max(wl[0], wl[2]) for wl in walls) + 0.3)
    unforeseen = []
    for k in range(int(np.clip(round(2 * level * rng.uniform()), 0, 2))):
        i = int(rng.integers(1, n))
        centre = ((bases[i - 1] + bases[i]) / 2, h / 2 + rng.uniform(-0.15, 0.15))
        unforeseen.append(box(centre, (rng.uniform(0.03, 0.05), rng.uniform(0.06, 0.12)), rng.uniform(0.2, 1.4)))
    start = [rng.uniform(0.08, 0.12), h / 2 + rng.uniform(-0.2, 0.2), rng.uniform(-math.pi, math.pi)]
    goal = [w - rng.uniform(0.08, 0.12), h / 2 + rng.uniform(-0.2, 0.2)]
    return Layout({"size": [w, h], "walls": walls, "unforeseen": unforeseen, "start": start, "goal": goal,
                   "wall_thickness": T})


FAMILY = Family("slanted", layout, "baffle walls slanted off the axes, openings down to 12 cm, turned boxes between")
