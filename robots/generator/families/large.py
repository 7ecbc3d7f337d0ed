"""The ``large`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.families.maze import _spanning_tree
from robots.generator.layout import T, edge_line, Layout, Retry, room_edges, wall, wall_with_door


def layout(rng, level: float) -> Layout:
    """A building of many rooms, 3 m (level 0) to 6 m (level 1) on its long side: a grid of rooms 0.6-0.9 m
    wide, joined by doors 14-20 cm wide (known walls) along a random depth-first spanning tree, plus extra
    doors (a third of the other walls at level 0, fewer with the level), so routes are long and there are
    several. Start in a corner room, goal in the opposite one: routes of 3-10 m."""
    side = rng.uniform(0.6, 0.9)
    long_side = 3.0 + 3.0 * level + rng.uniform(-0.3, 0.3)
    nx = int(np.clip(round(long_side / side), 3, 8))
    ny = int(np.clip(round(nx * rng.uniform(0.5, 0.8)), 2, 6))
    if nx * side > 6.3:
        raise Retry
    edges = _spanning_tree(rng, nx, ny)
    others = [e for e in room_edges(nx, ny) if e not in edges]
    for k in rng.permutation(len(others))[:int(len(others) * (0.35 - 0.25 * level))]:
        edges.add(others[k])
    walls = []
    for e in room_edges(nx, ny):
        a, b = edge_line(e, side)
        walls += wall_with_door(a, b, rng.uniform(0.3, 0.7) * side, rng.uniform(0.14, 0.2)) if e in edges \
            else [wall(a, b)]
    start = (np.array([0, 0]) + 0.5) * side + rng.uniform(-0.1, 0.1, 2)
    goal = (np.array([nx - 1, ny - 1]) + 0.5) * side + rng.uniform(-0.1, 0.1, 2)
    doc = {"size": [nx * side, ny * side], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)],
           "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


FAMILY = Family("large", layout, "a building of many rooms 3-6 m long, doors 14-20 cm, routes of 3-10 m")
