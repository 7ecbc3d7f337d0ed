"""Declared movers' lanes: the ground a mover on a straight path sweeps, for the planner to keep off (issue 35).

The thesis's planner knows the a-priori map only; moving obstacles are left to the reactive layer (ch. 7).
A declared mover shuttling along a corridor, though, sweeps a lane the route can keep beside when the corridor
has room for both — and a reactive layer that meets the mover head-on in the corridor's middle has to go round
it where there is no room to (``docs/reproduce/every-kind.md``, the `movers` family). So, a labelled extension:
the lane of a mover on a :class:`~robots.worldfile.LinePath` is the convex hull of its shape at the two ends of
the path — exactly the ground the shape sweeps, for a convex shape moved without turning. :func:`planner.plan`
keeps the route off the lanes when that lengthens it by at most a factor and leaves the robot a margin beside every
lane (its ``lanes`` argument), and plans through them otherwise (a mover crossing the only doorway, or a corridor
with no room beside the mover). Movers on circles are left to the reactive layer: their lane is a ring round the
room.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from robots.geometry import Circle, Polygon, Segment, polygon_contains

#: Corners of the polygon that stands for a round mover (it circumscribes the circle).
ROUND = 16


def lanes(world, grow: float = 0.0) -> tuple[Polygon, ...]:
    """The lanes ``(Polygon, ...)`` of ``world``'s movers on straight paths: the convex hull of each mover's shape at
    the path's two ends (a circle by its circumscribed ``ROUND``-gon), grown by ``grow`` (m; each corner by the
    ``ROUND``-gon round a circle of that radius)."""
    return tuple(lane for _, lane in _movers_lanes(world, grow))


def _movers_lanes(world, grow: float = 0.0):
    """``(mover, lane)`` pairs of :func:`lanes`."""
    from robots.worldfile import LinePath

    out = []
    for mover in world.moving:
        if not isinstance(mover.path, LinePath):
            continue
        corners = _outline(mover.shape)
        if grow > 0:
            corners = (corners[:, None, :] + _ring(grow)[None]).reshape(-1, 2)
        ends = np.asarray([mover.path.start, mover.path.end], dtype=float)
        hull = convex_hull(np.vstack([corners + ends[0], corners + ends[1]]))
        if len(hull) >= 3:
            out.append((mover, Polygon(tuple((float(x), float(y)) for x, y in hull))))
    return out


def runs_along(world, points, angle: float = math.pi / 4, step: float = 0.005) -> tuple[bool, ...]:
    """For each lane of :func:`lanes` (same order), whether the route through ``points`` ``(n, 2)`` (start,
    checkpoints) runs along it: some stretch of a leg inside the lane within ``angle`` (rad) of the mover's path,
    sampled every ``step`` m. Where a route runs along a lane the robot meets the mover head-on; one that crosses it
    meets the mover once, from the side."""
    ends = np.asarray(points, dtype=float)
    out = []
    for mover, lane in _movers_lanes(world):
        path = np.subtract(mover.path.end, mover.path.start, dtype=float)
        along = False
        for a, b in zip(ends[:-1], ends[1:]):
            leg = b - a
            length = float(np.hypot(*leg))
            cos = abs(float(leg @ path)) / max(length * float(np.hypot(*path)), 1e-12)
            if length == 0 or cos < math.cos(angle):
                continue
            s = np.linspace(0.0, 1.0, max(2, int(math.ceil(length / step)) + 1))[:, None]
            if polygon_contains(a + s * leg, np.asarray(lane.vertices(), dtype=float)).any():
                along = True
                break
        out.append(along)
    return tuple(out)


def keeping_off(world, shapes) -> object:
    """``world`` with ``shapes`` among its known obstacles: the map a route that keeps off them is planned on."""
    return replace(world, obstacles=tuple(world.obstacles) + tuple(shapes))


def convex_hull(points) -> np.ndarray:
    """The convex hull ``(h, 2)`` of ``points`` ``(n, 2)``, counter-clockwise, without collinear points (Andrew's
    monotone chain)."""
    pts = sorted({(float(x), float(y)) for x, y in np.asarray(points, dtype=float)})
    if len(pts) < 3:
        return np.asarray(pts, dtype=float).reshape(-1, 2)

    def chain(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and _cross(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    return np.asarray(lower[:-1] + upper[:-1], dtype=float)


def _cross(o, a, b) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _ring(radius: float) -> np.ndarray:
    """``ROUND`` points ``(ROUND, 2)`` whose polygon circumscribes the circle of ``radius`` round the origin."""
    k = np.linspace(0.0, 2.0 * math.pi, ROUND, endpoint=False)
    return radius / math.cos(math.pi / ROUND) * np.stack([np.cos(k), np.sin(k)], axis=1)


def _outline(shape) -> np.ndarray:
    """Points ``(n, 2)`` whose convex hull holds ``shape``: a circle's circumscribed ``ROUND``-gon, a segment's ends,
    a box's or polygon's corners."""
    if isinstance(shape, Circle):
        return np.asarray(shape.center, dtype=float) + _ring(shape.radius)
    return np.asarray([shape.start, shape.end] if isinstance(shape, Segment) else shape.vertices(), dtype=float)
