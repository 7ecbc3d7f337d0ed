"""The geometry a family checks its layout with: offset and thick polylines, the gaps between walls and between
shapes, and whether a route passes a shape (metres)."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.layout import T
from robots.geometry import Circle, distance, segment_distance


def offset_polyline(points, d: float) -> np.ndarray:
    """The polyline ``points`` ``(k, 2)`` moved ``d`` to its left (mitred corners: the distance between the
    two lines is ``d`` along every leg)."""
    p = np.asarray(points, dtype=float)
    u = np.diff(p, axis=0)
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    inner = [p[k] + d * (n[k - 1] + n[k]) / (1.0 + n[k - 1] @ n[k]) for k in range(1, len(p) - 1)]
    return np.array([p[0] + d * n[0], *inner, p[-1] + d * n[-1]])


def thick_polyline(points, thickness: float) -> list:
    """The polygon ``thickness`` wide around the polyline ``points`` (square ends, mitred corners)."""
    left = offset_polyline(points, thickness / 2)
    right = offset_polyline(points, -thickness / 2)
    return [list(p) for p in [*left, *right[::-1]]]


def _segment_gap(a, b, c, d) -> float:
    """Distance between the segments ``a``-``b`` and ``c``-``d`` (0 when they cross)."""
    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
        return 0.0
    return float(min(segment_distance(a, c, d), segment_distance(b, c, d),
                     segment_distance(c, a, b), segment_distance(d, a, b)))


def walls_apart(walls, gap: float) -> bool:
    """Do wall segments ``[x0, y0, x1, y1]`` that share no end keep at least ``gap`` between their surfaces?"""
    segs = [(np.array(w[:2]), np.array(w[2:])) for w in walls]
    for i, (a, b) in enumerate(segs):
        for c, d in segs[i + 1:]:
            if min(np.hypot(*(p - q)) for p in (a, b) for q in (c, d)) < 1e-9:
                continue
            if _segment_gap(a, b, c, d) < T + gap:
                return False
    return True


def shape_gap(a, b) -> float:
    """The gap between two box or circle shapes (<= 0 when they touch or overlap)."""
    if isinstance(a, Circle) and isinstance(b, Circle):
        return math.dist(a.center, b.center) - a.radius - b.radius
    if isinstance(a, Circle) or isinstance(b, Circle):
        circle, box = (a, b) if isinstance(a, Circle) else (b, a)
        p, v = np.asarray(circle.center, dtype=float)[None], box.vertices()
        inside = bool(_convex_contains(p, v)[0])
        return (0.0 if inside else float(_to_edges(p, v)[0])) - circle.radius
    va, vb = a.vertices(), b.vertices()
    if _convex_contains(va, vb).any() or _convex_contains(vb, va).any() or _edges_cross(va, vb):
        return 0.0
    return float(min(_to_edges(va, vb).min(), _to_edges(vb, va).min()))


def _to_edges(p, v) -> np.ndarray:
    """Distance from each point ``p`` ``(n, 2)`` to the nearest edge of the closed polygon ``v`` ``(m, 2)``."""
    a, ab = v, np.roll(v, -1, axis=0) - v
    ap = p[:, None, :] - a[None]
    t = np.clip(np.einsum("nmk,mk->nm", ap, ab) / np.einsum("mk,mk->m", ab, ab), 0.0, 1.0)
    d = ap - t[..., None] * ab
    return np.sqrt(np.einsum("nmk,nmk->nm", d, d)).min(axis=1)


def _convex_contains(p, v) -> np.ndarray:
    """Which points ``p`` ``(n, 2)`` lie inside the convex polygon ``v`` ``(m, 2)`` (counter-clockwise)."""
    ab = np.roll(v, -1, axis=0) - v
    ap = p[:, None, :] - v[None]
    return np.all(ab[None, :, 0] * ap[..., 1] - ab[None, :, 1] * ap[..., 0] > 0, axis=1)


def _edges_cross(va, vb) -> bool:
    """Does an edge of the closed polygon ``va`` cross one of ``vb``?"""
    a, b = va[:, None], np.roll(va, -1, axis=0)[:, None]
    c, d = vb[None], np.roll(vb, -1, axis=0)[None]

    def side(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    return bool(np.any((side(a, b, c) * side(a, b, d) < 0) & (side(c, d, a) * side(c, d, b) < 0)))


def bounding_radius(s) -> float:
    return s.radius if isinstance(s, Circle) else 0.5 * math.hypot(*s.size)


def route_passes(route, shape, within: float = 0.0) -> bool:
    """Does the polyline ``route`` ``(k, 2)`` come within ``within`` (m) of ``shape`` (or through it)?"""
    route = np.asarray(route, dtype=float)
    for a, b in zip(route, route[1:]):
        n = max(2, math.ceil(math.dist(a, b) / 0.005) + 1)
        samples = a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)
        if np.min(distance(samples, shape)) <= within:
            return True
    return False
