"""Can the robot get from start to goal, and how hard is the way? A grid search of its own.

This is the generator's check and measure of every world it makes, independent of the slippery-cell
planner (``planner/``), so that a planner bug cannot pass off an unsolvable world as solvable.

The grid covers the arena at ``step`` (1 cm by default); each node holds its exact clearance, the distance
from the node to the nearest surface, from :meth:`robots.worldfile.World.clearance` (walls with half their
thickness, known and unforeseen obstacles and every event's shapes; moving obstacles are left out). A node
is *usable* when the robot's disc fits there with room to move: clearance >= radius + half a grid diagonal
+ ``MARGIN``. The clearance field is 1-Lipschitz, so the straight move between two usable neighbours
keeps the robot ``MARGIN`` clear of everything; a route of usable nodes is a route the robot can drive.
Start and goal join the grid at their nearest usable node (within one and a half steps).

The measures (all lengths in metres):

- ``narrowest_passage_m``: the physical width of the narrowest gap the best route passes: 2 x the largest,
  over all routes, of the route's smallest centre clearance (the widest-path bottleneck). Nodes within
  ``END_ZONE`` of the start or the goal do not count (a robot parked near a wall is no passage). The
  grid's nodes need not sit on a gap's centre line, so the bottleneck found on the grid (the widest path)
  is refined at its narrowest spots on a 1 mm lattice of exact clearances: the value is then that of the
  gap's cross-section, to about a millimetre for a gap crossed square-on, and never more than half a grid
  diagonal from the grid's.
- ``route_length_m``: the shortest route, any-angle: the 8-connected grid path (A*) pulled straight
  wherever the line of sight keeps the robot clear (checked on samples against a lower bound of the
  clearance field), from the start to the goal point. It is a close upper bound of the true shortest
  route of a disc of the robot's radius.
- ``straight_m``: start to goal as the crow flies; ``route_ratio``: route / straight (>= 1).
- ``turns``: the smoothed route's direction changes of more than 30 deg; vertices closer together than
  ``TURN_MERGE`` count as one turn, by their net change (a round corner cut by several short segments is
  one turn).
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field

import numpy as np

from ekm.angles import wrap
from robots.geometry import distance
from robots.params import KHEPERA

STEP = 0.01  # m: grid spacing (at most; the arena's sides are divided evenly)
MARGIN = 0.002  # m: what a usable node keeps beyond the robot's radius and half a grid diagonal
END_ZONE = 0.1  # m: nodes this close to the start or the goal are no passage for narrowest_passage_m
TURN_DEG = 30.0  # a turn changes direction by more than this
TURN_MERGE = 0.08  # m: vertices of the smoothed route closer than this make one turn (a cut corner)
SMOOTH_WINDOW = 16  # string pulling looks this many corners of the grid path ahead
REFINE = 4  # narrowest spots of the widest path whose bottleneck is refined off the grid


@dataclass(frozen=True, eq=False)
class Reach:
    """What :func:`reach` found: ``solvable``, and for a solvable world the measures (module docstring)
    and ``route``, the smoothed route ``(k, 2)`` in metres from the start point to the goal point."""

    solvable: bool
    straight_m: float
    narrowest_passage_m: float = math.nan
    route: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    turns: int = 0

    @property
    def route_length_m(self) -> float:
        """Length of :attr:`route` (nan when unsolvable)."""
        if len(self.route) < 2:
            return math.nan
        return float(np.sum(np.hypot(*np.diff(self.route, axis=0).T)))

    @property
    def route_ratio(self) -> float:
        """Route length over the straight start-goal distance (>= 1)."""
        return max(1.0, self.route_length_m / self.straight_m) if self.straight_m > 0 else math.nan

    def measures(self) -> dict:
        """The measures a world file's ``difficulty`` holds (rounded to 0.1 mm), for a solvable world."""
        return {"narrowest_passage_m": round(self.narrowest_passage_m, 4),
                "route_length_m": round(self.route_length_m, 4), "straight_m": round(self.straight_m, 4),
                "route_ratio": round(self.route_ratio, 4), "turns": int(self.turns)}


