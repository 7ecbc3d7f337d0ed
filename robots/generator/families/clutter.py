"""The ``clutter`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import T, as_shape, box, circle, doc_bounds, Layout, unit
from robots.generator.shapes import bounding_radius, shape_gap
from robots.geometry import Box, Circle


def layout(rng, level: float) -> Layout:
    """Unforeseen boxes (half of them turned, longer with the level) and circles strewn over an open arena
    larger with the level, covering 4 % of it at level 0 and 20-25 % at level 1 (as densely as the gaps
    allow: shapes are placed at random until the cover is reached or no more fit). Every gap between two
    shapes, or a shape and the border, is at least 15 cm at level 0 and 8 cm at level 1, or closed: at
    higher levels a few shapes overlap into clusters of up to three. Start at one side, goal at the other, both
    10 cm clear of everything."""
    w = rng.uniform(1.0, 1.4) + 0.6 * level
    h = rng.uniform(0.8, 1.1) + 0.4 * level
    min_gap = 0.08 + 0.07 * (1 - level)
    start = np.array([rng.uniform(0.1, 0.15), rng.uniform(0.15, h - 0.15)])
    goal = np.array([w - rng.uniform(0.1, 0.15), rng.uniform(0.15, h - 0.15)])
    target = (0.04 + 0.24 * level) * w * h
    shapes, docs, cluster, area = [], [], [], 0.0
    centres, radii = np.zeros((1500, 2)), np.zeros(1500)  # of the shapes placed, for a quick first test
    for _ in range(1500):
        if area >= target:
            break
        joined = None
        if shapes and rng.uniform() < 0.2 * level:  # overlap a shape already placed: a cluster
            joined = int(rng.integers(len(shapes)))
            if cluster.count(cluster[joined]) >= 3:
                continue
            centre = np.asarray(shapes[joined].center) + bounding_radius(shapes[joined]) * rng.uniform(0.5, 0.9) \
                * unit(rng.uniform(-math.pi, math.pi))
        else:
            centre = np.array([rng.uniform(0, w), rng.uniform(0, h)])
        if rng.uniform() < 0.55:
            turned = rng.uniform() < 0.5
            doc = box(centre, (rng.uniform(0.03, 0.12), rng.uniform(0.05, 0.18 + 0.17 * level)),
                       rng.uniform(0, math.pi) if turned else float(rng.choice([0.0, math.pi / 2])))
        else:
            doc = circle(centre, rng.uniform(0.02, 0.07))
        s = as_shape(doc)
        x0, y0, x1, y1 = doc_bounds(doc) if doc["type"] == "box" else (*(centre - s.radius), *(centre + s.radius))
        room = T / 2 + min_gap
        if x0 < room or y0 < room or x1 > w - room or y1 > h - room:
            continue
        if any(math.dist(centre, p) < bounding_radius(s) + 0.1 and shape_gap(s, Circle(tuple(p), 0.0)) < 0.1
               for p in (start, goal)):
            continue
        own = cluster[joined] if joined is not None else len(shapes)
        if joined is not None and shape_gap(s, shapes[joined]) > 0:
            continue
        if not _clear_of(s, shapes, centres[:len(shapes)], radii[:len(shapes)], cluster, own, min_gap):
            continue
        centres[len(shapes)], radii[len(shapes)] = s.center, bounding_radius(s)
        shapes.append(s)
        docs.append(doc)
        cluster.append(own)
        area += s.size[0] * s.size[1] if isinstance(s, Box) else math.pi * s.radius ** 2
    heading = math.atan2(*(goal - start)[::-1]) + rng.uniform(-0.5, 0.5)
    doc = {"size": [w, h], "unforeseen": docs, "start": [*start, heading], "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


def _clear_of(s, shapes, centres, radii, cluster, own: int, gap: float) -> bool:
    """Is ``s`` at least ``gap`` from every shape, or (of its own cluster ``own``) overlapping it? (``centres``
    and ``radii``: the shapes' bounding circles.)"""
    near = np.flatnonzero(np.hypot(*(centres - s.center).T) < radii + bounding_radius(s) + gap)
    gaps = ((shape_gap(s, shapes[k]), cluster[k] == own) for k in near)
    return all(g >= gap or (same and g <= 0.0) for g, same in gaps)


FAMILY = Family("clutter", layout, "unforeseen boxes and circles, denser with the difficulty, gaps down to 8 cm")
