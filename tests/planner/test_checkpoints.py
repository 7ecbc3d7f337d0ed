"""The greedy checkpoint rule of thesis ch. 3.2.3 (planner.checkpoints): Fig. 3.6, closest points on the
boundaries, and a fixed case where it matters where distances are measured from (issue 12, item 5).

"From the start position, the closest point is found on the boundary between the current cell and the
next cell in the sequence. This point becomes the first checkpoint. The second checkpoint is found in
the same manner, except that the first checkpoint is now the position from which the distance is
calculated."
"""

import math

import numpy as np
import pytest

from planner import plan_bitmap
from planner.bitmap import FREE
from planner.checkpoints import closest_point, greedy_checkpoints, path_length
from planner.examples import fig_3_3, parse_map, random_bitmap
from planner.graph import adjacency
from tests.planner.checks import assert_checkpoints_on_shared_boundaries


def test_fig_3_6_two_checkpoints_between_x_and_y():
    W, robot, goal = fig_3_3()
    centre = lambda c: (c[1] + 0.5, c[0] + 0.5)  # noqa: E731
    p = plan_bitmap(W, 1.0, centre(robot), centre(goal))
    assert p.route == (1, 2, 3)
    assert p.checkpoints.tolist() == [[7.0, 7.0], [14.0, 3.0], [16.5, 4.5]]
    assert_checkpoints_on_shared_boundaries(p)


def test_closest_point_clamps_to_runs_and_breaks_ties_by_run_order():
    runs = ((0.0, 0.0, 0.0, 2.0), (3.0, 1.0, 5.0, 1.0))
    assert closest_point(-1.0, 1.0, runs) == (0.0, 1.0)
    assert closest_point(4.0, 3.0, runs) == (4.0, 1.0)
    assert closest_point(1.5, 1.0, runs) == (0.0, 1.0)  # equidistant: first run


def test_start_and_goal_in_one_cell_need_no_checkpoint_but_the_goal():
    W = np.zeros((4, 4), np.int32)
    p = plan_bitmap(W, 1.0, (0.5, 0.5), (3.5, 2.5))
    assert p.route == (1,) and p.checkpoints.tolist() == [[3.5, 2.5]]
    assert p.length == pytest.approx(math.hypot(3, 2))


# -------------------------------------------------------------------- measured from the previous checkpoint

# Cell size 1, row 0 at the bottom (labels[iy, ix]); -1 occupied.
#
#   y 3..4   A A B #
#   y 2..3   A A B #
#   y 1..2   # B B #
#   y 0..1   # C C #
#
# A = 1 (x 0..2, y 2..4), B = 2 (an L: x 2..3, y 1..4 and x 1..2, y 1..2), C = 3 (x 1..3, y 0..1).
# Boundary A|B: x = 2 for y 2..4, and y = 2 for x 1..2. Boundary B|C: y = 1 for x 1..3.
LABELS = np.array([
    [-1, 3, 3, -1],
    [-1, 2, 2, -1],
    [1, 1, 2, -1],
    [1, 1, 2, -1],
], dtype=np.int32)
START = (0.5, 3.5)  # in A
GOAL = (2.5, 0.5)  # in C


def test_the_fixed_case_has_the_boundaries_drawn_above():
    g = adjacency(LABELS, 1.0)
    assert g.edges.tolist() == [[1, 2], [2, 3]]
    assert set(g.boundary[(1, 2)]) == {(2.0, 2.0, 2.0, 4.0), (1.0, 2.0, 2.0, 2.0)}
    assert g.boundary[(2, 3)] == ((1.0, 1.0, 3.0, 1.0),)


def test_second_checkpoint_is_measured_from_the_first_checkpoint_not_from_the_start():
    g = adjacency(LABELS, 1.0)
    cps = greedy_checkpoints(g, (1, 2, 3), START, GOAL)
    # 1st: nearest point of A|B to the start (0.5, 3.5): (2, 3.5) at 1.5 (the corner (1, 2) is at 1.58).
    # 2nd: nearest point of B|C (y = 1, x 1..3) to (2, 3.5): (2, 1). From the start it would be (1, 1).
    assert cps.tolist() == [[2.0, 3.5], [2.0, 1.0], [2.5, 0.5]]
    from_start = closest_point(*START, g.boundary[(2, 3)])
    assert from_start == (1.0, 1.0) and tuple(cps[1]) != from_start
    assert path_length(START, cps) == pytest.approx(1.5 + 2.5 + math.hypot(0.5, 0.5))


ROOMS = """
#########
#G.#.S..#
#..#....#
##.#....#
#..#....#
#.......#
#.......#
#########
"""


