"""The ``shapes`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import T, Layout, unit
from robots.generator.shapes import thick_polyline


def layout(rng, level: float) -> Layout:
    """Irregular, non-convex unforeseen shapes strewn over an open arena: L's, C's (open to any side), Z's and
    stars of five to seven points, 10-30 cm across, turned at random, three (level 0) to nine (level 1). Their
    bounding circles keep at least 15 cm apart at level 0 and 8 cm at level 1 (and from the border), so every
    gap between them is at least that; the concave sides are pockets the robot can drive into. Start at one
    side, goal at the other, both 12 cm clear of every bounding circle."""
    w = rng.uniform(1.2, 1.5) + 0.5 * level
    h = rng.uniform(0.8, 1.0) + 0.3 * level
    n = int(np.clip(round(3 + 6 * level + rng.uniform(-0.5, 0.5)), 3, 9))
    gap = 0.15 - 0.07 * level
    start = np.array([rng.uniform(0.08, 0.12), rng.uniform(0.2, h - 0.2)])
    goal = np.array([w - rng.uniform(0.08, 0.12), rng.uniform(0.2, h - 0.2)])
    placed, docs = [], []
    for _ in range(400):
        if len(docs) == n:
            break
        kind = str(rng.choice(["L", "C", "Z", "star"]))
        size = rng.uniform(0.1, 0.2) + 0.1 * level
        points, radius = _shape(rng, kind, size)
        c = np.array([rng.uniform(0, w), rng.uniform(0, h)])
        if not (T / 2 + gap + radius <= c[0] <= w - T / 2 - gap - radius
                and T / 2 + gap + radius <= c[1] <= h - T / 2 - gap - radius):
            continue
        if any(math.dist(c, e) < radius + 0.12 for e in (start, goal)):
            continue
        if any(math.dist(c, p) < radius + q + gap for p, q in placed):
            continue
        turn = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
        docs.append({"type": "polygon", "points": [list(c + rot @ p) for p in points]})
        placed.append((c, radius))
    heading = math.atan2(*(goal - start)[::-1]) + rng.uniform(-0.5, 0.5)
    return Layout({"size": [w, h], "unforeseen": docs, "start": [*start, heading], "goal": list(goal),
                   "wall_thickness": T})


def _shape(rng, kind: str, size: float) -> tuple[np.ndarray, float]:
    """A non-convex polygon ``(k, 2)`` about ``size`` across, centred on the origin, and its bounding radius."""
    t = rng.uniform(0.02, 0.035)  # arm thickness
    s = size / 2
    if kind == "star":
        k = int(rng.integers(5, 8))
        inner = rng.uniform(0.35, 0.55)
        angles = np.arange(2 * k) * math.pi / k
        radii = np.where(np.arange(2 * k) % 2 == 0, s, inner * s)
        points = np.array([r * unit(a) for r, a in zip(radii, angles)])
    else:
        line = {"L": [(-s, s), (-s, -s), (s, -s)], "C": [(s, s), (-s, s), (-s, -s), (s, -s)],
                "Z": [(-s, s), (s * 0.2, s), (-s * 0.2, -s), (s, -s)]}[kind]
        points = np.array(thick_polyline(line, t))
    points = points - points.mean(axis=0)
    return points, float(np.max(np.hypot(points[:, 0], points[:, 1])))


FAMILY = Family("shapes", layout, "unforeseen non-convex shapes (L, C, Z, stars) in an open arena, gaps down to 8 cm")
