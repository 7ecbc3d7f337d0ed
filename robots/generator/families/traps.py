"""The ``traps`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import ARENA, T, box, doc_bounds, Layout, moved, Retry
from robots.generator.shapes import thick_polyline


def layout(rng, level: float) -> Layout:
    """One trap (level 0) to three (level 1), unforeseen, one after another on the line from the start to
    the goal, each open towards the robot as it comes: a U (one polygon, as ``concave-obstacle``), a V,
    or a U or V made of two or three boxes whose gaps (1-2.5 cm) the robot cannot pass. Deeper with the
    level; at least 13 cm to pass round every trap on both sides; an open arena otherwise."""
    n = int(np.clip(round(1 + 2 * level + rng.uniform(-0.5, 0.5)), 1, 3))
    t = 0.02  # the traps' arm thickness (m)
    shapes, extents = [], []
    for kind in rng.choice(["U", "V", "boxes"], size=n):
        mouth = rng.uniform(0.14, 0.22) + 0.04 * level
        depth = rng.uniform(0.14, 0.2) + 0.12 * level
        made = _trap(rng, str(kind), mouth, depth, t)  # mouth at x = 0, centred on y = 0, open towards -x
        box = np.array([doc_bounds(s) for s in made])
        shapes.append(made)
        extents.append((box[:, 0].min(), box[:, 1].min(), box[:, 2].max(), box[:, 3].max()))
    half = max(max(-e[1], e[3]) for e in extents)
    height = max(ARENA[0], 2 * half + 2 * (0.14 + rng.uniform(0.0, 0.15)))
    x_start = rng.uniform(0.12, 0.18)
    x = x_start + rng.uniform(0.2, 0.3)
    placed_x = []
    for e in extents:
        placed_x.append(x)
        x += e[2] + rng.uniform(0.18, 0.28)
    x_goal = x - rng.uniform(0.0, 0.06)
    width = x_goal + rng.uniform(0.12, 0.2)
    if width > ARENA[1]:
        raise Retry
    width = max(width, ARENA[0])

    def y_room(e):  # centre lines that leave >= 13 cm between the trap and the border's surface
        return (0.135 + T / 2 - e[1], height - 0.135 - T / 2 - e[3])

    lo0, hi0 = y_room(extents[0])
    lo1, hi1 = y_room(extents[-1])
    y_start, y_goal = rng.uniform(lo0, hi0), rng.uniform(lo1, hi1)
    unforeseen = []
    for made, e, px in zip(shapes, extents, placed_x):
        lo, hi = y_room(e)
        s = (px - x_start) / (x_goal - x_start)
        yc = float(np.clip(y_start + s * (y_goal - y_start) + rng.uniform(-0.02, 0.02), lo, hi))
        unforeseen += [moved(sh, px, yc) for sh in made]
    doc = {"size": [width, height], "unforeseen": unforeseen, "start": [x_start, y_start, 0.0],
           "goal": [x_goal, y_goal], "wall_thickness": T}
    return Layout(doc, traps=n)


def _trap(rng, kind: str, mouth: float, depth: float, t: float) -> list:
    """One trap's shapes, its mouth (inner width ``mouth``) at x = 0 facing -x, ``depth`` deep inside."""
    h = mouth / 2 + t / 2  # the arms' centre lines
    if kind == "U":
        back = depth + t / 2
        return [{"type": "polygon", "points": thick_polyline([(0, h), (back, h), (back, -h), (0, -h)], t)}]
    if kind == "V":
        return [{"type": "polygon", "points": thick_polyline([(0, h), (depth, 0.0), (0, -h)], t)}]
    gap = rng.uniform(0.01, 0.025)  # between the boxes: too narrow for the robot
    if rng.uniform() < 0.5:  # a U of three boxes
        arm = depth - gap
        return [box((arm / 2, h), (arm, t)), box((arm / 2, -h), (arm, t)),
                box((depth + t / 2, 0.0), (t, mouth + 2 * t))]
    # a V of two boxes that almost meet at the apex
    length = math.hypot(depth, h)
    u = np.array([depth, -h]) / length  # along the upper arm, towards the apex
    cut = (gap / 2 + t * depth / (2 * length)) * length / h  # leaves the gap between the arms' inner corners
    tip, end = np.array([0.0, h]), np.array([depth, 0.0]) - cut * u
    angle = math.atan2(u[1], u[0])
    mid = (tip + end) / 2
    arm = float(np.hypot(*(end - tip)))
    return [box(mid, (arm, t), angle), box((mid[0], -mid[1]), (arm, t), -angle)]


FAMILY = Family("traps", layout,
                "one to three unforeseen U, V and box-made traps in an open arena, open towards the robot")