@dataclass(frozen=True, eq=False)
class Grid:
    """Node ``(j, i)`` sits at ``(x0 + i hx, y0 + j hy)``; ``clearance`` ``(ny, nx)`` in metres."""

    x0: float
    y0: float
    hx: float
    hy: float
    clearance: np.ndarray

    def node(self, p) -> tuple[int, int]:
        """The ``(j, i)`` of the node nearest the point ``p``."""
        ny, nx = self.clearance.shape
        i = int(np.clip(round((p[0] - self.x0) / self.hx), 0, nx - 1))
        j = int(np.clip(round((p[1] - self.y0) / self.hy), 0, ny - 1))
        return j, i

    def point(self, j: int, i: int) -> tuple[float, float]:
        return (self.x0 + i * self.hx, self.y0 + j * self.hy)

    def clearance_bound(self, points) -> np.ndarray:
        """A lower bound of the clearance at ``points`` ``(n, 2)``: the best of the four surrounding nodes'
        clearance less the distance to them (the field is 1-Lipschitz)."""
        ny, nx = self.clearance.shape
        fx = (points[:, 0] - self.x0) / self.hx
        fy = (points[:, 1] - self.y0) / self.hy
        i0 = np.clip(np.floor(fx).astype(int), 0, nx - 2)
        j0 = np.clip(np.floor(fy).astype(int), 0, ny - 2)
        best = np.full(len(points), -np.inf)
        for di in (0, 1):
            for dj in (0, 1):
                i, j = i0 + di, j0 + dj
                d = np.hypot(points[:, 0] - (self.x0 + i * self.hx), points[:, 1] - (self.y0 + j * self.hy))
                best = np.maximum(best, self.clearance[j, i] - d)
        return best


def clearance_grid(world, step: float = STEP, known_only: bool = False, movers_at: float | None = None) -> Grid:
    """The arena's nodes and their exact clearance (see the module docstring).

    ``known_only``: only the planner's a-priori map (walls, known obstacles, known events).
    ``movers_at``: also the moving obstacles, frozen where they are at that time (s); by default they are
    left out.
    """
    w, h = world.size
    nx, ny = max(2, math.ceil(w / step - 1e-9)), max(2, math.ceil(h / step - 1e-9))
    hx, hy = w / nx, h / ny
    xs = 0.5 * hx + hx * np.arange(nx)
    ys = 0.5 * hy + hy * np.arange(ny)
    points = np.stack(np.meshgrid(xs, ys), axis=-1)
    return Grid(float(xs[0]), float(ys[0]), hx, hy, clearance(world, points, known_only, movers_at))


def clearance(world, points, known_only: bool = False, movers_at: float | None = None) -> np.ndarray:
    """Exact clearance at ``points`` ``(..., 2)`` of what :func:`clearance_grid` counts (every event's shapes)."""
    c = world.clearance(points, t=math.inf, include_moving=False, known_only=known_only)
    if movers_at is not None:
        for m in world.moving:
            c = np.minimum(c, distance(points, m.at(movers_at)))
    return c


