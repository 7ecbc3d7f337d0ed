"""Quadtree decomposition of a bitmap: the classical approximate cell decomposition baseline (docs/design.md §4).

The thesis compares slippery cells with octree decompositions (ch. 3.2.2, after Quinlan and Khatib
1993a and Faverjon 1984); in the plane that is the quadtree. To compare like with like, the quadtree
here decomposes the *same* padded bitmap as the slippery cells, so both are exact to the same resolution:

* the bitmap is embedded at its bottom-left corner in a square of side 2^k ≥ max(ny, nx) cells, the
  padding counting as occupied;
* a square block is a leaf when it is entirely free (a free leaf, one graph node) or entirely occupied;
  a mixed block is split into its four quadrants; single bitmap cells are never mixed, so the recursion
  bottoms out at the bitmap's resolution.

The tree is built bottom-up without recursion: level ``j`` holds whether each ``2^j``-block is all free,
computed from level ``j - 1`` by a 2×2 reduction; a free block is a leaf iff its parent block is not all
free. Labels are numbered from the largest leaves down, row-major within a level.
"""

from __future__ import annotations

import numpy as np

from planner.bitmap import FREE, OCCUPIED


def label_quadtree(W: np.ndarray) -> np.ndarray:
    """Label the free cells of the bitmap ``W`` ``(ny, nx)`` with the free leaves ``1 … n`` of its quadtree.

    Returns ``labels`` ``(ny, nx)`` int32: ``-1`` occupied, ``k >= 1`` the free leaf holding the cell.
    """
    W = np.asarray(W)
    ny, nx = W.shape
    side = 1 << max(0, int(np.ceil(np.log2(max(ny, nx)))))
    free = np.zeros((side, side), dtype=bool)
    free[:ny, :nx] = W == FREE
    levels = [free]  # levels[j][by, bx]: the 2^j-block (by, bx) is all free
    while levels[-1].shape[0] > 1:
        f = levels[-1]
        n = f.shape[0] // 2
        levels.append(f.reshape(n, 2, n, 2).all(axis=(1, 3)))

    labels = np.zeros((side, side), dtype=np.int32)
    next_label = 1
    for j in range(len(levels) - 1, -1, -1):
        leaf = levels[j].copy()
        if j + 1 < len(levels):
            parent_free = levels[j + 1]
            leaf &= ~np.repeat(np.repeat(parent_free, 2, axis=0), 2, axis=1)
        count = int(leaf.sum())
        if count == 0:
            continue
        ids = np.zeros(leaf.shape, dtype=np.int32)
        ids[leaf] = np.arange(next_label, next_label + count, dtype=np.int32)
        next_label += count
        block = 1 << j
        labels += np.repeat(np.repeat(ids, block, axis=0), block, axis=1)
    labels = labels[:ny, :nx]
    return np.where(W == FREE, labels, OCCUPIED).astype(np.int32)
