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
from robots.geometry import Circle, Segment, bounds, distance

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
    p = np.asarray(points, dtype=float)
    table = _table(obstacles)
    out = np.full(p.shape[:-1], np.inf)
    for k in np.flatnonzero(table.other).tolist():
        shape, clearance = obstacles[k]
        out = np.minimum(out, distance(p, shape) - clearance)
    for which, rows, gaps in table.arrays():
        if which.any():
            out = np.minimum(out, _least(p.reshape(-1, 2), rows[which], None, gaps).reshape(out.shape))
    return out


def _least(p: np.ndarray, rows: np.ndarray, near: np.ndarray | None, gaps) -> np.ndarray:
    """min over the shapes ``rows`` ``(m, ...)`` of ``gaps(p, rows)`` ``(n, m)`` (distance − clearance, m) at the
    points ``p`` ``(n, 2)``, ``(n,)``; with ``near`` ``(n, m)`` bool, over the shapes near each point only. All
    shapes at once, in chunks of at most 2 million point-shape pairs: a large world has hundreds of walls and a
    recovery hundreds of sensed discs, and one NumPy call a shape cost more than the sums."""
    out = np.full(len(p), np.inf)
    chunk = max(1, 2_000_000 // max(1, len(p)))
    for k in range(0, len(rows), chunk):
        s = gaps(p, rows[k:k + chunk])
        if near is not None:
            s = np.where(near[:, k:k + chunk], s, np.inf)
        out = np.minimum(out, s.min(axis=1))
    return out


def _wall_gaps(p: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Distance − clearance ``(n, m)`` from the points ``p`` ``(n, 2)`` to the walls ``w`` ``(m, 6)`` (rows of
    :attr:`_Table.walls`): the arithmetic of :func:`robots.geometry.segment_distance` (t clipped to the wall, 0 on
    a wall of no length, whose end − start is zero), written out per coordinate."""
    rx = p[:, 0:1] - w[:, 0]
    ry = p[:, 1:2] - w[:, 1]
    t = np.minimum(np.maximum((rx * w[:, 2] + ry * w[:, 3]) / w[:, 4], 0.0), 1.0)
    dx = rx - t * w[:, 2]
    dy = ry - t * w[:, 3]
    return np.sqrt(dx * dx + dy * dy) - w[:, 5]


def _circle_gaps(p: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance − clearance ``(n, m)`` from the points ``p`` ``(n, 2)`` to the circles ``c`` ``(m, 4)`` (rows of
    :attr:`_Table.circles`): the arithmetic of :func:`robots.geometry.distance` for a circle, per coordinate."""
    dx = p[:, 0:1] - c[:, 0]
    dy = p[:, 1:2] - c[:, 1]
    return np.maximum(np.sqrt(dx * dx + dy * dy) - c[:, 2], 0.0) - c[:, 3]


def segment_slack(a, b, obstacles: Sequence[Padded], step: float = STEP) -> float:
    """Least slack (m) of the points of segment ``a``–``b``, sampled every ``step`` (the slack is 1-Lipschitz,
    so the true least is within ``step / 2`` of this). Only obstacles whose grown box meets the segment's
    box are measured."""
    return float(_legs_slack(*_legs([(a, b)], obstacles, step), obstacles, every=1)[0])


def segment_clear(a, b, obstacles: Sequence[Padded], least: float, step: float = STEP, every: int = 16) -> bool:
    """Whether ``segment_slack(a, b, obstacles, step) >= least`` — the same answer, found faster: the slack is
    measured first at every ``every``-th sample point (and the last); one below ``least`` answers no, and if even
    the least of them less ``every / 2`` sample spacings (the slack is 1-Lipschitz, and every sample point is that
    close to a measured one) is ``>= least``, every sample point is clear. Only in between are all measured. A
    long leg of a large world has thousands of sample points near dozens of walls; most legs are decided on a
    sixteenth of them (issue 35: planning a 4 m world took seconds)."""
    return legs_clear([(a, b, least)], obstacles, step, every)[0]


def legs_clear(legs: Sequence, obstacles: Sequence[Padded], step: float = STEP, every: int = 16) -> list[bool]:
    """:func:`segment_clear` of each leg ``(a, b, least)`` of ``legs``, the same answers, measured together: a few
    NumPy calls for all the legs instead of a few for each (:func:`taut` asks thousands of legs, in runs of
    candidates of which it needs the first clear one)."""
    if not legs:
        return []
    a, b, n, near = _legs([(a, b) for a, b, _ in legs], obstacles, step)
    coarse = _legs_slack(a, b, n, near, obstacles, every).tolist()
    measured = near.any(axis=1).tolist()
    # The last sample point less the first, each made as _legs_slack makes them (at fractions 1 and 0).
    span = (a + 1.0 * (b - a)) - (a + 0.0 * (b - a))
    answers: list = [None] * len(legs)
    finer = []
    for i, (_, _, least) in enumerate(legs):
        if not measured[i]:
            answers[i] = math.inf >= least
            continue
        if coarse[i] < least:
            answers[i] = False
            continue
        if coarse[i] - (every / 2) * (float(np.linalg.norm(span[i])) / (n[i] - 1)) >= least:
            answers[i] = True
        else:
            finer.append(i)
    if finer:
        full = _legs_slack(a[finer], b[finer], [n[i] for i in finer], near[finer], obstacles, every=1)
        for i, s in zip(finer, full.tolist()):
            answers[i] = s >= legs[i][2]
    return answers


def _legs(pairs: Sequence, obstacles: Sequence[Padded], step: float):
    """The legs ``pairs`` (``(a, b)`` each) as their ends ``a``, ``b`` ``(L, 2)``, their numbers of sample points
    ``n`` (every ``step``, at least the two ends; a list of ``L`` ints) and ``near`` ``(L, k)`` bool: the padded
    obstacles whose box grown by their clearance + 5 cm meets each leg's box."""
    a = np.array([p for p, _ in pairs], dtype=float).reshape(-1, 2)
    b = np.array([q for _, q in pairs], dtype=float).reshape(-1, 2)
    n = [max(2, int(math.ceil(float(np.linalg.norm(q - p)) / step)) + 1) for p, q in zip(a, b)]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    x0, y0, x1, y1 = _table(obstacles).boxes
    near = (x0 <= hi[:, 0:1]) & (y0 <= hi[:, 1:2]) & (lo[:, 0:1] <= x1) & (lo[:, 1:2] <= y1)
    return a, b, n, near


def _legs_slack(a: np.ndarray, b: np.ndarray, n: Sequence[int], near: np.ndarray, obstacles: Sequence[Padded],
                every: int) -> np.ndarray:
    """Least slack ``(L,)`` (m) over every ``every``-th sample point (and the last) of each leg ``a``–``b`` (as from
    :func:`_legs`), measured to the obstacles near it (inf if none is). The points of all legs are measured against
    the walls near any of them at once, a wall counting only for the legs it is near; the circles (a
    recovery's sensed points, hundreds of them) likewise; each other shape once, at the points of the legs it is
    near."""
    fractions = [_fractions(k, every) for k in n]
    counts = [len(f) for f in fractions]
    leg = np.repeat(np.arange(len(n)), counts)
    p = a[leg] + np.concatenate(fractions) * (b - a)[leg]  # (N, 2)
    starts = np.cumsum([0] + counts[:-1])
    table = _table(obstacles)
    least = np.full(len(p), np.inf)
    for which, rows, gaps in table.arrays():
        ks = np.flatnonzero(near.any(axis=0) & which)
        if len(ks):
            least = np.minimum(least, _least(p, rows[ks], near[:, ks][leg], gaps))
    for k in np.flatnonzero(near.any(axis=0) & table.other).tolist():
        rows = near[leg, k]  # the points of the legs this shape is near, all at once
        shape, clearance = obstacles[k]
        least[rows] = np.minimum(least[rows], distance(p[rows], shape) - clearance)
    return np.minimum.reduceat(least, starts)


@functools.lru_cache(maxsize=1024)
def _fractions(n: int, every: int) -> np.ndarray:
    """Where along a leg of ``n`` sample points (``np.linspace(0, 1, n)``) every ``every``-th one and the last lie,
    ``(k, 1)``, read-only: remembered, as the legs of a plan have a few hundred lengths among thousands of legs."""
    fractions = np.linspace(0.0, 1.0, n)[np.append(np.arange(0, n - 1, every), n - 1), None]
    fractions.flags.writeable = False
    return fractions


class _Table(NamedTuple):
    """A list of ``k`` padded obstacles as arrays. ``boxes`` ``(4, k)``: their bounding boxes ``x0, y0, x1, y1``
    grown by their clearance + 5 cm (which :func:`_legs` tests); ``wall`` ``(k,)``: whether each is a wall segment;
    ``walls`` ``(k, 6)``: for a segment its start ``(x, y)``, end − start, squared length (1 for a segment of no
    length, whose end − start is zero) and clearance (zeros for other shapes); ``circle`` ``(k,)``: whether each is a
    circle; ``circles`` ``(k, 4)``: for a circle its centre ``(x, y)``, radius and clearance (zeros for other shapes) —
    a recovery's sensed points are hundreds of small circles."""

    boxes: np.ndarray
    wall: np.ndarray
    walls: np.ndarray
    circle: np.ndarray
    circles: np.ndarray

    @property
    def other(self) -> np.ndarray:
        """``(k,)``: the obstacles measured one by one (:func:`robots.geometry.distance`), neither wall nor circle."""
        return ~self.wall & ~self.circle

    def arrays(self) -> tuple:
        """The kinds measured all at once, as ``(which (k,), rows (k, ...), gaps)`` for :func:`_least`."""
        return ((self.wall, self.walls, _wall_gaps), (self.circle, self.circles, _circle_gaps))


_TABLES: dict = {}


def _table(obstacles: Sequence[Padded]) -> _Table:
    """The :class:`_Table` of ``obstacles``, made once per obstacle list (kept while the list lives; a plan and a run
    each measure one list thousands of times)."""
    key = id(obstacles)
    held = _TABLES.get(key)
    if held is not None and held[0] is obstacles:
        return held[1]
    boxes = np.array([(lambda x0, y0, x1, y1, g: (x0 - g, y0 - g, x1 + g, y1 + g))(*bounds(s), c + 0.05)
                      for s, c in obstacles], dtype=float).reshape(-1, 4).T.copy()
    wall = np.array([isinstance(s, Segment) for s, _ in obstacles], dtype=bool)
    ends = np.array([(s.start, s.end) if isinstance(s, Segment) else ((0.0, 0.0), (0.0, 0.0)) for s, _ in obstacles],
                    dtype=float).reshape(-1, 2, 2)
    ab = ends[:, 1] - ends[:, 0]
    denom = ab[:, 0] * ab[:, 0] + ab[:, 1] * ab[:, 1]
    clearance = np.array([c for _, c in obstacles], dtype=float)
    walls = np.column_stack([ends[:, 0], ab, np.where(denom > 0, denom, 1.0), np.where(wall, clearance, 0.0)])
    circle = np.array([isinstance(s, Circle) for s, _ in obstacles], dtype=bool)
    circles = np.array([(*s.center, s.radius, c) if isinstance(s, Circle) else (0.0, 0.0, 0.0, 0.0)
                        for s, c in obstacles], dtype=float).reshape(-1, 4)
    table = _Table(boxes, wall, walls, circle, circles)
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
    cells = _cheapest_cells(inside, penalty, first, last)
    if cells is None:
        return None
    pts = np.array([((x + 0.5) * cell, (y + 0.5) * cell) for y, x in cells])
    pts = np.vstack([np.asarray(start, float)[None, :2], pts, np.asarray(goal, float)[None, :2]])
    ends = slack(pts[[0, -1]], obstacles)
    return pts, np.concatenate([[ends[0]], s[tuple(np.array(cells).T)], [ends[1]]]), centres, s[iy, ix]


_MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))


