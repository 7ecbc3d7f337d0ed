"""Checkpoints that see each other: the default checkpoint rule, a labelled extension of thesis ch. 3.2.3.

The thesis's greedy rule (:mod:`planner.checkpoints`) puts one checkpoint on each boundary the route
crosses. A slippery cell need not be convex — a staircase of steps passes its row/column test — so the
straight leg between two greedy checkpoints can run through walls, and a reactive layer pulled towards
a checkpoint behind several walls has nothing to follow. Here the checkpoints are the corners of a path
through the *same route of cells* on which **every leg is a straight segment that keeps the robot's
clearance**:

1. every free bitmap cell of the route gets its *slack* — how far its centre is from the nearest padded
   obstacle beyond the cushion (:func:`slack`; the cushion is the robot radius, ch. 3.2.2, so slack is
   the gap the body keeps);
2. a shortest path over the route's free bitmap cells (8-connected, no corner cutting) whose step cost
   grows where the slack is below ``margin``, ``length · (1 + weight · (margin − slack) / margin)``:
   it keeps ``margin`` from walls where there is room and takes the middle of a narrow doorway;
3. that path pulled taut: from each checkpoint the next is the farthest path point that the straight
   segment reaches while keeping ``min(margin, least slack of the path in between) − tolerance``
   (:func:`segment_slack`), the goal last.

4. a narrow stretch of the path — slack below ``margin``, a doorway or corridor less than about 11 cm
   wide — gets a checkpoint ``LEAD`` before and after it (:func:`narrow_ends`), and step 3 pulls each piece
   between those taut on its own: the robot lines up with the passage before it enters.

So consecutive checkpoints see each other with ``margin`` to spare where the path had it, and with the
path's own slack through a narrow passage. The route of cells is the thesis's (slippery cells and the
search of :mod:`planner.search`); ``checkpoints="thesis"`` in :func:`planner.plan` keeps the greedy rule.
"""

from __future__ import annotations

import functools
import heapq
import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from planner.bitmap import FREE, Padded, free_cell_at
from robots.geometry import Segment, bounds, distance

#: Extra clearance (m) beyond the cushion that checkpoint legs keep where there is room: a little less
#: than the 1.5 cm each side that an 8 cm doorway leaves the 5 cm robot.
MARGIN = 0.03

#: How much dearer a step with no slack is than one with ``margin`` (the path's pull to the middle).
WEIGHT = 4.0

#: Slack (m) a leg may lose against the path it replaces: the path's cells are sampled at their centres.
TOLERANCE = 0.003

#: Spacing (m) of the points at which a leg's slack is measured.
STEP = 0.002

#: Distance (m) along the path before and after a narrow stretch at which a checkpoint lines the robot up.
LEAD = 0.06


def slack(points, obstacles: Sequence[Padded]) -> np.ndarray:
    """Slack ``(...,)`` of ``points`` ``(..., 2)``: min over padded obstacles of distance − clearance (m);
    negative inside a cushion."""
    return _slack(points, obstacles, np.arange(len(obstacles)))


