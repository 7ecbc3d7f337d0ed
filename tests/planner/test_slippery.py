"""Slippery cells (planner.slippery; thesis ch. 3.2.1-3.2.2, Fig. 3.3–3.5): the inputs the labelling refuses,
small labellings and the three rooms of Fig. 3.3 worked out by hand (issue 12, item 5), the property checks
on random workspaces, and the coarseness of the labelling."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.bitmap import FREE, OCCUPIED, grid_cells
from planner.examples import fig_3_3, format_labels, parse_map, random_bitmap
from planner.graph import adjacency
from planner.quadtree import label_quadtree
from planner.slippery import is_slippery, label_slippery
from tests.planner.checks import check_decomposition, workspaces


# ----------------------------------------------------------------------- refused inputs, labellings by hand

@pytest.mark.parametrize("seed", [(3, 0), (0, 4), (-1, 0), (0, -1), (3, 4), (-1, 9)])
def test_a_seed_outside_the_bitmap_is_refused(seed):
    W = np.zeros((3, 4), np.int32)  # every cell free, so only the bounds can refuse it
    with pytest.raises(ValueError, match=r"^seed \(-?\d+, -?\d+\) is not a free cell of the 3 x 4 bitmap$"):
        label_slippery(W, seed)


def test_an_occupied_seed_is_refused():
    W = np.zeros((3, 4), np.int32)
    W[1, 2] = OCCUPIED
    with pytest.raises(ValueError, match=r"^seed \(1, 2\) is not a free cell of the 3 x 4 bitmap$"):
        label_slippery(W, (1, 2))


@pytest.mark.parametrize("shape", [(4,), (2, 2, 2)])
def test_a_bitmap_that_is_not_2_d_is_refused(shape):
    with pytest.raises(ValueError, match=r"^W must be a 2-D bitmap, got shape \("):
        label_slippery(np.zeros(shape, np.int32))


def test_the_corner_seeds_are_accepted():
    W = np.zeros((3, 4), np.int32)
    for seed in ((0, 0), (2, 3), (0, 3), (2, 0)):
        assert label_slippery(W, seed).tolist() == np.ones((3, 4), int).tolist()


def test_a_u_is_cut_where_a_column_would_get_a_second_run():
    """A U seeded at the bottom of its left arm: cell 1 grows up the left arm and along the bottom row;
    the right arm above the bottom would give the upper rows a second run each (left and right arm), so
    it is refused and becomes cell 2 (ch. 3.2.1: an outward normal from the left arm would re-enter)."""
    W, marks = parse_map("""
        #####
        #.#.#
        #.#.#
        #X..#
        #####
    """.replace(" ", ""))
    labels = label_slippery(W, marks["X"])
    assert format_labels(labels) == "\n".join([
        " -1 -1 -1 -1 -1",
        " -1  1 -1  2 -1",
        " -1  1 -1  2 -1",
        " -1  1  1  1 -1",
        " -1 -1 -1 -1 -1"])
    assert is_slippery(labels == 1) and is_slippery(labels == 2)
    assert not is_slippery(labels > 0)


def test_a_ring_around_a_pillar_needs_more_than_one_cell_and_each_is_slippery():
    W, marks = parse_map("""
        #####
        #...#
        #.#.#
        #X..#
        #####
    """.replace(" ", ""))
    labels = label_slippery(W, marks["X"])
    assert labels.max() == 2
    for k in (1, 2):
        assert is_slippery(labels == k)
    assert labels[marks["X"]] == 1


# ------------------------------------------------------------------------------------------------- Fig. 3.3

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


# ----------------------------------------------------------------------------------------------- properties

@settings(max_examples=300, deadline=None)
@given(W=workspaces, data=st.data())
def test_slippery_cells_are_slippery_and_partition_the_free_cells(W, data):
    free = np.argwhere(W == FREE)
    seed = tuple(free[data.draw(st.integers(0, len(free) - 1))]) if len(free) else None
    labels = label_slippery(W, seed)
    check_decomposition(W, labels)
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
    check_decomposition(W, labels)
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


def test_slippery_cells_are_fewer_than_quadtree_leaves_on_the_fig_3_3_workspace():
    W, robot, _ = fig_3_3()
    assert label_slippery(W, robot).max() < label_quadtree(W).max()


# ----------------------------------------------------------------------------------------------- coarseness

# The property tests above check that every cell is slippery and that the cells partition the free bitmap
# cells. A plain grid — every free bitmap cell a cell of its own (planner.bitmap.grid_cells) — passes
# those checks too: a single bitmap cell is slippery. What makes slippery cells worth having is that they
# are *few* ("much fewer cells or graph nodes than the other approximate methods", ch. 3.3). The check
# here: **no two adjacent cells could be merged into one slippery cell**. label_slippery grows each cell
# until every free neighbour would open a second run in a row or column, and passes it; the plain grid
# fails it on any workspace with two free bitmap cells side by side.

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