def _cheapest_cells(inside: np.ndarray, penalty: np.ndarray, first, last) -> list[tuple[int, int]] | None:
    """The cells ``(iy, ix)``, in order, of the cheapest 8-connected path over ``inside`` cells from ``first`` to
    ``last``, a step costing its length times the mean ``penalty`` of its two cells; a diagonal step needs both
    cells it passes between inside (no corner cutting). None if there is none.

    Dijkstra's search, its heap ordered by (cost, iy, ix): of paths of equal cost it keeps the one that order
    reaches first. It runs on flat Python lists with a one-cell frame that is not inside (no bounds checks, no
    NumPy scalars): a large world's route has tens of thousands of cells."""
    ny, nx = inside.shape
    stride = nx + 2
    framed = np.zeros((ny + 2, nx + 2), dtype=bool)
    framed[1:-1, 1:-1] = inside
    ok = framed.ravel().tolist()
    weights = np.zeros((ny + 2, nx + 2))
    weights[1:-1, 1:-1] = penalty
    pen = weights.ravel().tolist()
    # A move: the step to the next cell, the steps to the two cells a diagonal passes between (0 if straight), and
    # half its length (the mean of the two penalties is taken with it).
    moves = [(dy * stride + dx, dx if dy and dx else 0, dy * stride, (1.4142135623730951 if dy and dx else 1.0) * 0.5)
             for dy, dx in _MOVES]
    start, goal = (first[0] + 1) * stride + first[1] + 1, (last[0] + 1) * stride + last[1] + 1
    cost = [math.inf] * len(ok)
    cost[start] = 0.0
    parent = [start] * len(ok)
    done = [False] * len(ok)
    heap = [(0.0, start)]
    while heap:
        c, here = heapq.heappop(heap)
        if done[here]:
            continue
        if here == goal:
            break
        done[here] = True
        p = pen[here]
        for step, side, other, half in moves:
            there = here + step
            if not ok[there] or (side and not (ok[here + side] and ok[here + other])):
                continue
            nc = c + half * (p + pen[there])
            if nc < cost[there]:
                cost[there] = nc
                parent[there] = here
                heapq.heappush(heap, (nc, there))
    else:
        return None
    cells = [goal]
    while cells[-1] != start:
        cells.append(parent[cells[-1]])
    return [(f // stride - 1, f % stride - 1) for f in reversed(cells)]


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
    lengths: dict = {}  # (a, c) -> length of the leg a–c
    floors: dict = {}  # (i, j) -> least capped slack of the path points i … j
    # A corner: (point, its slack capped at margin, the path index whose stretch it stands for).
    Corner = tuple

    def need(a: Corner, c: Corner) -> float:
        i, j = sorted((a[2], c[2]))
        if (i, j) not in floors:  # the passes below ask the same stretches again and again
            floors[(i, j)] = float(floor[i:j + 1].min())
        return min(floors[(i, j)], a[1], c[1]) - tolerance

    def clear_all(legs) -> list[bool]:
        """Whether each leg ``(a, c, stretch)`` is clear; ``stretch`` (two corners, or None) widens the path stretch
        whose least slack counts, for a corner that replaces those between them. The legs not asked before are
        measured together (:func:`legs_clear`)."""
        keys = []
        for a, c, stretch in legs:
            least = need(a, c) if stretch is None else min(need(*stretch), a[1] - tolerance, c[1] - tolerance)
            keys.append((a[0].tobytes(), c[0].tobytes(), least))  # the passes below ask the same legs again and again
        new = {key: (a[0], c[0], key[2]) for key, (a, c, _) in zip(keys, legs) if key not in seen}
        seen.update(zip(new, legs_clear(list(new.values()), obstacles)))
        return [seen[key] for key in keys]

    def clear(a: Corner, c: Corner) -> bool:
        return clear_all([(a, c, None)])[0]

    def at(i: int) -> Corner:
        return (points[i], float(floor[i]), i)

    def leg(p: Corner, q: Corner):
        key = (p[0].tobytes(), q[0].tobytes())  # via below measures the same legs for every corner it tries
        if key not in lengths:
            lengths[key] = np.linalg.norm(q[0] - p[0])
        return lengths[key]

    def length(ks) -> float:
        return float(sum(leg(p, q) for p, q in zip(ks[:-1], ks[1:])))

    def reach(i: int) -> int:
        """The last path index j such that the legs from point i to each of i + 2 … j are clear (i + 1 if the leg to
        i + 2 is not). The legs ahead are asked a few at a time, twice as many each time, up to 32."""
        j, block = i + 1, 4
        while j + 1 < n:
            ahead = range(j + 1, min(n, j + 1 + block))
            ok = clear_all([(at(i), at(k), None) for k in ahead])
            if not all(ok):
                return j + ok.index(False)
            j, block = ahead[-1], min(2 * block, 32)
        return j

    def via(a: Corner, c: Corner, current: float, extra=()):
        """The point b (a path point between a and c, or one of ``extra``) that makes a → b → c shortest with
        both legs clear, if shorter than ``current``; None if there is none. The points are tried shortest first,
        a few at a time, twice as many each time, up to 32."""
        options = [at(i) for i in range(a[2] + 1, c[2])] + list(extra)
        total = [length([a, b, c]) for b in options]
        shorter = [options[k] for k in sorted(range(len(options)), key=total.__getitem__) if total[k] < current - 1e-12]
        start, block = 0, 2
        while start < len(shorter):
            tried = shorter[start:start + block]
            first = [b for b, ok in zip(tried, clear_all([(a, b, (a, c)) for b in tried])) if ok]
            for b, ok in zip(first, clear_all([(b, c, (a, c)) for b in first])):
                if ok:
                    return b
            start, block = start + block, min(2 * block, 32)
        return None

    corners = [at(0)]
    i = 0
    while i < n - 1:
        i = reach(i)
        corners.append(at(i))
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