def _slack(points, obstacles: Sequence[Padded], which: np.ndarray) -> np.ndarray:
    """:func:`slack` over the obstacles ``obstacles[which]`` only (``which`` ``(m,)`` int). The walls are measured
    all at once (:func:`_walls_slack`, in chunks of at most 2 million point-wall pairs), the other shapes one by
    one."""
    p = np.asarray(points, dtype=float)
    table = _table(obstacles)
    out = np.full(p.shape[:-1], np.inf)
    for k in which[~table.wall[which]].tolist():
        shape, clearance = obstacles[k]
        out = np.minimum(out, distance(p, shape) - clearance)
    walls = table.walls[which[table.wall[which]]]
    if len(walls):
        flat = p.reshape(-1, 2)
        chunk = max(1, 2_000_000 // max(1, len(flat)))
        least = out.reshape(-1)
        for k in range(0, len(walls), chunk):
            least = np.minimum(least, _walls_slack(flat, walls[k:k + chunk]).min(axis=1))
        out = least.reshape(out.shape)
    return out


def _walls_slack(p: np.ndarray, walls: np.ndarray) -> np.ndarray:
    """Distance − clearance ``(n, m)`` (m) from the points ``p`` ``(n, 2)`` to the walls ``walls`` ``(m, 6)`` (rows of
    :attr:`_Table.walls`), all at once: a large world has hundreds of walls, and one NumPy call a wall cost more
    than the sums. The arithmetic of :func:`robots.geometry.segment_distance` (t clipped to the wall, 0 on a wall
    of no length, whose ``ab`` is zero), written out per coordinate."""
    rx = p[:, 0:1] - walls[:, 0]  # (n, m)
    ry = p[:, 1:2] - walls[:, 1]
    t = np.minimum(np.maximum((rx * walls[:, 2] + ry * walls[:, 3]) / walls[:, 4], 0.0), 1.0)
    dx = rx - t * walls[:, 2]
    dy = ry - t * walls[:, 3]
    return np.sqrt(dx * dx + dy * dy) - walls[:, 5]


def segment_slack(a, b, obstacles: Sequence[Padded], step: float = STEP) -> float:
    """Least slack (m) of the points of segment ``a``–``b``, sampled every ``step`` (the slack is 1-Lipschitz,
    so the true least is within ``step / 2`` of this). Only obstacles whose grown box meets the segment's
    box are measured."""
    a, b, n, near = _leg(a, b, obstacles, step)
    if not len(near):
        return math.inf
    return float(_slack(_points(a, b, n), obstacles, near).min())


def segment_clear(a, b, obstacles: Sequence[Padded], least: float, step: float = STEP, every: int = 16) -> bool:
    """Whether ``segment_slack(a, b, obstacles, step) >= least`` — the same answer, found faster: the slack is
    measured first at every ``every``-th sample point (and the last); one below ``least`` answers no, and if even
    the least of them less ``every / 2`` sample spacings (the slack is 1-Lipschitz, and every sample point is that
    close to a measured one) is ``>= least``, every sample point is clear. Only in between are all measured. A
    long leg of a large world has thousands of sample points near dozens of walls; most legs are decided on a
    sixteenth of them (issue 35: planning a 4 m world took seconds)."""
    a, b, n, near = _leg(a, b, obstacles, step)
    if not len(near):
        return math.inf >= least
    pts = _points(a, b, n, every)
    coarse = float(_slack(pts, obstacles, near).min())
    if coarse < least:
        return False
    spacing = float(np.linalg.norm(pts[-1] - pts[0])) / (n - 1)
    if coarse - (every / 2) * spacing >= least:
        return True
    return float(_slack(_points(a, b, n), obstacles, near).min()) >= least


def _leg(a, b, obstacles: Sequence[Padded], step: float):
    """The ends ``a``, ``b`` of a leg as float arrays ``(2,)``, its number of sample points ``n`` (every ``step``,
    at least its two ends) and the indices ``(m,)`` of the padded obstacles whose box grown by their clearance +
    5 cm meets the leg's box."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    n = max(2, int(math.ceil(float(np.linalg.norm(b - a)) / step)) + 1)
    boxes = _table(obstacles).boxes
    near = np.all(boxes[:, :2] <= np.maximum(a, b), axis=1) & np.all(np.minimum(a, b) <= boxes[:, 2:], axis=1)
    return a, b, n, np.flatnonzero(near)


def _points(a: np.ndarray, b: np.ndarray, n: int, every: int = 1) -> np.ndarray:
    """Every ``every``-th of the ``n`` sample points of the leg ``a``–``b`` and the last, ``(k, 2)``."""
    return a + _fractions(n, every) * (b - a)


@functools.lru_cache(maxsize=4096)
def _fractions(n: int, every: int) -> np.ndarray:
    """Where along a leg of ``n`` sample points (``np.linspace(0, 1, n)``) every ``every``-th one and the last lie,
    ``(k, 1)``, read-only: remembered, as the legs of a plan have a few hundred lengths among thousands of legs."""
    fractions = np.linspace(0.0, 1.0, n)[np.append(np.arange(0, n - 1, every), n - 1), None]
    fractions.flags.writeable = False
    return fractions


class _Table(NamedTuple):
    """A list of ``k`` padded obstacles as arrays. ``boxes`` ``(k, 4)``: their bounding boxes grown by their clearance
    + 5 cm (which :func:`_leg` tests); ``wall`` ``(k,)``: whether each is a wall segment; ``walls`` ``(k, 6)``: for a
    segment its start ``(x, y)``, end − start, squared length (1 for a segment of no length, whose end − start is
    zero) and clearance (zeros for other shapes)."""

    boxes: np.ndarray
    wall: np.ndarray
    walls: np.ndarray


_TABLES: dict = {}


def _table(obstacles: Sequence[Padded]) -> _Table:
    """The :class:`_Table` of ``obstacles``, made once per obstacle list (kept while the list lives; a plan and a run
    each measure one list thousands of times)."""
    key = id(obstacles)
    held = _TABLES.get(key)
    if held is not None and held[0] is obstacles:
        return held[1]
    boxes = np.array([(lambda x0, y0, x1, y1, g: (x0 - g, y0 - g, x1 + g, y1 + g))(*bounds(s), c + 0.05)
                      for s, c in obstacles], dtype=float).reshape(-1, 4)
    wall = np.array([isinstance(s, Segment) for s, _ in obstacles], dtype=bool)
    ends = np.array([(s.start, s.end) if isinstance(s, Segment) else ((0.0, 0.0), (0.0, 0.0)) for s, _ in obstacles],
                    dtype=float).reshape(-1, 2, 2)
    ab = ends[:, 1] - ends[:, 0]
    denom = ab[:, 0] * ab[:, 0] + ab[:, 1] * ab[:, 1]
    clearance = np.array([c for _, c in obstacles], dtype=float)
    walls = np.column_stack([ends[:, 0], ab, np.where(denom > 0, denom, 1.0), np.where(wall, clearance, 0.0)])
    table = _Table(boxes, wall, walls)
    if len(_TABLES) > 64:
        _TABLES.clear()
    _TABLES[key] = (obstacles, table)
    return table


def route_path(W: np.ndarray, labels: np.ndarray, route: Sequence[int], cell: float, start, goal,
               obstacles: Sequence[Padded], margin: float = MARGIN, weight: float = WEIGHT):
    """The path of step 2 (module docstring): points ``(n, 2)`` from ``start`` through the centres of free
    bitmap cells of the ``route``'s cells to ``goal``, and the slack ``(n,)`` of each point; then the centres
    ``(m, 2)`` and slacks ``(m,)`` of all those free cells (where :func:`taut` may put a corner). None if the
    route's cells do not join start and goal (which a plan's route always does)."""
    inside = (W == FREE) & np.isin(labels, np.asarray(route))
    first, last = free_cell_at(W, start, cell), free_cell_at(W, goal, cell)
    if first is None or last is None or not inside[first] or not inside[last]:
        return None
    iy, ix = np.nonzero(inside)
    centres = (np.stack([ix, iy], axis=-1) + 0.5) * cell
    s = np.full(W.shape, -np.inf)
    s[iy, ix] = slack(centres, obstacles)
    penalty = 1.0 + weight * np.clip((margin - s) / margin, 0.0, None)  # (ny, nx), inf outside
    parent = _dijkstra(inside, penalty, first, last)
    if parent is None:
        return None
    cells = [last]
    while cells[-1] != first:
        cells.append(parent[cells[-1]])
    cells.reverse()
    pts = np.array([((x + 0.5) * cell, (y + 0.5) * cell) for y, x in cells])
    pts = np.vstack([np.asarray(start, float)[None, :2], pts, np.asarray(goal, float)[None, :2]])
    ends = slack(pts[[0, -1]], obstacles)
    return pts, np.concatenate([[ends[0]], s[tuple(np.array(cells).T)], [ends[1]]]), centres, s[iy, ix]


_MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))


def _dijkstra(inside: np.ndarray, penalty: np.ndarray, first, last) -> dict | None:
    """Parents of the cheapest 8-connected path over ``inside`` cells from ``first`` to ``last`` (``(iy, ix)``),
    a step costing its length times the mean ``penalty`` of its two cells; a diagonal step needs both
    cells it passes between inside (no corner cutting)."""
    ny, nx = inside.shape
    cost = {first: 0.0}
    parent = {first: first}
    heap = [(0.0, first)]
    done = set()
    while heap:
        c, here = heapq.heappop(heap)
        if here in done:
            continue
        if here == last:
            return parent
        done.add(here)
        y, x = here
        for dy, dx in _MOVES:
            v, u = y + dy, x + dx
            if not (0 <= v < ny and 0 <= u < nx and inside[v, u]):
                continue
            if dy and dx and not (inside[y, u] and inside[v, x]):
                continue
            nc = c + (1.4142135623730951 if dy and dx else 1.0) * 0.5 * (penalty[y, x] + penalty[v, u])
            if nc < cost.get((v, u), math.inf):
                cost[(v, u)] = nc
                parent[(v, u)] = here
                heapq.heappush(heap, (nc, (v, u)))
    return None


def taut(points: np.ndarray, slacks: np.ndarray, obstacles: Sequence[Padded], margin: float = MARGIN,
         tolerance: float = TOLERANCE, cells: tuple[np.ndarray, np.ndarray] | None = None,
         near: float = 0.06) -> np.ndarray:
    """Step 3 (module docstring): the corners ``(k, 2)`` of ``points`` ``(n, 2)`` pulled taut, the last point last.

    A leg between corners is *clear* when the straight segment keeps ``min(margin, least slack of the path
    between them, the corners' own slack) − tolerance``. First, from each corner the next is the last point
    before the first that no clear leg reaches; then, until nothing changes: a corner whose neighbours see
    each other is dropped; two corners that one point can replace — a path point, or a free cell
    (``cells``: centres ``(m, 2)`` and slacks ``(m,)``) within ``near`` of them — are replaced by it (a cell
    path can take one bend in two steps), even if the legs get up to ``near / 3`` longer; and each corner slides along the path between its neighbours to
    the point that makes its two legs shortest while both stay clear (so corners sit where the path turns
    round an obstacle, not wherever the first pass stopped).
    """
    n = len(points)
    floor = np.minimum(slacks, margin)
    seen: dict = {}  # (a, c, least) -> whether the leg a–c is clear
    # A corner: (point, its slack capped at margin, the path index whose stretch it stands for).
    Corner = tuple

    def need(a: Corner, c: Corner) -> float:
        i, j = sorted((a[2], c[2]))
        return min(float(floor[i:j + 1].min()), a[1], c[1]) - tolerance

    def clear(a: Corner, c: Corner, stretch=None) -> bool:
        """Whether the leg a–c is clear; ``stretch`` (two corners) widens the path stretch whose least slack
        counts, for a corner that replaces those between them."""
        least = need(a, c) if stretch is None else min(need(*stretch), a[1] - tolerance, c[1] - tolerance)
        key = (a[0].tobytes(), c[0].tobytes(), least)  # the passes below ask the same legs again and again
        if key not in seen:
            seen[key] = segment_clear(a[0], c[0], obstacles, least)
        return seen[key]

    def at(i: int) -> Corner:
        return (points[i], float(floor[i]), i)

    def length(ks) -> float:
        return float(sum(np.linalg.norm(q[0] - p[0]) for p, q in zip(ks[:-1], ks[1:])))

    def via(a: Corner, c: Corner, current: float, extra=()):
        """The point b (a path point between a and c, or one of ``extra``) that makes a → b → c shortest with
        both legs clear, if shorter than ``current``; None if there is none."""
        options = [at(i) for i in range(a[2] + 1, c[2])] + list(extra)
        options.sort(key=lambda b: length([a, b, c]))
        for b in options:
            if length([a, b, c]) >= current - 1e-12:
                return None
            if clear(a, b, (a, c)) and clear(b, c, (a, c)):
                return b
        return None

    corners = [at(0)]
    i = 0
    while i < n - 1:
        j = i + 1
        while j + 1 < n and clear(at(i), at(j + 1)):
            j += 1
        corners.append(at(j))
        i = j
    for _ in range(8):
        changed = False
        k = 1
        while k < len(corners) - 1:
            a, b, c = corners[k - 1], corners[k], corners[k + 1]
            if clear(a, c):  # the corner is not needed
                del corners[k]
                changed = True
                continue
            if k + 2 < len(corners):  # two corners where one would do (one bend taken in two steps)
                d = corners[k + 2]
                extra = ()
                if cells is not None:
                    centres, cell_slack = cells
                    close = np.nonzero(np.minimum(np.linalg.norm(centres - b[0], axis=1),
                                                  np.linalg.norm(centres - c[0], axis=1)) <= near)[0]
                    extra = [(centres[m], float(min(cell_slack[m], margin)), b[2]) for m in close]
                one = via(a, d, length([a, b, c, d]) + near / 3, extra)  # one corner fewer is worth 2 cm
                if one is not None:
                    corners[k:k + 2] = [(one[0], one[1], b[2])]
                    changed = True
                    continue
            one = via(a, c, length([a, b, c]))  # the corner slides to where the two legs are shortest
            if one is not None and one[2] != b[2]:
                corners[k], changed = one, True
            k += 1
        if not changed:
            break
    return np.array([p for p, _, _ in corners[1:]], dtype=float).reshape(-1, 2)


def visible_checkpoints(W: np.ndarray, labels: np.ndarray, route: Sequence[int], cell: float, start, goal,
                        obstacles: Sequence[Padded], margin: float = MARGIN) -> np.ndarray | None:
    """Checkpoints ``(k, 2)`` that see each other (module docstring), the goal last; None if the route's cells
    do not join ``start`` and ``goal``."""
    found = route_path(W, labels, route, cell, start, goal, obstacles, margin)
    if found is None:
        return None
    pts, s, centres, cell_slack = found
    anchors = [0, *narrow_ends(pts, s, margin), len(pts) - 1]
    pieces = [taut(pts[a:b + 1], s[a:b + 1], obstacles, margin, cells=(centres, cell_slack))
              for a, b in zip(anchors[:-1], anchors[1:])]
    corners = np.vstack(pieces)
    corners[-1] = np.asarray(goal, dtype=float)[:2]
    return corners


def narrow_ends(points: np.ndarray, slacks: np.ndarray, margin: float = MARGIN, lead: float = LEAD) -> list[int]:
    """Indices of the path points ``lead`` metres (along the path) before and after each narrow stretch — path
    points whose slack is below ``margin``: a doorway or corridor less than about 11 cm wide; stretches less
    than ``2 lead`` apart (a corridor's bends, where the outer corner leaves more room) count as one. They
    become checkpoints, so the robot lines up with a narrow passage before it enters and leaves it straight,
    instead of crossing it on the slant of a long leg (step 4 of the module docstring)."""
    n = len(points)
    narrow = slacks < margin
    narrow[0] = narrow[-1] = False  # the start and goal are where they are
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    runs, i = [], 1
    while i < n - 1:
        if narrow[i]:
            j = i
            while j + 1 < n - 1 and narrow[j + 1]:
                j += 1
            if runs and along[i] - along[runs[-1][1]] < 2 * lead:
                runs[-1] = (runs[-1][0], j)
            else:
                runs.append((i, j))
            i = j
        i += 1
    ends = []
    for i, j in runs:
        before = max(int(np.searchsorted(along, along[i] - lead, side="right")) - 1, 0)
        after = min(int(np.searchsorted(along, along[j] + lead)), n - 1)
        if before > (ends[-1] if ends else 0):
            ends.append(before)
        if after < n - 1 and after > (ends[-1] if ends else 0):
            ends.append(after)
    return ends