def test_a_planned_route_through_rooms_measures_each_checkpoint_from_the_previous_one():
    """The same rule through the planner's front door (slippery cells, Fig. 3.5). The labelling is

         .  .  .  .  .  .  .  .  .
         .  3  2  .  1  1  1  1  .      cell 3: x 1..2, y 5..7 (the goal's corner)
         .  3  2  .  1  1  1  1  .      cell 2: the column x 2..3 and the row x 1..3, y 3..4
         .  .  2  .  1  1  1  1  .      cell 1: the right room and the bottom strip
         .  2  2  .  1  1  1  1  .
         .  1  1  1  1  1  1  1  .
         .  1  1  1  1  1  1  1  .

    Route 1, 2, 3. Checkpoint 1: the point of 1|2 (y = 3, x 1..3) nearest the start (5.5, 6.5) is (3, 3).
    Checkpoint 2: the point of 2|3 (x = 2, y 5..7) nearest (3, 3) is (2, 5); nearest the start it
    would be (2, 6.5).
    """
    W, marks = parse_map(ROOMS)
    (sy, sx), (gy, gx) = marks["S"], marks["G"]
    p = plan_bitmap(W, 1.0, (sx + 0.5, sy + 0.5), (gx + 0.5, gy + 0.5), "slippery")
    assert p.route == (1, 2, 3)
    assert p.graph.boundary[(1, 2)] == ((1.0, 3.0, 3.0, 3.0),) and p.graph.boundary[(2, 3)] == ((2.0, 5.0, 2.0, 7.0),)
    assert p.checkpoints.tolist() == [[3.0, 3.0], [2.0, 5.0], [1.5, 6.5]]
    assert closest_point(*p.start, p.graph.boundary[(2, 3)]) == (2.0, 6.5)  # the rule measured from the start
    assert p.length == pytest.approx(math.hypot(2.5, 3.5) + math.hypot(1, 2) + math.hypot(0.5, 1.5))
    assert_greedy_from_previous(p)


def brute_closest(point, labels, a, b, cell):
    """Distance from ``point`` to the boundary shared by cells ``a`` and ``b``, over every unit edge between
    a bitmap cell labelled ``a`` and one labelled ``b`` (independently of planner.graph)."""
    px, py = point
    best = math.inf
    ny, nx = labels.shape
    for iy in range(ny):
        for ix in range(nx):
            for jy, jx, seg in ((iy, ix + 1, ((ix + 1, iy), (ix + 1, iy + 1))),
                                (iy + 1, ix, ((ix, iy + 1), (ix + 1, iy + 1)))):
                if jy < ny and jx < nx and {labels[iy, ix], labels[jy, jx]} == {a, b}:
                    (x0, y0), (x1, y1) = (np.asarray(seg, float) * cell)
                    qx, qy = min(max(px, x0), x1), min(max(py, y0), y1)
                    best = min(best, math.hypot(qx - px, qy - py))
    return best


def assert_greedy_from_previous(p):
    prev = p.start
    for i, (a, b) in enumerate(zip(p.route[:-1], p.route[1:])):
        cp = tuple(p.checkpoints[i])
        want = brute_closest(prev, p.labels, a, b, p.cell)
        assert math.hypot(cp[0] - prev[0], cp[1] - prev[1]) == pytest.approx(want, abs=1e-9), (i, prev, cp)
        assert brute_closest(cp, p.labels, a, b, p.cell) == pytest.approx(0.0, abs=1e-9)  # on the boundary
        prev = cp
    assert tuple(p.checkpoints[-1]) == p.goal


def test_fig_3_6_checkpoints_follow_the_rule():
    W, robot, goal = fig_3_3()
    p = plan_bitmap(W, 1.0, (robot[1] + 0.5, robot[0] + 0.5), (goal[1] + 0.5, goal[0] + 0.5))
    assert_greedy_from_previous(p)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("method", ["slippery", "quadtree", "grid"])
def test_checkpoints_follow_the_rule_on_random_workspaces(seed, method):
    rng = np.random.default_rng(seed)
    W = random_bitmap((12, 16), 0.3, rng, max_side=4)
    free = np.argwhere(W == FREE)
    (sy, sx), (gy, gx) = free[0], free[-1]
    try:
        p = plan_bitmap(W, 1.0, (sx + 0.3, sy + 0.6), (gx + 0.7, gy + 0.2), method)
    except Exception as e:  # noqa: BLE001  (a workspace without a route says nothing here)
        pytest.skip(f"no plan: {e}")
    assert_greedy_from_previous(p)


def test_path_length_starts_at_the_position_of_a_pose():
    """``start`` may be a pose (x, y, θ): only its position counts."""
    assert path_length((0.0, 0.0, 2.5), np.array([[3.0, 4.0], [3.0, 6.0]])) == pytest.approx(7.0)
    assert path_length((0.0, 0.0), np.array([[3.0, 4.0]])) == pytest.approx(5.0)
