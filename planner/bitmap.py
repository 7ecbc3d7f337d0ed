"""The padded workspace as a bitmap of free (0) and occupied (−1) cells (thesis ch. 3.2.2, Fig. 3.2, 3.3a).

The planner works in the *workspace* (ch. 3.1): the obstacles of the a-priori map are padded with a
cushion of about the robot radius (Fig. 3.2b), so that the robot can be planned for as a point, and the
padded workspace is cut into a grid of square cells of side ``cell``.

Conventions (all planner modules):

* ``W`` is an integer array of shape ``(ny, nx)`` indexed ``W[iy, ix]``; cell ``(ix, iy)`` is the square
  ``[ix·cell, (ix+1)·cell] × [iy·cell, (iy+1)·cell]`` (origin bottom-left, y up, row 0 at the bottom);
* ``W == 0`` free, ``W == -1`` occupied (the labels of Fig. 3.3a);
* a decomposition (slippery cells, quadtree leaves, or the grid itself) is a ``labels`` array of the same
  shape with ``-1`` on occupied cells and ``1 … n`` on free ones.

**Conservative rasterisation.** "Free cells are entirely within the free space while occupied cells
intersect obstacles or the cushion" (ch. 3.2.2). A cell is free only if the *whole closed square* lies
inside the arena and at least the padding away from every obstacle: the exact Euclidean distance from
the square to each shape is computed (not a sample at the cell centre), so no point of a free cell is
ever closer than the padding to an obstacle. Exact ties (a cell edge at exactly the padding distance, as
when a doorway's edges fall on grid lines) count as free, up to a round-off tolerance of 1e-9 m: the
robot may touch, not cross, the cushion's edge.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

from ekm.errors import InputError
from robots.geometry import Box, Circle, Polygon, Segment, Shape, bounds, distance, polygon_contains, segment_distance

FREE, OCCUPIED = 0, -1

#: Round-off tolerance (m) of the free-space tests: a distance of ``padding - TIE`` still counts as free.
TIE = 1e-9

#: Largest bitmap the planner accepts (cells); a finer grid is almost surely a typo in the cell size.
MAX_CELLS = 1_000_000

#: A padded obstacle: the shape and how far the robot's centre must stay from it (m).
Padded = tuple[Shape, float]


def padded_obstacles(world, t: float = 0.0, padding: float = 0.025) -> tuple[Padded, ...]:
    """The planner's a-priori map at time ``t`` with its cushion (ch. 3.2.2, Fig. 3.2b).

    Walls — the arena's border and ``world.walls`` — count with half their thickness plus ``padding``;
    known obstacles and the shapes added by known events so far (``world.known_shapes(t)``) with
    ``padding``. Unforeseen and moving obstacles are not on the map.
    """
    half = 0.5 * world.wall_thickness
    walls = set(world.walls)
    border = tuple((s, padding + half) for s in world.border)
    return border + tuple((s, padding + half if s in walls else padding) for s in world.known_shapes(t))


def grid_shape(size, cell: float) -> tuple[int, int]:
    """``(ny, nx)`` of the grid of ``cell``-sized squares covering an arena of ``size`` = (w, h).

    Raises :class:`InputError` for a cell size that is not a positive finite number, or that would give
    more than :data:`MAX_CELLS` cells.
    """
    try:
        ok = math.isfinite(cell) and cell > 0
    except TypeError:
        ok = False
    if not ok:
        raise InputError(f"cell size: must be a positive number of metres, got {cell!r}")
    nx, ny = (max(1, math.ceil(s / cell - 1e-9)) for s in size)
    if nx * ny > MAX_CELLS:
        raise InputError(f"cell size: {cell} m cuts the {size[0]} x {size[1]} m arena into {nx} x {ny} cells, "
                         f"more than {MAX_CELLS:,}; use a larger cell")
    return ny, nx


def cell_squares(shape: tuple[int, int], cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Lower-left and upper-right corners ``(ny, nx, 2)`` of every cell of a grid of ``shape`` = (ny, nx)."""
    ny, nx = shape
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny))
    lo = np.stack([ix, iy], axis=-1) * cell
    return lo, lo + cell


