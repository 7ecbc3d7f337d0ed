"""Checkpoints by the greedy rule of thesis ch. 3.2.3 (Fig. 3.6).

"From the start position, the closest point is found on the boundary between the current cell and the
next cell in the sequence. This point becomes the first checkpoint. The second checkpoint is found in
the same manner, except that the first checkpoint is now the position from which the distance is
calculated. This is repeated until the last cell is reached." The goal is the last checkpoint.

Boundaries are unions of axis-aligned runs (:mod:`planner.graph`), so the closest point on a run is the
point clamped to its box. Ties between runs at the same distance go to the first run in sorted order,
so the rule is deterministic. :mod:`planner.search` uses :func:`closest_point` to score routes, so a
route's search cost is exactly the length of its checkpoint path.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from planner.graph import Graph, Run


def closest_point(x: float, y: float, runs: Sequence[Run]) -> tuple[float, float]:
    """The point of the boundary ``runs`` closest to ``(x, y)`` (first run on ties)."""
    best, best_d2 = None, math.inf
    for x0, y0, x1, y1 in runs:
        qx = x0 if x < x0 else (x1 if x > x1 else x)
        qy = y0 if y < y0 else (y1 if y > y1 else y)
        d2 = (qx - x) ** 2 + (qy - y) ** 2
        if d2 < best_d2:
            best, best_d2 = (qx, qy), d2
    return best


def greedy_checkpoints(graph: Graph, route: Sequence[int], start, goal) -> np.ndarray:
    """Checkpoints ``(len(route), 2)`` along ``route`` (cells ``route[0] … route[-1]``), from ``start`` to ``goal``.

    Checkpoint ``i < len(route) - 1`` is the point of the boundary between ``route[i]`` and
    ``route[i+1]`` closest to checkpoint ``i - 1`` (to ``start`` for ``i = 0``); the last is ``goal``.
    """
    points = []
    x, y = float(start[0]), float(start[1])
    for a, b in zip(route[:-1], route[1:]):
        x, y = closest_point(x, y, graph.boundary[(a, b)])
        points.append((x, y))
    points.append((float(goal[0]), float(goal[1])))
    return np.array(points, dtype=float)


def path_length(start, checkpoints: np.ndarray) -> float:
    """Length (m) of the polyline from ``start`` through ``checkpoints`` ``(k, 2)``."""
    pts = np.vstack([np.asarray(start, dtype=float)[None, :2], np.asarray(checkpoints, dtype=float)])
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
