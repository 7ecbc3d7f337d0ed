"""What a family lays out: a world-file document (:class:`Layout`) drawn from a random generator and a difficulty
level, made of the pieces below — walls, boxes and circles as world-file entries, rooms joined by doors — in a
frame of the family's own choosing (:mod:`robots.generator.build` turns, checks and keeps it).

Widths are physical gaps between surfaces: a wall is a segment grown by half its thickness (round caps), so a
door ``w`` wide between two wall segments has their ends ``w + T`` apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from robots.geometry import Box, Circle
from robots.params import KHEPERA

R = KHEPERA.radius  # m: the robot's radius
T = 0.01  # m: wall thickness of every generated world
ARENA = (0.8, 2.5)  # m: the smallest and largest side of an arena


class Retry(Exception):
    """The layout drawn does not fit (too big, overlapping, no route): try the next sub-seed. Its message, when
    given, says why in words a user can act on; :func:`robots.generator.build.build` reports it when no sub-seed
    fits."""


@dataclass
class Layout:
    """A builder's world-file document (without ``name``), the traps it placed, and for ``blocked`` the
    boxes that would close each door (``candidates``) and how many of them to close (``blockers``)."""

    doc: dict
    traps: int = 0
    blockers: int = 0
    candidates: list = field(default_factory=list)


# ------------------------------------------------------------------------------------------- documents

def wall(a, b) -> list:
    return [float(a[0]), float(a[1]), float(b[0]), float(b[1])]


def box(center, size, angle: float = 0.0) -> dict:
    doc = {"type": "box", "center": list(center), "size": list(size)}
    return {**doc, "angle": float(angle)} if angle else doc


def circle(center, radius: float) -> dict:
    return {"type": "circle", "center": list(center), "radius": float(radius)}


def as_shape(doc: dict):
    """A box or circle document as a :mod:`robots.geometry` shape."""
    if doc["type"] == "circle":
        return Circle(tuple(doc["center"]), doc["radius"])
    return Box(tuple(doc["center"]), tuple(doc["size"]), doc.get("angle", 0.0))


def unit(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


def unit_between(a, b) -> np.ndarray:
    v = np.asarray(b, float) - np.asarray(a, float)
    return v / np.hypot(*v)


def doc_bounds(s: dict) -> tuple:
    if s["type"] == "polygon":
        p = np.array(s["points"])
        return (*p.min(axis=0), *p.max(axis=0))
    v = as_shape(s).vertices()
    return (*v.min(axis=0), *v.max(axis=0))


def moved(s: dict, dx: float, dy: float) -> dict:
    if s["type"] == "polygon":
        return {**s, "points": [[x + dx, y + dy] for x, y in s["points"]]}
    return {**s, "center": [s["center"][0] + dx, s["center"][1] + dy]}


# ------------------------------------------------------------------------------------------- rooms and doors

def room_edges(nx: int, ny: int) -> list:
    """Pairs of neighbouring rooms ``((i, j), (i2, j2))``, each once, in a fixed order."""
    return ([((i, j), (i + 1, j)) for j in range(ny) for i in range(nx - 1)]
            + [((i, j), (i, j + 1)) for j in range(ny - 1) for i in range(nx)])


def edge_line(edge, s: float) -> tuple:
    """The wall between two neighbouring rooms, from its lower (left) end to its upper (right) end."""
    (i, j), (i2, j2) = edge
    if i2 > i:  # side by side: a vertical wall
        return np.array([i2 * s, j * s]), np.array([i2 * s, (j + 1) * s])
    return np.array([i * s, j2 * s]), np.array([(i + 1) * s, j2 * s])


def wall_with_door(a, b, at: float, width: float) -> list:
    """The wall ``a``-``b`` with a door ``width`` wide (between surfaces) centred ``at`` from ``a``."""
    u = unit_between(a, b)
    half = 0.5 * (width + T)
    return [wall(a, a + (at - half) * u), wall(a + (at + half) * u, b)]


# ------------------------------------------------------------------------------------------- routes

def route_of(doc: dict, known_only: bool = False):
    """The :func:`robots.generator.reach.reach` of a layout's document (every static shape, or ``known_only`` the
    planner's map): its ``route`` ``(k, 2)`` from start to goal; :class:`Retry` when there is none or the document
    does not parse."""
    from ekm.errors import InputError
    from robots.generator.reach import reach
    from robots.worldfile import parse_world

    try:
        world = parse_world({"name": "layout", **doc}, "layout")
    except InputError:
        raise Retry from None
    found = reach(world, known_only=known_only)
    if not found.solvable:
        raise Retry
    return world, found


def along(route, s: float) -> tuple[np.ndarray, np.ndarray]:
    """The point ``s`` metres along the polyline ``route`` ``(k, 2)`` and the unit direction of its leg there."""
    route = np.asarray(route, float)
    legs = np.diff(route, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    k = int(np.clip(np.searchsorted(np.cumsum(lengths), s), 0, len(legs) - 1))
    before = float(np.sum(lengths[:k]))
    u = legs[k] / max(lengths[k], 1e-12)
    return route[k] + (s - before) * u, u


def polyline_length(route) -> float:
    d = np.diff(np.asarray(route, float), axis=0)
    return float(np.hypot(d[:, 0], d[:, 1]).sum())
