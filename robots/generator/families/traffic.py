"""The ``traffic`` family of generated worlds: its :func:`layout` and :func:`overlay`, registered as :data:`FAMILY`.

The overlay lays movers across any world's route (``"large+traffic:7"``)."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import R, T, Layout, Retry, along, polyline_length, route_of, wall_with_door
from robots.geometry import segment_distance

TOP_SPEED = 0.16  # m/s: the Khepera's c*; the fastest movers are nearly as fast
RADII = (0.02, 0.035)  # m: the movers' radii are drawn between these
PASS = 0.04  # m to spare when the robot passes a mover at an end of its line


def layout(rng, level: float) -> Layout:
    """Two or three rooms in a row joined by doorways 20-30 cm wide (known walls), crossed by two (level 0) to
    five (level 1) movers (:func:`overlay`)."""
    rooms = int(np.clip(round(2 + level + rng.uniform(-0.5, 0.5)), 2, 3))
    widths = rng.uniform(0.5, 0.7, size=rooms)
    h = rng.uniform(0.8, 1.1)
    walls, x = [], 0.0
    for wd in widths[:-1]:
        x += float(wd)
        dw = rng.uniform(0.2, 0.3)
        walls += wall_with_door(np.array([x, 0.0]), np.array([x, h]), rng.uniform(0.15 + dw / 2, h - 0.15 - dw / 2),
                                dw)
    w = float(widths.sum())
    start = [rng.uniform(0.08, 0.15), rng.uniform(0.2, h - 0.2), rng.uniform(-0.5, 0.5)]
    goal = [w - rng.uniform(0.08, 0.15), rng.uniform(0.2, h - 0.2)]
    made = Layout({"size": [w, h], "walls": walls, "start": start, "goal": goal, "wall_thickness": T})
    return overlay(rng, level, made, n=int(np.clip(round(2 + 3 * level + rng.uniform(-0.5, 0.5)), 2, 5)))


def overlay(rng, level: float, made: Layout, n: int | None = None) -> Layout:
    """``made`` with ``n`` movers (default: one per 0.5 m of its route, 1 to 6, more with the level) crossing
    its route at places drawn along it: each a circle or box of 2-3.5 cm radius shuttling (bounce) on the line
    across the route, as far as the free space reaches on either side (up to 40 cm), at 3 cm/s up to 6-16 cm/s
    (faster with the level: the fastest nearly the robot's top speed). A line is kept only if the robot can pass
    the mover at either end of it (it spans the mover and the robot's diameter with 4 cm to spare), and its
    sweep stays clear of the start, the goal and the other movers."""
    doc = made.doc
    world, found = route_of(doc)
    route = found.route
    length = polyline_length(route)
    if n is None:
        n = int(np.clip(round(length / 0.5 * (0.5 + level)), 1, 6))
    moving = list(doc.get("moving", []))
    placed = 0
    for _ in range(40 * n):
        if placed == n or length < 0.5:
            break
        p, u = along(route, rng.uniform(0.2, length - 0.2))
        normal = np.array([-u[1], u[0]])
        rb = rng.uniform(*RADII)
        ends = [_free_end(world, p, sign * normal, rb) for sign in (1, -1)]
        a, b = ends
        if math.dist(a, b) < 2 * rb + 2 * R + PASS:
            continue
        if any(segment_distance(np.asarray(q, float), a, b) < R + rb + 0.05 for q in (doc["start"][:2], doc["goal"])):
            continue
        if any(_sweep_gap(a, b, m) < 2 * 0.035 + 0.01 for m in moving):
            continue
        speed = rng.uniform(0.03, 0.06 + 0.1 * level)
        shape = {"type": "circle", "radius": rb} if rng.uniform() < 0.5 else \
            {"type": "box", "size": [1.4 * rb, 1.4 * rb], "angle": rng.uniform(0, math.pi / 2)}
        ends = [list(a), list(b)][::int(rng.choice([-1, 1]))]
        moving.append({"shape": shape, "path": {"type": "line", "from": ends[0], "to": ends[1], "speed_mps": speed,
                                                "bounce": True}})
        placed += 1
    if placed < min(n, 1):
        least = 2 * RADII[0] + 2 * R + PASS
        raise Retry(f"traffic found no place on the route to lay a mover across it (one needs {least:.2f} m of free "
                    "space across the route at least, for the robot to pass it)")
    return Layout({**doc, "moving": moving}, made.traps, made.blockers, made.candidates)


def _free_end(world, p, direction, rb: float, reach: float = 0.4) -> np.ndarray:
    """The farthest point from ``p`` along ``direction`` (up to ``reach``) with the straight way to it clear for a
    disc of radius ``rb`` + 1 cm (1 cm steps)."""
    steps = np.arange(0.0, reach + 1e-9, 0.01)
    points = np.asarray(p) + steps[:, None] * direction
    inside = (points[:, 0] > 0) & (points[:, 1] > 0) & (points[:, 0] < world.size[0]) & (points[:, 1] < world.size[1])
    ok = inside & (world.clearance(points, include_moving=False) >= rb + 0.01)
    last = int(np.argmin(ok)) - 1 if not ok.all() else len(ok) - 1
    return points[max(last, 0)]


def _sweep_gap(a, b, mover: dict) -> float:
    """Distance between the sweep ``a``-``b`` and a mover's line path (its ends and the other's, both ways)."""
    from robots.generator.shapes import _segment_gap

    path = mover["path"]
    if path["type"] != "line":  # a circle path: its centre, less its radius
        return float(segment_distance(np.asarray(path["center"], float), a, b)) - path["radius"]
    c, d = np.asarray(path["from"], float), np.asarray(path["to"], float)
    return _segment_gap(np.asarray(a), np.asarray(b), c, d)


FAMILY = Family("traffic", layout, "rooms and doorways whose route 2 to 5 movers cross, up to nearly the robot's speed",
                overlay)
