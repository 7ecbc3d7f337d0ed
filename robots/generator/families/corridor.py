"""The ``corridor`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import ARENA, T, Layout, Retry, unit, unit_between, wall
from robots.generator.shapes import offset_polyline, walls_apart


def layout(rng, level: float) -> Layout:
    """A corridor of known walls along a random polyline of 90 deg (or 45 and 90 deg) bends, from 1 turn
    (level 0) to 8 (level 1), staircases and zig-zags of short steps among them; 15 cm wide at level 0
    down to 8 cm at level 1; closed at both ends. It never touches itself: walls that share no end keep
    1 cm apart. The robot starts at one end facing along it; the goal is at the other end."""
    width = float(np.clip(0.15 - 0.07 * level + rng.uniform(-0.01, 0.01), 0.08, 0.15))
    turns = int(np.clip(round(1 + 7 * level + rng.uniform(-0.5, 0.5)), 1, 8))
    diagonal = bool(rng.uniform() < 0.5)
    off = 0.5 * (width + T)  # centre line to the walls' centre lines
    for _ in range(60):
        line = _corridor_line(rng, turns, diagonal, width)
        left, right = offset_polyline(line, off), offset_polyline(line, -off)
        walls = ([wall(a, b) for a, b in zip(left, left[1:])] + [wall(a, b) for a, b in zip(right, right[1:])]
                 + [wall(left[0], right[0]), wall(left[-1], right[-1])])
        if not walls_apart(walls, 0.01):
            continue
        ends = np.array(walls).reshape(-1, 2)
        lo, hi = ends.min(axis=0), ends.max(axis=0)
        margin = rng.uniform(0.04, 0.12, size=2)
        size = np.maximum(hi - lo + 2 * margin, ARENA[0])
        if np.any(size > ARENA[1]):
            continue
        shift = 0.5 * (size - (hi - lo)) - lo
        u0, u1 = unit_between(line[0], line[1]), unit_between(line[-2], line[-1])
        start, goal = line[0] + 0.06 * u0 + shift, line[-1] - 0.06 * u1 + shift
        if math.dist(start, goal) < 0.5:
            continue
        doc = {"size": list(size), "walls": [wall(w[:2] + shift, w[2:] + shift) for w in np.array(walls)],
               "start": [*start, math.atan2(u0[1], u0[0])], "goal": list(goal), "wall_thickness": T}
        return Layout(doc)
    raise Retry


def _corridor_line(rng, turns: int, diagonal: bool, width: float) -> np.ndarray:
    """The corridor's centre line: a first leg, then bends, staircases and zig-zags until ``turns`` turns,
    then a last leg. Headings are multiples of 45 deg (of 90 deg unless ``diagonal``)."""
    short = (width + 2 * T + 0.04, width + 2 * T + 0.09)
    heading = int(rng.integers(8)) if diagonal else 2 * int(rng.integers(4))  # in 45 deg units
    points = [np.zeros(2)]

    def leg(length):
        points.append(points[-1] + length * unit(heading * math.pi / 4))

    def toward_home() -> int:
        """+1 or -1: the turn that points back towards the middle of the line so far (keeps it compact)."""
        home = np.mean(points, axis=0) - points[-1]
        cross = math.cos(heading * math.pi / 4) * home[1] - math.sin(heading * math.pi / 4) * home[0]
        return 1 if cross >= 0 else -1

    leg(rng.uniform(0.25, 0.4))
    done = 0
    while done < turns:
        left = turns - done
        kind = rng.choice(["bend", "stairs", "uturn"], p=[0.5, 0.35, 0.15])
        sign = toward_home() if rng.uniform() < 0.6 else int(rng.choice([-1, 1]))
        step = int(rng.choice([1, 2])) if diagonal else 2
        if kind == "stairs" and left >= 2:
            m = min(left, int(rng.integers(2, 5)))
            for k in range(m):
                heading += sign * step * (-1) ** k
                leg(rng.uniform(*short) if k < m - 1 else rng.uniform(0.2, 0.4))
            done += m
        elif kind == "uturn" and left >= 2:
            heading += 2 * sign
            leg(rng.uniform(short[1], short[1] + 0.1))
            heading += 2 * sign
            leg(rng.uniform(0.25, 0.45))
            done += 2
        else:
            heading += sign * step
            leg(rng.uniform(0.2, 0.45))
            done += 1
    return np.array(points)


FAMILY = Family("corridor", layout,
                "a closed corridor 8-15 cm wide that bends and zig-zags, 1 to 8 turns, start at one end")
