"""Shapes of a world and the vectorised geometry on them (NumPy).

World files (``robots.worldfile``) describe obstacles with four shapes; this module holds them as frozen
dataclasses and answers the two questions everybody asks — how far is a point from a shape, and is it
inside — for many points at once. The planner rasterises padded obstacles with :func:`distance`; the
world-file checker uses it for "start inside an obstacle".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Point = tuple[float, float]


@dataclass(frozen=True)
class Box:
    """Rectangle of ``size`` = (width, height) centred on ``center``, rotated by ``angle`` (rad, ccw)."""

    center: Point
    size: Point
    angle: float = 0.0

    def vertices(self) -> np.ndarray:
        """Corners ``(4, 2)``, counter-clockwise."""
        w, h = 0.5 * self.size[0], 0.5 * self.size[1]
        local = np.array([[-w, -h], [w, -h], [w, h], [-w, h]])
        c, s = math.cos(self.angle), math.sin(self.angle)
        return local @ np.array([[c, s], [-s, c]]) + np.asarray(self.center)


@dataclass(frozen=True)
class Circle:
    """Disc of ``radius`` around ``center``."""

    center: Point
    radius: float


@dataclass(frozen=True)
class Polygon:
    """Simple polygon (convex or not) through ``points``, closed implicitly."""

    points: tuple[Point, ...]

    def vertices(self) -> np.ndarray:
        return np.asarray(self.points, dtype=float)


@dataclass(frozen=True)
class Segment:
    """Line segment from ``start`` to ``end`` (JSON keys ``from`` and ``to``); walls are segments."""

    start: Point
    end: Point


Shape = Box | Circle | Polygon | Segment


def translate(shape: Shape, offset) -> Shape:
    """``shape`` moved by ``offset`` = (dx, dy)."""
    dx, dy = float(offset[0]), float(offset[1])
    if isinstance(shape, Box):
        return Box((shape.center[0] + dx, shape.center[1] + dy), shape.size, shape.angle)
    if isinstance(shape, Circle):
        return Circle((shape.center[0] + dx, shape.center[1] + dy), shape.radius)
    if isinstance(shape, Polygon):
        return Polygon(tuple((x + dx, y + dy) for x, y in shape.points))
    return Segment((shape.start[0] + dx, shape.start[1] + dy), (shape.end[0] + dx, shape.end[1] + dy))


def bounds(shape: Shape) -> tuple[float, float, float, float]:
    """Axis-aligned bounding box ``(xmin, ymin, xmax, ymax)``."""
    if isinstance(shape, Circle):
        (x, y), r = shape.center, shape.radius
        return (x - r, y - r, x + r, y + r)
    pts = np.array([shape.start, shape.end]) if isinstance(shape, Segment) else shape.vertices()
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))


def segment_distance(points, a, b) -> np.ndarray:
    """Distance from ``points`` ``(..., 2)`` to the segment ``a``–``b``."""
    p = np.asarray(points, dtype=float)
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ab = b - a
    denom = float(ab @ ab)
    t = np.zeros(p.shape[:-1]) if denom == 0.0 else np.clip(((p - a) @ ab) / denom, 0.0, 1.0)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1)


def polygon_contains(points, vertices) -> np.ndarray:
    """Even-odd point-in-polygon test for ``points`` ``(..., 2)`` against ``vertices`` ``(m, 2)``."""
    p = np.asarray(points, dtype=float)
    x, y = p[..., 0], p[..., 1]
    inside = np.zeros(p.shape[:-1], dtype=bool)
    v = np.asarray(vertices, dtype=float)
    for (x0, y0), (x1, y1) in zip(v, np.roll(v, -1, axis=0)):
        crosses = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        inside ^= crosses & (x < x_cross)
    return inside


def signed_area(vertices) -> float:
    """Shoelace area of the polygon through ``vertices`` ``(m, 2)``: positive when counter-clockwise."""
    v = np.asarray(vertices, dtype=float)
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _orientation(p, q, r) -> float:
    """Twice the signed area of triangle ``p q r`` (> 0: left turn)."""
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])


def _segments_touch(a, b, c, d) -> bool:
    """Do the closed segments ``a``–``b`` and ``c``–``d`` share a point (crossing or touching)?"""
    o1, o2, o3, o4 = _orientation(a, b, c), _orientation(a, b, d), _orientation(c, d, a), _orientation(c, d, b)
    if ((o1 > 0) != (o2 > 0) and o1 != 0 and o2 != 0) and ((o3 > 0) != (o4 > 0) and o3 != 0 and o4 != 0):
        return True

    def on(p, q, r):  # r collinear with p-q and within its bounding box
        return min(p[0], q[0]) <= r[0] <= max(p[0], q[0]) and min(p[1], q[1]) <= r[1] <= max(p[1], q[1])

    return ((o1 == 0 and on(a, b, c)) or (o2 == 0 and on(a, b, d))
            or (o3 == 0 and on(c, d, a)) or (o4 == 0 and on(c, d, b)))


def polygon_self_intersection(vertices) -> tuple[int, int] | None:
    """First pair of edges ``(i, j)`` of the closed polygon that cross or touch, or None if it is simple.

    Edge ``i`` runs from vertex ``i`` to vertex ``i + 1``. Neighbouring edges may share only their common
    vertex; a repeated vertex, a spike folding back on itself or two crossing edges all make a polygon
    non-simple (it then has no well-defined inside for the physics and the planner).
    """
    v = [tuple(map(float, p)) for p in vertices]
    m = len(v)
    edges = [(v[i], v[(i + 1) % m]) for i in range(m)]
    for i, (a, b) in enumerate(edges):
        if a == b:
            return (i, i)
        for j in range(i + 1, m):
            c, d = edges[j]
            if j == i + 1 or (i == 0 and j == m - 1):  # neighbours: only the shared vertex may touch
                shared, other_a, other_b = (b, a, d) if j == i + 1 else (a, b, c)
                if _orientation(other_a, shared, other_b) == 0 and _dot_back(other_a, shared, other_b):
                    return (i, j)
                continue
            if _segments_touch(a, b, c, d):
                return (i, j)
    return None


def _dot_back(p, q, r) -> bool:
    """For collinear ``p``, ``q``, ``r``: does the path ``p → q → r`` fold back at ``q``?"""
    return (q[0] - p[0]) * (r[0] - q[0]) + (q[1] - p[1]) * (r[1] - q[1]) < 0


def distance(points, shape: Shape) -> np.ndarray:
    """Distance from ``points`` ``(..., 2)`` to ``shape``; 0 inside a solid shape."""
    p = np.asarray(points, dtype=float)
    if isinstance(shape, Circle):
        return np.maximum(np.linalg.norm(p - np.asarray(shape.center), axis=-1) - shape.radius, 0.0)
    if isinstance(shape, Segment):
        return segment_distance(p, shape.start, shape.end)
    v = shape.vertices()
    d = np.min([segment_distance(p, a, b) for a, b in zip(v, np.roll(v, -1, axis=0))], axis=0)
    return np.where(polygon_contains(p, v), 0.0, d)
