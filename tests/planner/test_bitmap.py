"""Padded bitmap (thesis ch. 3.2.2, Fig. 3.2b/3.3a): conservative free cells, exact square distances."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ekm.errors import InputError
from planner.bitmap import (FREE, MAX_CELLS, OCCUPIED, cell_squares, free_cell_at, padded_obstacles, rasterise,
                            square_distance)
from robots.geometry import Box, Circle, Polygon, Segment, distance
from robots.worldnames import load_world

coord = st.floats(-1.0, 1.0, allow_nan=False)
positive = st.floats(0.02, 0.6, allow_nan=False)
shapes = st.one_of(
    st.builds(lambda c, r: Circle(c, r), st.tuples(coord, coord), positive),
    st.builds(lambda c, s, a: Box(c, s, a), st.tuples(coord, coord), st.tuples(positive, positive),
              st.floats(-math.pi, math.pi)),
    st.builds(lambda a, b: Segment(a, b), st.tuples(coord, coord), st.tuples(coord, coord))
    .filter(lambda s: s.start != s.end),
    # a concave "L"-ish polygon, scaled and shifted
    st.builds(lambda c, k: Polygon(tuple((c[0] + k * x, c[1] + k * y) for x, y in
                                         [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])),
              st.tuples(coord, coord), positive),
)


@settings(max_examples=150, deadline=None)
@given(shape=shapes, lo=st.tuples(coord, coord), side=st.floats(0.01, 0.5))
def test_square_distance_matches_dense_sampling(shape, lo, side):
    """The exact square-to-shape distance lies between a dense sample's minimum and that minimum less the
    sampling radius (distance is 1-Lipschitz)."""
    lo = np.asarray(lo)
    exact = float(square_distance(lo, lo + side, shape))
    n = 41
    u = np.linspace(0.0, side, n)
    pts = lo + np.stack(np.meshgrid(u, u), -1).reshape(-1, 2)
    sampled = float(distance(pts, shape).min())
    spacing = side / (n - 1) * math.sqrt(0.5)
    assert exact <= sampled + 1e-9
    assert exact >= sampled - spacing - 1e-9


def test_free_cells_lie_entirely_in_free_space_on_every_named_world():
    """Conservative bitmap: a dense sample of every free cell stays at least the padding from every wall
    (half thickness counted) and obstacle, as measured independently by World.clearance."""
    for name in ("three-rooms", "three-rooms-changed", "open-arena"):
        world = load_world(name)
        for t in (0.0, 10.0):
            W = rasterise(padded_obstacles(world, t, 0.025), world.size, 0.03)
            lo, _ = cell_squares(W.shape, 0.03)
            u = np.linspace(0.0, 0.03, 7)
            offsets = np.stack(np.meshgrid(u, u), -1).reshape(-1, 2)
            pts = (lo[W == FREE][:, None, :] + offsets).reshape(-1, 2)
            assert len(pts) > 0
            assert world.clearance(pts, t, include_moving=False).min() >= 0.025 - 1e-9


def test_doorways_of_three_rooms_stay_open_at_the_default_cell_size():
    world = load_world("three-rooms")
    W = rasterise(padded_obstacles(world, 0.0, 0.025), world.size, 0.02)
    assert W.shape == (30, 60)
    # column of cells centred on the wall at x = 0.4 (0.38 … 0.40): only the doorway 0.24 … 0.36 less the cushion
    free_rows = np.flatnonzero(W[:, 19] == FREE)
    assert free_rows.tolist() == [14, 15]  # y in [0.28, 0.32]
    free_rows = np.flatnonzero(W[:, 39] == FREE)
    assert free_rows.tolist() == [7, 8]  # y in [0.14, 0.18], the lower doorway 0.10 … 0.22 at x = 0.8


def test_known_event_enters_the_map_only_after_it_happens():
    world = load_world("three-rooms-changed")
    before = rasterise(padded_obstacles(world, 5.9, 0.025), world.size, 0.02)
    after = rasterise(padded_obstacles(world, 6.0, 0.025), world.size, 0.02)
    assert (before[:, 39] == FREE).any() and set(np.flatnonzero(before[:, 39] == FREE)) == {7, 8, 22, 23}
    assert set(np.flatnonzero(after[:, 39] == FREE)) == {22, 23}


def test_cells_beyond_the_arena_are_occupied():
    """A cell size that does not divide the arena leaves a partial last column, which is not free space."""
    W = rasterise((), (1.0, 1.0), 0.3)  # no obstacles; 1 m / 0.3 m: 4 columns, the last partial
    assert W.shape == (4, 4)
    assert (W[:, 3] == OCCUPIED).all() and (W[3, :] == OCCUPIED).all()
    assert (W[:3, :3] == FREE).all()


@pytest.mark.parametrize("cell", [0.0, -0.1, math.nan, math.inf])
def test_bad_cell_size_is_an_input_error(cell):
    with pytest.raises(InputError, match="cell size"):
        rasterise((), (1.0, 1.0), cell)


def test_too_fine_a_grid_is_refused():
    with pytest.raises(InputError, match=f"more than {MAX_CELLS:,}"):
        rasterise((), (1.0, 1.0), 1e-4)


def test_free_cell_at_prefers_the_own_cell_then_the_nearest_free_neighbour():
    W = np.full((3, 3), OCCUPIED)
    W[1, 2] = FREE
    W[2, 2] = FREE
    assert free_cell_at(W, (2.5, 1.5), 1.0) == (1, 2)  # own cell free
    assert free_cell_at(W, (1.9, 1.5), 1.0) == (1, 2)  # occupied own cell, free neighbour 0.1 away
    assert free_cell_at(W, (0.5, 0.5), 1.0) is None  # nearest free square more than a cell away
