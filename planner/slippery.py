"""Slippery-cell labelling of a bitmap (thesis ch. 3.2.1–3.2.2, Fig. 3.3b, 3.4, 3.5).

"A cell is defined to be slippery if the outward normal from any point on its boundary does not
intersect the same cell" (ch. 3.2.1). On a bitmap every boundary is made of horizontal and vertical
cell edges, so the outward normals run along rows and columns: a 4-connected set of bitmap cells is
slippery exactly when **every row and every column of it is one contiguous run** (an outward normal
that re-entered the set would cross a gap between two runs). :func:`is_slippery` checks this.

:func:`label_slippery` grows slippery cells as the text of ch. 3.2.2 describes: a seed cell is grown by
its unlabelled free 4-neighbours, queued first-in first-out (the list L of Fig. 3.5), and a free cell p
joins the current slippery cell unless

* it is connected to the cell **only horizontally** and its column already holds a cell of it, or
* it is connected **only vertically** and its row already holds a cell of it;

a cell connected both ways joins (Fig. 3.4b). The rows and columns of the cell are tracked by the
projections X and Y of Fig. 3.5. This rule keeps the invariant: joining a cell connected horizontally
extends the run of its row by one, and is allowed only if its column is empty or (connected vertically
too) it extends that column's run as well.

The printed pseudo-code of Fig. 3.5 has three slips, corrected here to follow the text: it appends the
neighbours of q (the seed) instead of those of p, it never removes p from L, and for a cell connected
both ways it returns the column test instead of admitting the cell. A rejected cell stays in the free
pool; it is queued again whenever one more of its neighbours joins (it may then be connected both ways),
and otherwise it seeds a later slippery cell.

Order: the first seed is the robot's cell (Fig. 3.3b: "the labeling of the first slippery cell '1'
starts at the robot's initial position"); later seeds are the unlabelled free cells in row-major order
from the bottom-left (Fig. 3.5 line 2: "for each element q in W"). Neighbours are queued in the order
up, right, down, left (Fig. 3.5 line 12). The labelling runs in O(free cells): each joined cell queues
at most four cells.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from planner.bitmap import FREE, OCCUPIED


def label_slippery(W: np.ndarray, seed: tuple[int, int] | None = None) -> np.ndarray:
    """Label the free cells of the bitmap ``W`` ``(ny, nx)`` with slippery cells ``1 … n`` (Fig. 3.5, corrected).

    ``seed`` = ``(iy, ix)`` is the robot's cell, where labelling starts (it must be free); ``None`` starts
    at the first free cell in row-major order. Returns ``labels`` ``(ny, nx)`` int32: ``-1`` occupied,
    ``k >= 1`` the slippery cell holding that bitmap cell. See the module docstring for the rule.
    """
    W = np.asarray(W)
    if W.ndim != 2:
        raise ValueError(f"W must be a 2-D bitmap, got shape {W.shape}")
    ny, nx = W.shape
    stride = nx + 2
    # Work on flat Python lists with a one-cell occupied frame: no bounds checks, no NumPy scalar overhead.
    framed = np.full((ny + 2, nx + 2), OCCUPIED, dtype=np.int64)
    framed[1:-1, 1:-1] = np.where(W == FREE, FREE, OCCUPIED)
    lab = framed.ravel().tolist()
    X = [0] * stride  # X[column] == cell: the column holds a cell of slippery cell `cell` (Fig. 3.5)
    Y = [0] * (ny + 2)  # Y[row] == cell: the row holds one
    seeds = np.flatnonzero(framed.ravel() == FREE).tolist()
    if seed is not None:
        iy, ix = seed
        if not (0 <= iy < ny and 0 <= ix < nx) or W[iy, ix] != FREE:
            raise ValueError(f"seed {seed} is not a free cell of the {ny} x {nx} bitmap")
        seeds.insert(0, (iy + 1) * stride + ix + 1)
    steps = (stride, 1, -stride, -1)  # up, right, down, left
    cell = 0
    for q in seeds:
        if lab[q] != FREE:
            continue
        cell += 1
        L = deque((q,))
        while L:
            p = L.popleft()
            if lab[p] != FREE:
                continue
            py, px = divmod(p, stride)
            horizontal = lab[p - 1] == cell or lab[p + 1] == cell
            vertical = lab[p - stride] == cell or lab[p + stride] == cell
            if horizontal != vertical and (X[px] == cell if horizontal else Y[py] == cell):
                continue  # connected one way only and would open a second run in its column/row
            lab[p] = cell
            X[px] = cell
            Y[py] = cell
            for s in steps:
                if lab[p + s] == FREE:
                    L.append(p + s)
    return np.asarray(lab, dtype=np.int32).reshape(ny + 2, nx + 2)[1:-1, 1:-1].copy()


def is_slippery(mask: np.ndarray) -> bool:
    """Whether the bitmap cells ``mask`` ``(ny, nx)`` bool form one slippery cell (ch. 3.2.1).

    True iff the set is non-empty, 4-connected, and each of its rows and columns is one contiguous run.
    """
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return False
    for m in (mask, mask.T):
        # Runs per line = number of 0→1 steps along it; a line of the set must have exactly one.
        starts = np.diff(m.astype(np.int8), axis=1, prepend=0) == 1
        runs = starts.sum(axis=1)
        if np.any(runs[m.any(axis=1)] != 1):
            return False
    return _connected(mask)


def _connected(mask: np.ndarray) -> bool:
    """Whether the cells of ``mask`` are 4-connected (flood fill from one of them)."""
    cells = set(zip(*np.nonzero(mask)))
    todo = [next(iter(cells))]
    seen = {todo[0]}
    while todo:
        y, x = todo.pop()
        for n in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
            if n in cells and n not in seen:
                seen.add(n)
                todo.append(n)
    return len(seen) == len(cells)
