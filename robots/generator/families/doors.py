"""The ``doors`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.families.blocked import _blocker, ring_of_rooms
from robots.generator.layout import T, Layout, Retry, along, as_shape, polyline_length, route_of, wall
from robots.generator.shapes import route_passes

TOP_SPEED = 0.16  # m/s: the Khepera's c*; a door shuts before the fastest robot could reach it


def layout(rng, level: float) -> Layout:
    """A wall across the arena with two or three doors 12-18 cm wide, or a ring of 2x2 (level < 0.5) or 3x2
    rooms, all known walls; during the run the door on the shortest route of the known map shuts: an
    unforeseen event adds the box that closes it at a time before the fastest robot could get there (30-70 %
    of the route's length to the door at 0.16 m/s), so the robot learns of it on its way. Another route stays
    open (the world is checked with the door shut)."""
    doc, candidates = _door_wall(rng, level) if rng.uniform() < 0.5 else _ring(rng, level)
    _, found = route_of(doc, known_only=True)
    route = found.route
    for c in candidates:
        if route_passes(route, as_shape(c)):
            centre = np.asarray(c["center"], float)
            to_door = _distance_along(route, centre)
            if to_door < 0.3:
                raise Retry
            at = round(rng.uniform(0.3, 0.7) * to_door / TOP_SPEED, 2)
            return Layout({**doc, "events": [{"at_s": at, "add": [c], "known": False}]})
    raise Retry


def _distance_along(route, point) -> float:
    """How far along the polyline ``route`` its nearest point to ``point`` is (m)."""
    length = polyline_length(route)
    s = np.linspace(0.0, length, max(2, int(length / 0.005)))
    d = [math.dist(along(route, x)[0], point) for x in s]
    return float(s[int(np.argmin(d))])


def _door_wall(rng, level: float):
    w, h = rng.uniform(1.0, 1.4) + 0.4 * level, rng.uniform(0.8, 1.1)
    xw = w * rng.uniform(0.4, 0.6)
    k = 2 + int(rng.uniform() < 0.5 * level)
    ys = np.sort(rng.uniform(0.15, h - 0.15, size=k))
    if np.any(np.diff(ys) < 0.3):
        raise Retry
    walls, candidates, y = [], [], 0.0
    for yd in ys:
        dw = rng.uniform(0.12, 0.18)
        walls.append(wall((xw, y), (xw, yd - (dw + T) / 2)))
        candidates.append(_blocker(rng, (xw, yd), math.pi / 2, dw))
        y = yd + (dw + T) / 2
    walls.append(wall((xw, y), (xw, h)))
    start = [rng.uniform(0.1, xw - 0.3), rng.uniform(0.15, h - 0.15), rng.uniform(-math.pi, math.pi)]
    goal = [rng.uniform(xw + 0.3, w - 0.1), rng.uniform(0.15, h - 0.15)]
    return {"size": [w, h], "walls": walls, "start": start, "goal": goal, "wall_thickness": T}, candidates


def _ring(rng, level: float):
    nx, ny = (2, 2) if level < 0.5 else (3, 2)
    return ring_of_rooms(rng, nx, ny, rng.uniform(0.4, 0.55), (0.12, 0.18), 0.05)


FAMILY = Family("doors", layout, "rooms whose door on the shortest route shuts during the run, another route open")
