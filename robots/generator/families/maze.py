"""The ``maze`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import ARENA, T, edge_line, Layout, Retry, room_edges, wall, wall_with_door


def layout(rng, level: float) -> Layout:
    """A grid of rooms, 2x2 at level 0 to 4x4 at level 1, walled by known walls with doors 8-12 cm wide:
    a perfect maze (a random depth-first spanning tree of the rooms, so dead ends), plus up to two extra
    doors at low levels (loops), and half walls (stubs from a room's wall into it, more with the level).
    Start in one corner room, goal in the far one."""
    nx, ny = (int(np.clip(round(2 + 2 * level + rng.uniform(-0.5, 0.5)), 2, 4)) for _ in range(2))
    s = max(rng.uniform(0.3, 0.42), ARENA[0] / min(nx, ny))
    if max(nx, ny) * s > ARENA[1]:
        raise Retry
    edges = _spanning_tree(rng, nx, ny)
    others = [e for e in room_edges(nx, ny) if e not in edges]
    extra = min(len(others), int(round((1 - level) * rng.uniform(0.0, 2.4))))
    for k in rng.permutation(len(others))[:extra]:
        edges.add(others[k])
    doors = {e: (rng.uniform(0.3, 0.7) * s, rng.uniform(0.08, 0.12)) for e in sorted(edges)}
    walls = []
    for e in room_edges(nx, ny):
        a, b = edge_line(e, s)
        walls += wall_with_door(a, b, *doors[e]) if e in doors else [wall(a, b)]
    start_room, goal_room = (0, 0), (nx - 1, ny - 1)
    for room in ((i, j) for i in range(nx) for j in range(ny)):
        if room in (start_room, goal_room) or rng.uniform() > 0.15 + 0.5 * level:
            continue
        stub = _stub(rng, room, s, doors, nx, ny)
        if stub is not None:
            walls.append(stub)
    start = (np.array(start_room) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    goal = (np.array(goal_room) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    if math.dist(start, goal) < 0.5:
        raise Retry
    doc = {"size": [nx * s, ny * s], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)],
           "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


def _spanning_tree(rng, nx: int, ny: int) -> set:
    """A random depth-first spanning tree of the rooms (the recursive backtracker: long paths, dead ends)."""
    seen, stack, tree = {(0, 0)}, [(0, 0)], set()
    while stack:
        i, j = stack[-1]
        nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di < nx and 0 <= j + dj < ny and (i + di, j + dj) not in seen]
        if not nbrs:
            stack.pop()
            continue
        nxt = nbrs[int(rng.integers(len(nbrs)))]
        tree.add(tuple(sorted([(i, j), nxt])))
        seen.add(nxt)
        stack.append(nxt)
    return tree


def _stub(rng, room, s: float, doors: dict, nx: int, ny: int):
    """A half wall into ``room`` from the middle part of one of its sides, kept 10 cm from that side's door;
    None if the side drawn has no room for it."""
    i, j = room
    side = int(rng.integers(4))  # 0: left, 1: right, 2: bottom, 3: top
    corner = np.array([i * s, j * s])
    along, inward = (np.array([0.0, 1.0]), np.array([1.0, 0.0]))
    if side >= 2:
        along, inward = inward, along
    base = corner + (s * inward if side in (1, 3) else 0.0)
    direction = -inward if side in (1, 3) else inward
    nbr = {0: (i - 1, j), 1: (i + 1, j), 2: (i, j - 1), 3: (i, j + 1)}[side]
    at = rng.uniform(0.35, 0.65) * s
    door = doors.get(tuple(sorted([room, nbr])))
    if door is not None and abs(at - door[0]) < door[1] / 2 + T + 0.1:
        return None
    start = base + at * along
    return wall(start, start + rng.uniform(0.3, 0.5) * s * direction)


FAMILY = Family("maze", layout,
                "2x2 to 4x4 rooms of known walls: a perfect maze with 8-12 cm doors, dead ends, half walls")
