"""The connectivity graph of a cell decomposition and the boundaries its arcs cross (thesis ch. 3.2.3).

"The graph nodes represent the slippery cells and the graph arcs represent the adjacent cells." Two
cells are adjacent when a bitmap cell of one shares an edge (not just a corner) with a bitmap cell of
the other. The boundary between them is the union of those unit edges, merged into maximal straight
runs; every point of it lies on the closed squares of two free bitmap cells and hence in free space.

The graph is built from any ``labels`` array (slippery cells, quadtree leaves or the grid itself), so
the three decompositions share the graph, the search and the checkpoint rule.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: An axis-aligned piece of boundary ``(x0, y0, x1, y1)`` in metres, with ``x0 <= x1`` and ``y0 <= y1``.
Run = tuple[float, float, float, float]


@dataclass(frozen=True)
class Graph:
    """Connectivity graph of a decomposition with ``n`` cells labelled ``1 … n``.

    ``edges`` ``(E, 2)`` int: adjacent pairs ``(a, b)``, ``a < b``, sorted. ``boundary[(a, b)]`` (either
    order) is the shared boundary as straight runs; ``neighbours[a]`` the cells adjacent to ``a``.
    """

    n: int
    edges: np.ndarray
    boundary: dict[tuple[int, int], tuple[Run, ...]]
    neighbours: dict[int, tuple[int, ...]]


def adjacency(labels: np.ndarray, cell: float) -> Graph:
    """The connectivity graph of the decomposition ``labels`` ``(ny, nx)`` on a grid of ``cell`` metres."""
    labels = np.asarray(labels)
    runs: dict[tuple[int, int], list[Run]] = {}
    # Cells side by side along a row share a vertical edge (x fixed); cells stacked in a column a
    # horizontal one (y fixed): the same scan on the transposed labels.
    for a, b, line, lo, hi in _unit_edges(labels):
        runs.setdefault((a, b), []).append((line * cell, lo * cell, line * cell, hi * cell))
    for a, b, line, lo, hi in _unit_edges(labels.T):
        runs.setdefault((a, b), []).append((lo * cell, line * cell, hi * cell, line * cell))
    boundary: dict[tuple[int, int], tuple[Run, ...]] = {}
    neighbours: dict[int, list[int]] = {}
    for a, b in sorted(runs):
        boundary[(a, b)] = boundary[(b, a)] = tuple(sorted(runs[(a, b)]))
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    edges = np.array(sorted(runs), dtype=np.int64).reshape(-1, 2)
    return Graph(n=int(labels.max(initial=0)), edges=edges, boundary=boundary,
                 neighbours={k: tuple(sorted(v)) for k, v in neighbours.items()})


def _unit_edges(labels: np.ndarray) -> list[tuple[int, int, int, int, int]]:
    """Maximal runs of unit edges between differently labelled free cells that are neighbours along a row.

    For ``labels`` ``(rows, cols)``, the edge between ``(r, c)`` and ``(r, c+1)`` sits at column line
    ``c + 1`` and spans rows ``r … r+1``. Returns ``(a, b, line, r0, r1)`` with ``a < b``: the run of
    consecutive rows ``r0 … r1`` on column line ``line`` between cells ``a`` and ``b``.
    """
    left, right = labels[:, :-1], labels[:, 1:]
    r, c = np.nonzero((left > 0) & (right > 0) & (left != right))
    if r.size == 0:
        return []
    a = np.minimum(left[r, c], right[r, c]).astype(np.int64)
    b = np.maximum(left[r, c], right[r, c]).astype(np.int64)
    line = c + 1
    order = np.lexsort((r, line, b, a))
    a, b, line, r = a[order], b[order], line[order], r[order]
    same = (a[1:] == a[:-1]) & (b[1:] == b[:-1]) & (line[1:] == line[:-1]) & (r[1:] == r[:-1] + 1)
    start = np.flatnonzero(np.concatenate([[True], ~same]))
    end = np.concatenate([start[1:], [r.size]]) - 1
    return list(zip(a[start].tolist(), b[start].tolist(), line[start].tolist(),
                    r[start].tolist(), (r[end] + 1).tolist()))