def rasterise(obstacles: Sequence[Padded], size, cell: float) -> np.ndarray:
    """Bitmap ``W`` ``(ny, nx)`` of the padded workspace: 0 free, −1 occupied (Fig. 3.3a).

    ``obstacles`` are ``(shape, clearance)`` pairs (see :func:`padded_obstacles`); ``size`` = (w, h) of
    the arena. A cell is free iff its closed square lies inside the arena and
    ``distance(square, shape) >= clearance`` for every obstacle (module docstring).
    """
    key = (tuple(obstacles), tuple(size), cell)
    try:
        hash(key)
    except TypeError:  # an unhashable argument: rasterise without remembering
        return _rasterise(obstacles, size, cell)
    return _remembered_bitmap(*key)


@functools.lru_cache(maxsize=64)
def _remembered_bitmap(obstacles, size, cell: float) -> np.ndarray:
    """:func:`rasterise`, remembered per process (read-only): a replan after a known event rasterises the same
    map in every run of a world, and a comparison runs every architecture and trial in it."""
    W = _rasterise(obstacles, size, cell)
    W.flags.writeable = False
    return W


def _rasterise(obstacles, size, cell: float) -> np.ndarray:
    ny, nx = grid_shape(size, cell)
    lo, hi = cell_squares((ny, nx), cell)
    free = np.all(hi <= np.asarray(size, dtype=float) + TIE, axis=-1)
    for shape, clearance in obstacles:
        # Only the cells near the shape's box can be closer than its clearance (a square's distance to the shape
        # is at least its distance to the box): the window one cell beyond the box grown by the clearance. A wall
        # of a 4 m world touches a few hundred of its 40 000 cells.
        x0, y0, x1, y1 = bounds(shape)
        grow = clearance + cell
        i0, i1 = max(0, int((x0 - grow) // cell)), min(nx, int((x1 + grow) // cell) + 1)
        j0, j1 = max(0, int((y0 - grow) // cell)), min(ny, int((y1 + grow) // cell) + 1)
        if i0 >= i1 or j0 >= j1:
            continue
        window = (slice(j0, j1), slice(i0, i1))
        free[window] &= square_distance(lo[window], hi[window], shape) >= clearance - TIE
    return np.where(free, FREE, OCCUPIED).astype(np.int32)


def square_distance(lo, hi, shape: Shape) -> np.ndarray:
    """Exact distance between each axis-aligned square ``[lo, hi]`` ``(..., 2)`` and ``shape``; 0 if they meet.

    Circles: distance from the centre to the square minus the radius. Segments and polygons: zero if
    an edge crosses the square or (for solids) the square's centre lies inside; otherwise the smallest
    vertex-to-edge distance in either direction (for two disjoint polygonal sets the closest pair of
    points always has a vertex of one of them).
    """
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    if isinstance(shape, Circle):
        return np.maximum(_point_box_distance(np.asarray(shape.center, dtype=float), lo, hi) - shape.radius, 0.0)
    if isinstance(shape, Segment):
        vertices, solid = np.array([shape.start, shape.end], dtype=float), False
        edges = [(vertices[0], vertices[1])]
    elif isinstance(shape, (Box, Polygon)):
        vertices, solid = shape.vertices(), True
        edges = list(zip(vertices, np.roll(vertices, -1, axis=0)))
    else:
        raise TypeError(f"unknown shape {shape!r}")
    corners = np.stack([lo, np.stack([hi[..., 0], lo[..., 1]], -1), hi, np.stack([lo[..., 0], hi[..., 1]], -1)], -2)
    meets = polygon_contains(0.5 * (lo + hi), vertices) if solid else np.zeros(lo.shape[:-1], dtype=bool)
    d = np.full(lo.shape[:-1], np.inf)
    for a, b in edges:
        meets |= _segment_meets_box(a, b, lo, hi)
        d = np.minimum(d, segment_distance(corners, a, b).min(axis=-1))
    for v in vertices:
        d = np.minimum(d, _point_box_distance(v, lo, hi))
    return np.where(meets, 0.0, d)


def _point_box_distance(p, lo, hi) -> np.ndarray:
    """Distance from the point ``p`` ``(2,)`` to the boxes ``[lo, hi]`` ``(..., 2)``."""
    gap = np.maximum(np.maximum(lo - p, p - hi), 0.0)
    return np.hypot(gap[..., 0], gap[..., 1])


def _segment_meets_box(a, b, lo, hi) -> np.ndarray:
    """Whether the segment ``a``–``b`` meets the closed boxes ``[lo, hi]`` (Liang–Barsky clipping)."""
    t0 = np.zeros(lo.shape[:-1])
    t1 = np.ones(lo.shape[:-1])
    ok = np.ones(lo.shape[:-1], dtype=bool)
    for k in range(2):
        d = b[k] - a[k]
        if d == 0.0:
            ok &= (lo[..., k] <= a[k]) & (a[k] <= hi[..., k])
            continue
        with np.errstate(over="ignore"):  # a tiny d gives ±inf: the right limits for the clipping below
            ta, tb = (lo[..., k] - a[k]) / d, (hi[..., k] - a[k]) / d
        t0 = np.maximum(t0, np.minimum(ta, tb))
        t1 = np.minimum(t1, np.maximum(ta, tb))
    return ok & (t0 <= t1)


def clearance_ok(point, obstacles: Sequence[Padded], size) -> bool:
    """Whether ``point`` (x, y) lies in the free space: inside the arena and clear of every padded obstacle."""
    p = np.asarray(point, dtype=float)
    if not (0.0 <= p[0] <= size[0] and 0.0 <= p[1] <= size[1]):
        return False
    return all(float(distance(p, s)) >= c - TIE for s, c in obstacles)


def cell_index(point, cell: float) -> tuple[int, int]:
    """``(iy, ix)`` of the cell holding ``point`` (a point on a shared edge goes to the cell above/right)."""
    return int(math.floor(point[1] / cell)), int(math.floor(point[0] / cell))


def free_cell_at(W: np.ndarray, point, cell: float) -> tuple[int, int] | None:
    """The free cell ``(iy, ix)`` the robot at ``point`` is in, or ``None``.

    The cell holding ``point`` if it is free. Because free cells are conservative, a point in free space
    can lie in an occupied cell (next to a wall, or in a doorway narrower than two cells); then the
    nearest free cell among its 8 neighbours whose square is within ``cell`` of the point is used — the
    robot reaches it in a straight move of at most one cell.
    """
    ny, nx = W.shape
    iy, ix = cell_index(point, cell)
    candidates = []
    for jy in range(iy - 1, iy + 2):
        for jx in range(ix - 1, ix + 2):
            if 0 <= jy < ny and 0 <= jx < nx and W[jy, jx] == FREE:
                lo = np.array([jx, jy], dtype=float) * cell
                d = float(_point_box_distance(np.asarray(point, dtype=float), lo, lo + cell))
                candidates.append((d, (jy, jx) != (iy, ix), jy, jx))
    if not candidates:
        return None
    d, _, jy, jx = min(candidates)
    return (jy, jx) if d <= cell + TIE else None


def grid_cells(W: np.ndarray) -> np.ndarray:
    """The uniform-grid decomposition (a baseline of docs/design.md §4): every free bitmap cell is a cell of its own.

    Labels ``1 … n`` in row-major order (bottom row first), ``-1`` on occupied cells.
    """
    free = W == FREE
    labels = np.full(W.shape, OCCUPIED, dtype=np.int32)
    labels[free] = np.arange(1, int(free.sum()) + 1, dtype=np.int32)
    return labels