def reach(world, *, known_only: bool = False, movers_at: float | None = None, step: float = STEP,
          radius: float = KHEPERA.radius, start=None, goal=None) -> Reach:
    """Search ``world`` from its start to its goal (or ``start``, ``goal`` points) on a ``step`` grid.

    ``known_only`` and ``movers_at`` choose what is in the way (:func:`clearance_grid`); ``radius`` is the
    robot's (m). Returns a :class:`Reach`; an unsolvable world has ``solvable`` False and no route.
    """
    start = np.asarray(world.start[:2] if start is None else start, dtype=float)
    goal = np.asarray(world.goal_at(0.0) if goal is None else goal, dtype=float)
    straight = float(np.hypot(*(goal - start)))
    grid = clearance_grid(world, step, known_only, movers_at)
    c = grid.clearance
    ny, nx = c.shape
    usable = c >= radius + 0.5 * math.hypot(grid.hx, grid.hy) + MARGIN
    s, g = _entry(grid, usable, start), _entry(grid, usable, goal)
    if s is None or g is None:
        return Reach(False, straight)

    # Flat indices into a grid padded by one unusable node on every side: no bounds checks in the loops.
    cols = nx + 2
    padded = np.zeros((ny + 2, cols), dtype=bool)
    padded[1:-1, 1:-1] = usable
    flat_usable = padded.ravel().tolist()
    si, gi = (s[0] + 1) * cols + s[1] + 1, (g[0] + 1) * cols + g[1] + 1

    zone = np.zeros_like(c)
    points = np.stack(np.meshgrid(grid.x0 + grid.hx * np.arange(nx), grid.y0 + grid.hy * np.arange(ny)), axis=-1)
    for p in (start, goal):
        zone[np.hypot(*(points - p).transpose(2, 0, 1)) < END_ZONE] = np.inf
    counted = np.zeros((ny + 2, cols))
    counted[1:-1, 1:-1] = np.maximum(c, zone)
    value = counted.ravel().tolist()
    widest = _widest(flat_usable, value, si, gi, cols)
    if widest is None:
        return Reach(False, straight)
    narrow = [(grid.point(u // cols - 1, u % cols - 1), grid.point(v // cols - 1, v % cols - 1), value[v])
              for u, v, w in zip(widest, widest[1:], widest[2:]) if value[v] <= min(value[u], value[w])]
    bottleneck = _refined(world, grid, narrow, known_only, movers_at) if narrow else float(c.max())

    nodes = _shortest(flat_usable, si, gi, cols, grid.hx, grid.hy)
    path = [grid.point(u // cols - 1, u % cols - 1) for u in _corners(nodes, cols)]
    route = _smooth(grid, np.array([start, *path, goal]), radius)
    return Reach(True, straight, 2.0 * bottleneck, route, count_turns(route))


def _entry(grid: Grid, usable: np.ndarray, p) -> tuple[int, int] | None:
    """The usable node nearest ``p`` within one and a half grid steps, or None."""
    j, i = grid.node(p)
    ny, nx = usable.shape
    best, where = math.inf, None
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            jj, ii = j + dj, i + di
            if 0 <= jj < ny and 0 <= ii < nx and usable[jj, ii]:
                x, y = grid.point(jj, ii)
                d = math.hypot(x - p[0], y - p[1])
                if d < best and d <= 1.5 * max(grid.hx, grid.hy):
                    best, where = d, (jj, ii)
    return where


def _moves(cols: int, hx: float = 1.0, hy: float = 1.0) -> tuple[tuple[int, float], ...]:
    hd = math.hypot(hx, hy)
    return ((1, hx), (-1, hx), (cols, hy), (-cols, hy), (cols + 1, hd), (cols - 1, hd), (1 - cols, hd), (-1 - cols, hd))


def _widest(usable: list, value: list, s: int, g: int, cols: int) -> list[int] | None:
    """The path of usable nodes from ``s`` to ``g`` whose smallest ``value`` is largest (a Dijkstra that
    keeps the best bottleneck instead of the shortest distance), as flat indices; None if ``g`` is cut off."""
    best = [-1.0] * len(usable)
    prev = [-1] * len(usable)
    best[s] = value[s]
    heap = [(-value[s], s)]
    moves = [m for m, _ in _moves(cols)]
    pop, push = heapq.heappop, heapq.heappush
    while heap:
        b, u = pop(heap)
        b = -b
        if b < best[u]:
            continue
        if u == g:
            path = [g]
            while path[-1] != s:
                path.append(prev[path[-1]])
            return path[::-1]
        for m in moves:
            v = u + m
            if usable[v]:
                w = value[v] if value[v] < b else b
                if w > best[v]:
                    best[v] = w
                    prev[v] = u
                    push(heap, (-w, v))
    return None


def _refined(world, grid: Grid, narrow: list, known_only: bool, movers_at: float | None) -> float:
    """The widest path's bottleneck, refined off the grid: at each of its local minima ``(before, node,
    value)`` within half a grid diagonal of the lowest (at most ``REFINE``), the exact clearance on a local
    1 mm lattice, its largest across the path's direction (the best place to pass) and the smallest of
    those along it (the gap's narrowest cross-section); the smallest of these, kept within half a grid
    diagonal of the grid's answer."""
    half = 0.5 * math.hypot(grid.hx, grid.hy)
    lowest = min(v for _, _, v in narrow)
    if not math.isfinite(lowest):
        return float(grid.clearance.max())
    spots = sorted((v, k) for k, (_, _, v) in enumerate(narrow) if v <= lowest + half)[:REFINE]
    along = np.linspace(-half, half, 2 * math.ceil(half / 0.001) + 1)
    across = np.linspace(-2 * half, 2 * half, 4 * math.ceil(half / 0.001) + 1)
    best = math.inf
    for _, k in spots:
        before, node, _ = narrow[k]
        d = np.subtract(node, before)
        d /= np.hypot(*d)
        n = np.array([-d[1], d[0]])
        points = np.asarray(node) + along[:, None, None] * d + across[None, :, None] * n
        best = min(best, float(clearance(world, points, known_only, movers_at).max(axis=1).min()))
    return float(np.clip(best, lowest - half, lowest + half))


def _shortest(usable: list, s: int, g: int, cols: int, hx: float, hy: float) -> list[int]:
    """The shortest 8-connected path of usable nodes from ``s`` to ``g`` (A*, octile heuristic), as flat
    indices; ``g`` must be reachable."""
    moves = _moves(cols, hx, hy)
    hd = math.hypot(hx, hy)
    gr, gc = divmod(g, cols)

    def heuristic(u: int) -> float:
        r, c = divmod(u, cols)
        dr, dc = abs(r - gr), abs(c - gc)
        m = min(dr, dc)
        return m * hd + (dc - m) * hx + (dr - m) * hy

    cost = [math.inf] * len(usable)
    prev = [-1] * len(usable)
    cost[s] = 0.0
    heap = [(heuristic(s), 0.0, s)]
    pop, push = heapq.heappop, heapq.heappush
    while heap:
        _, d, u = pop(heap)
        if d > cost[u]:
            continue
        if u == g:
            break
        for m, step in moves:
            v = u + m
            if usable[v]:
                nd = d + step
                if nd < cost[v]:
                    cost[v] = nd
                    prev[v] = u
                    push(heap, (nd + heuristic(v), nd, v))
    path = [g]
    while path[-1] != s:
        path.append(prev[path[-1]])
    return path[::-1]


def _corners(nodes: list[int], cols: int) -> list[int]:
    """The path's nodes where its direction changes (and its ends)."""
    if len(nodes) <= 2:
        return nodes
    keep = [nodes[0]]
    for a, b, c in zip(nodes, nodes[1:], nodes[2:]):
        if b - a != c - b:
            keep.append(b)
    keep.append(nodes[-1])
    return keep


def _clear_line(grid: Grid, a, b, radius: float) -> bool:
    """Does the robot stay clear of everything on the straight line from ``a`` to ``b``? Checked on samples
    a quarter step apart, each needing clearance radius + half the spacing (so the whole line is clear)."""
    length = math.hypot(b[0] - a[0], b[1] - a[1])
    n = max(2, math.ceil(length / (0.25 * min(grid.hx, grid.hy))) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    samples = a + t * (np.asarray(b) - a)
    return bool(np.all(grid.clearance_bound(samples) >= radius + 0.5 * length / (n - 1)))


def _smooth(grid: Grid, path: np.ndarray, radius: float, window: int = SMOOTH_WINDOW) -> np.ndarray:
    """Pull ``path`` straight: from each kept vertex, go to the farthest of the next ``window`` vertices in
    line of sight (string pulling), then drop the vertices whose neighbours see each other. The route stays
    clear: every edge is either in line of sight or an edge of ``path``."""
    out = [path[0]]
    i, last = 0, len(path) - 1
    while i < last:
        j = next((j for j in range(min(last, i + window), i + 1, -1) if _clear_line(grid, path[i], path[j], radius)),
                 i + 1)
        out.append(path[j])
        i = j
    kept = [out[0]]  # a second look: drop a vertex whose neighbours see each other
    for k in range(1, len(out) - 1):
        if not _clear_line(grid, kept[-1], out[k + 1], radius):
            kept.append(out[k])
    kept.append(out[-1])
    return np.array(kept)


def count_turns(route, min_deg: float = TURN_DEG, merge: float = TURN_MERGE) -> int:
    """Direction changes of more than ``min_deg`` along the polyline ``route`` ``(k, 2)``; interior vertices
    closer than ``merge`` (m) to the previous one join its turn, which counts by its net change."""
    route = np.asarray(route, dtype=float)
    seg = np.diff(route, axis=0)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    seg, lengths = seg[lengths > 0], lengths[lengths > 0]
    if len(seg) < 2:
        return 0
    heading = np.arctan2(seg[:, 1], seg[:, 0])
    change = wrap(np.diff(heading))  # at each interior vertex
    turns, net = 0, 0.0
    for k, d in enumerate(change):
        if k > 0 and lengths[k] >= merge:  # the segment before this vertex is long: a new turn starts
            turns += abs(net) > math.radians(min_deg)
            net = 0.0
        net += d
    return turns + (abs(net) > math.radians(min_deg))
