"""Slippery-cell labelling (planner.slippery): the inputs it refuses, and small labellings worked out by hand
(thesis ch. 3.2.1-3.2.2, Fig. 3.4, 3.5; issue 12, item 5)."""

import numpy as np
import pytest

from planner.bitmap import OCCUPIED
from planner.examples import format_labels, parse_map
from planner.slippery import is_slippery, label_slippery


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
