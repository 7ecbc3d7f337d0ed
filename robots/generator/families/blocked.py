"""The ``blocked`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import (ARENA, T, box, edge_line, Layout, Retry, room_edges, unit_between, wall,
                                     wall_with_door)


def layout(rng, level: float) -> Layout:
    """Known walls that leave two or more routes: a wall across the arena with two or three doors, or a
    ring of 2x2, 3x2 or 3x3 rooms (the middle one closed) with the goal across the ring. Unforeseen boxes
    close the door on the shortest route of the known map, one (or, at higher levels on the wall with
    three doors, two: the second on the shortest route that is left) -- found by
    :func:`robots.generator.reach.reach` on the known map (:func:`robots.generator.build.close_doors`) -- so the
    robot must find the route that is left."""
    if rng.uniform() < 0.5:
        n_block = 2 if rng.uniform() < 0.8 * level else 1
        return _door_wall(rng, level, n_block)
    return _ring(rng, level)


def _door_wall(rng, level: float, n_block: int) -> Layout:
    w = rng.uniform(1.0, 1.3) + 0.6 * level
    h = rng.uniform(0.8, 1.0) + 0.5 * level
    xw = w * rng.uniform(0.4, 0.6)
    k = n_block + 1 + int(rng.uniform() < 0.3)
    dws = rng.uniform(0.1, 0.16, size=k)
    spacing, lo, hi = 0.25, 0.15, h - 0.15  # door centres: 25 cm apart at least, 15 cm from the border
    if hi - lo < (k - 1) * spacing:
        raise Retry
    ys = lo + np.sort(rng.uniform(0.0, hi - lo - (k - 1) * spacing, size=k)) + spacing * np.arange(k)
    walls, candidates, y = [], [], 0.0
    for yd, dw in zip(ys, dws):
        walls.append(wall((xw, y), (xw, yd - (dw + T) / 2)))
        candidates.append(_blocker(rng, (xw, yd), math.pi / 2, dw))
        y = yd + (dw + T) / 2
    walls.append(wall((xw, y), (xw, h)))
    start = np.array([rng.uniform(0.1, xw - 0.2), rng.uniform(0.15, h - 0.15)])
    goal = np.array([rng.uniform(xw + 0.2, w - 0.1), rng.uniform(0.15, h - 0.15)])
    if math.dist(start, goal) < 0.5:
        raise Retry
    doc = {"size": [w, h], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)], "goal": list(goal),
           "wall_thickness": T}
    return Layout(doc, blockers=n_block, candidates=candidates)


def _ring(rng, level: float) -> Layout:
    nx, ny = (2, 2) if level < 0.35 else [(3, 2), (2, 3), (3, 3)][int(rng.integers(3))]
    s = max(rng.uniform(0.35, 0.5), ARENA[0] / min(nx, ny))
    doc, candidates = ring_of_rooms(rng, nx, ny, s, (0.1, 0.16), 0.04)
    return Layout(doc, blockers=1, candidates=candidates)


def ring_of_rooms(rng, nx: int, ny: int, s: float, door: tuple[float, float], jitter: float) -> tuple[dict, list]:
    """``nx`` × ``ny`` rooms of side ``s`` (m) joined in a ring by doors ``door`` (m, a uniform range of widths) wide
    — two routes between any two rooms — with the start and the goal in rooms opposite on the ring, each within
    ``jitter`` m of its room's centre: the world's document, and for each door an unforeseen box that would shut
    it (``blocked`` and ``doors`` use them). Raises :class:`Retry` for a start and goal under 0.5 m apart."""
    ring = [(i, 0) for i in range(nx)] + [(nx - 1, j) for j in range(1, ny)] \
        + [(i, ny - 1) for i in range(nx - 2, -1, -1)] + [(0, j) for j in range(ny - 2, 0, -1)]
    linked = {tuple(sorted([a, b])) for a, b in zip(ring, ring[1:] + ring[:1])}
    walls, candidates = [], []
    for e in room_edges(nx, ny):
        a, b = edge_line(e, s)
        if e in linked:
            at, dw = rng.uniform(0.3, 0.7) * s, rng.uniform(*door)
            walls += wall_with_door(a, b, at, dw)
            u = unit_between(a, b)
            candidates.append(_blocker(rng, a + at * u, math.atan2(u[1], u[0]), dw))
        else:
            walls.append(wall(a, b))
    start = (np.array(ring[0]) + 0.5) * s + rng.uniform(-jitter, jitter, 2)
    goal = (np.array(ring[len(ring) // 2]) + 0.5) * s + rng.uniform(-jitter, jitter, 2)
    if math.dist(start, goal) < 0.5:
        raise Retry
    return {"size": [nx * s, ny * s], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)],
            "goal": list(goal), "wall_thickness": T}, candidates


def _blocker(rng, centre, angle: float, dw: float) -> dict:
    """A box that closes the door ``dw`` wide centred on ``centre`` in a wall along ``angle``: 1 cm over
    each of the door's wall ends, 3-5 cm thick."""
    return box(centre, (dw + T + 0.02, rng.uniform(0.03, 0.05)), angle)


FAMILY = Family("blocked", layout,
                "known walls with two or more routes; unforeseen boxes close the doors of the shortest")
