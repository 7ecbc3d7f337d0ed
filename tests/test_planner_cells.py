"""Cell decompositions: slippery cells (thesis Fig. 3.3–3.5), quadtree and grid baselines."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planner import decompose
from planner.bitmap import FREE, OCCUPIED
from planner.examples import fig_3_3, format_labels, parse_map, random_bitmap
from planner.quadtree import label_quadtree
from planner.slippery import is_slippery, label_slippery

FIG_3_3_LABELS = """\
 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1
 -1  1  1  1  1  1  1  1  1  1  1  1  1 -1  3  3  3  3  3 -1
 -1  1  1  1  1  1  1  1  1  1  1  1  1 -1  3  3  3  3  3 -1
 -1  1  1  1  1  1 -1  2  2  2  2  2  2 -1  3  3  3  3  3 -1
 -1  1  X  1  1  1 -1  2  2  2  2  2  2 -1  3  3  3  3  3 -1
 -1  1  1  1  1  1 -1  2  2  2  2  2  2 -1  3  3  3  3  3 -1
 -1  1  1  1  1  1 -1  2  2  2  2  2  2 -1  3  3  3  3  3 -1
 -1  1  1  1  1  1 -1  2  2  2  2  2  2  2  2  2  2  2  2 -1
 -1  1  1  1  1  1 -1  2  2  2  2  2  2  2  2  2  2  2  2 -1
 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1"""


def test_fig_3_3_three_rooms_give_three_slippery_cells():
    W, robot, _ = fig_3_3()
    assert W.shape == (10, 20)
    labels = label_slippery(W, robot)
    assert labels.max() == 3
    assert format_labels(labels, {robot: "X"}) == FIG_3_3_LABELS
    assert labels[robot] == 1  # "the labeling of the first slippery cell '1' starts at ... 'X'"


def test_fig_3_3_count_does_not_depend_on_where_the_robot_stands_in_its_room():
    W, _, _ = fig_3_3()
    for iy in range(1, 9):
        for ix in range(1, 6):
            assert label_slippery(W, (iy, ix)).max() == 3


def test_fig_3_3_bitmap_prints_as_in_fig_3_3a():
    W, robot, _ = fig_3_3()
    text = format_labels(W, {robot: "X"})
    lines = text.splitlines()
    assert len(lines) == 10 and lines[0] == " -1" * 20
    assert lines[1] == " -1" + "  0" * 12 + " -1" + "  0" * 5 + " -1"  # top doorway through the first wall
    assert lines[4].split()[2] == "X"


def test_a_doorway_halfway_up_the_first_wall_splits_the_middle_room():
    """Why the count depends on the layout: the first cell runs a strip through the doorway into the next
    room (its columns are still empty there), cutting that room in two."""
    W, marks = parse_map("""
        #########
        #...#...#
        #.X.....#
        #...#...#
        #########
    """.replace(" ", ""))
    labels = label_slippery(W, marks["X"])
    assert labels.max() == 3
    assert len(set(labels[1:4, 5:8].ravel())) == 3  # strip of cell 1, and the rooms' halves above and below


def _check_decomposition(W, labels):
    free = W == FREE
    assert ((labels > 0) == free).all(), "labels must cover exactly the free cells"
    assert (labels[~free] == OCCUPIED).all()
    n = labels.max(initial=0)
    assert set(np.unique(labels[free]).tolist()) == set(range(1, n + 1)), "labels are 1 … n without gaps"


workspaces = st.tuples(st.integers(1, 14), st.integers(1, 14)).flatmap(
    lambda shape: arrays(np.int32, shape, elements=st.sampled_from([FREE, FREE, OCCUPIED])))


@settings(max_examples=300, deadline=None)
@given(W=workspaces, data=st.data())
def test_slippery_cells_are_slippery_and_partition_the_free_cells(W, data):
    free = np.argwhere(W == FREE)
    seed = tuple(free[data.draw(st.integers(0, len(free) - 1))]) if len(free) else None
    labels = label_slippery(W, seed)
    _check_decomposition(W, labels)
    for k in range(1, labels.max(initial=0) + 1):
        assert is_slippery(labels == k), f"cell {k} is not slippery:\n{format_labels(labels)}"
    if seed is not None:
        assert labels[seed] == 1


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), density=st.floats(0.0, 0.6))
def test_slippery_cells_on_random_room_like_workspaces(seed, density):
    W = random_bitmap((40, 60), density, np.random.default_rng(seed), max_side=8)
    free = np.argwhere(W == FREE)
    labels = label_slippery(W, tuple(free[len(free) // 2]) if len(free) else None)
    _check_decomposition(W, labels)
    for k in range(1, labels.max(initial=0) + 1):
        assert is_slippery(labels == k)


def test_is_slippery_rejects_gapped_rows_columns_and_disconnected_sets():
    assert is_slippery(np.array([[1, 1, 1], [0, 1, 0]], bool))  # a T is slippery
    assert not is_slippery(np.array([[1, 1, 1], [1, 0, 1]], bool))  # a U: its second row has a gap
    assert not is_slippery(np.array([[1, 0], [0, 1]], bool))  # runs fine, not 4-connected
    assert not is_slippery(np.zeros((2, 2), bool))


def test_a_cell_connected_both_ways_joins_against_the_printed_pseudo_code():
    """Fig. 3.4b: a cell touching cell 1 horizontally and vertically joins. In an open 2 × 2 block seeded at
    the bottom-left, the top-right cell is reached last, connected both ways, with its column already
    holding cell 1; Fig. 3.5 as printed returns the column test and would make it a second cell."""
    W = np.zeros((2, 2), np.int32)
    assert label_slippery(W, (0, 0)).tolist() == [[1, 1], [1, 1]]


@settings(max_examples=200, deadline=None)
@given(W=workspaces)
def test_quadtree_leaves_are_maximal_aligned_free_squares_partitioning_the_free_cells(W):
    labels = label_quadtree(W)
    _check_decomposition(W, labels)
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


@pytest.mark.parametrize("method", ["slippery", "quadtree", "grid"])
def test_every_decomposition_labels_exactly_the_free_cells(method):
    W = random_bitmap((30, 50), 0.3, np.random.default_rng(7))
    _check_decomposition(W, decompose(W, method, tuple(np.argwhere(W == FREE)[0])))


def test_grid_makes_one_cell_per_free_bitmap_cell():
    W = random_bitmap((30, 50), 0.3, np.random.default_rng(3))
    assert decompose(W, "grid").max() == (W == FREE).sum()


def test_slippery_cells_are_fewer_than_quadtree_leaves_on_the_fig_3_3_workspace():
    W, robot, _ = fig_3_3()
    assert label_slippery(W, robot).max() < label_quadtree(W).max()
