"""The quadtree baseline (planner.quadtree): its leaves are maximal aligned free squares that partition the
free cells."""

import numpy as np
from hypothesis import given, settings

from planner.bitmap import FREE
from planner.quadtree import label_quadtree
from tests.planner.checks import check_decomposition, workspaces


@settings(max_examples=200, deadline=None)
@given(W=workspaces)
def test_quadtree_leaves_are_maximal_aligned_free_squares_partitioning_the_free_cells(W):
    labels = label_quadtree(W)
    check_decomposition(W, labels)
    side = 1 << int(np.ceil(np.log2(max(W.shape))))
    padded = np.full((side, side), False)
    padded[: W.shape[0], : W.shape[1]] = W == FREE
    for k in range(1, labels.max(initial=0) + 1):
        iy, ix = np.nonzero(labels == k)
        size = iy.max() - iy.min() + 1
        assert size == ix.max() - ix.min() + 1 and len(iy) == size * size, "a leaf is a full square"
        assert size & (size - 1) == 0 and iy.min() % size == 0 and ix.min() % size == 0, "aligned power of 2"
        if size < side:  # maximal: the parent block is not all free
            py, px = iy.min() // (2 * size) * 2 * size, ix.min() // (2 * size) * 2 * size
            assert not padded[py:py + 2 * size, px:px + 2 * size].all()
