"""Coarseness of the slippery-cell labelling (thesis ch. 3.2.1-3.2.2; issue 12, item 5).

The property tests of ``test_planner_cells.py`` check that every cell is slippery and that the cells
partition the free bitmap cells. A plain grid — every free bitmap cell a cell of its own
(:func:`planner.bitmap.grid_cells`) — passes those checks too: a single bitmap cell is slippery. What
makes slippery cells worth having is that they are *few* ("much fewer cells or graph nodes than the
other approximate methods", ch. 3.3). The check added here: **no two adjacent cells could be merged into
one slippery cell**. :func:`label_slippery` grows each cell until every free neighbour would open a second
run in a row or column, and passes it; the plain grid fails it on any workspace with two free bitmap
cells side by side.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planner.bitmap import FREE, OCCUPIED, grid_cells
from planner.examples import fig_3_3, parse_map, random_bitmap
from planner.graph import adjacency
from planner.quadtree import label_quadtree
from planner.slippery import is_slippery, label_slippery


def mergeable_pairs(labels):
    """Adjacent cells (sharing an edge) whose union is one slippery cell."""
    g = adjacency(labels, 1.0)
    return [(a, b) for a, b in g.edges.tolist() if is_slippery((labels == a) | (labels == b))]


def check_slippery_labelling(W, labels):
    """The slippery-cell property checks: the cells partition the free bitmap cells into labels 1 … n, each
    cell is slippery (ch. 3.2.1), and the labelling is coarse — no two adjacent cells merge into one
    slippery cell."""
    free = W == FREE
    assert ((labels > 0) == free).all(), "labels must cover exactly the free cells"
    assert (labels[~free] == OCCUPIED).all()
    n = int(labels.max(initial=0))
    assert set(np.unique(labels[free]).tolist()) == set(range(1, n + 1)), "labels are 1 … n without gaps"
    for k in range(1, n + 1):
        assert is_slippery(labels == k), f"cell {k} is not slippery"
    pairs = mergeable_pairs(labels)
    assert not pairs, f"cells {pairs[0]} could be one slippery cell: the labelling is finer than slippery cells"


workspaces = st.tuples(st.integers(1, 14), st.integers(1, 14)).flatmap(
    lambda shape: arrays(np.int32, shape, elements=st.sampled_from([FREE, FREE, OCCUPIED])))


def has_two_free_neighbours(W):
    free = W == FREE
    return bool((free[:, 1:] & free[:, :-1]).any() or (free[1:, :] & free[:-1, :]).any())


@settings(max_examples=300, deadline=None, derandomize=True)
@given(W=workspaces, data=st.data())
def test_slippery_labelling_passes_the_coarseness_check(W, data):
    free = np.argwhere(W == FREE)
    seed = tuple(free[data.draw(st.integers(0, len(free) - 1))]) if len(free) else None
    check_slippery_labelling(W, label_slippery(W, seed))


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1), density=st.floats(0.0, 0.6))
def test_slippery_labelling_of_room_like_workspaces_passes_the_coarseness_check(seed, density):
    W = random_bitmap((40, 60), density, np.random.default_rng(seed), max_side=8)
    free = np.argwhere(W == FREE)
    check_slippery_labelling(W, label_slippery(W, tuple(free[len(free) // 2]) if len(free) else None))


@settings(max_examples=200, deadline=None, derandomize=True)
@given(W=workspaces)
def test_a_plain_grid_fails_the_coarseness_check_wherever_two_free_cells_touch(W):
    labels = grid_cells(W)
    for k in range(1, int(labels.max(initial=0)) + 1):
        assert is_slippery(labels == k)  # it passes the old per-cell checks ...
    if has_two_free_neighbours(W):
        with pytest.raises(AssertionError, match="finer than slippery cells"):  # ... but not this one
            check_slippery_labelling(W, labels)
    else:
        check_slippery_labelling(W, labels)  # isolated free cells: nothing to merge


def test_a_plain_grid_of_an_open_room_fails_and_its_slippery_labelling_is_one_cell():
    W = np.zeros((3, 4), np.int32)
    grid = grid_cells(W)
    assert grid.max() == 12 and (1, 2) in mergeable_pairs(grid)
    with pytest.raises(AssertionError, match="finer than slippery cells"):
        check_slippery_labelling(W, grid)
    slippery = label_slippery(W, (1, 1))
    assert slippery.tolist() == np.ones((3, 4), int).tolist()
    check_slippery_labelling(W, slippery)


def test_fig_3_3_three_cells_are_coarse_and_its_grid_and_quadtree_are_not():
    W, robot, _ = fig_3_3()
    check_slippery_labelling(W, label_slippery(W, robot))
    for finer in (grid_cells(W), label_quadtree(W)):
        assert mergeable_pairs(finer)
        with pytest.raises(AssertionError, match="finer than slippery cells"):
            check_slippery_labelling(W, finer)


def test_splitting_a_slippery_cell_in_two_fails_the_check():
    """The smallest finer labelling: one slippery cell cut in two."""
    W, marks = parse_map("""
        ######
        #....#
        #.X..#
        ######
    """.replace(" ", ""))
    labels = label_slippery(W, marks["X"])
    assert labels.max() == 1
    cut = labels.copy()
    cut[1:3, 3:5] = 2  # the right half of the room
    assert is_slippery(cut == 1) and is_slippery(cut == 2)
    with pytest.raises(AssertionError, match="finer than slippery cells"):
        check_slippery_labelling(W, cut)


def test_an_l_shaped_room_needs_no_more_than_one_cell():
    """An L is slippery (every row and column one run), so a coarse labelling of it has one cell."""
    W, marks = parse_map("""
        #####
        #X..#
        #.###
        #.###
        #####
    """.replace(" ", ""))
    assert label_slippery(W, marks["X"]).max() == 1
    assert label_slippery(W).max() == 1
