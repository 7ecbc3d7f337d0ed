"""Graph, greedy checkpoints (thesis ch. 3.2.3) and the exact route search (ch. 7.1.2)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planner import NoRouteError, plan_bitmap
from planner.bitmap import FREE, OCCUPIED
from planner.checkpoints import closest_point, greedy_checkpoints, path_length
from planner.examples import fig_3_3
from planner.graph import adjacency
from planner_checks import assert_checkpoints_on_shared_boundaries, flood


def test_graph_of_fig_3_3_is_a_chain_with_straight_boundaries():
    W, robot, _ = fig_3_3()
    from planner.slippery import label_slippery

    g = adjacency(label_slippery(W, robot), 1.0)
    assert g.n == 3
    assert g.edges.tolist() == [[1, 2], [2, 3]]
    assert g.boundary[(1, 2)] == ((7.0, 7.0, 13.0, 7.0),)  # below the strip cell 1 runs through the middle room
    assert g.boundary[(2, 3)] == ((14.0, 3.0, 19.0, 3.0),)
    assert g.boundary[(2, 1)] == g.boundary[(1, 2)]
    assert g.neighbours == {1: (2,), 2: (1, 3), 3: (2,)}


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


def test_disconnected_goal_raises_no_route():
    W = np.zeros((3, 5), np.int32)
    W[:, 2] = OCCUPIED
    with pytest.raises(NoRouteError, match="no route from start"):
        plan_bitmap(W, 1.0, (0.5, 0.5), (4.5, 0.5))


def all_routes(graph, a, b, limit=20000):
    """Every simple route from ``a`` to ``b`` (depth-first), at most ``limit``."""
    out, stack = [], [(a, (a,))]
    while stack and len(out) < limit:
        cell, route = stack.pop()
        if cell == b:
            out.append(route)
            continue
        stack.extend((n, route + (n,)) for n in graph.neighbours.get(cell, ()) if n not in route)
    return out


small = st.sampled_from(["slippery", "quadtree", "grid"]).flatmap(
    lambda m: st.tuples(st.just(m), arrays(np.int32, (5, 7) if m != "grid" else (3, 4),
                                           elements=st.sampled_from([FREE, FREE, FREE, OCCUPIED]))))


@settings(max_examples=150, deadline=None)
@given(case=small, data=st.data())
def test_search_finds_the_shortest_checkpoint_path_over_all_routes(case, data):
    """Brute force: the A* route is at least as short as every simple route's greedy checkpoint path, and
    its reported length is exactly its own checkpoint path's."""
    method, W = case
    free = np.argwhere(W == FREE)
    assume(len(free) >= 2)
    pick = lambda: tuple(free[data.draw(st.integers(0, len(free) - 1))])  # noqa: E731
    frac = st.floats(0.0, 0.999)
    (sy, sx), (gy, gx) = pick(), pick()
    start = (sx + data.draw(frac), sy + data.draw(frac))
    goal = (gx + data.draw(frac), gy + data.draw(frac))
    try:
        p = plan_bitmap(W, 1.0, start, goal, method)
    except NoRouteError:
        assert (gy, gx) not in flood(W, (sy, sx)), "a route exists through free bitmap cells"
        return
    routes = all_routes(p.graph, p.route[0], p.route[-1])
    assume(len(routes) < 20000)
    best = min(path_length(start, greedy_checkpoints(p.graph, r, start, goal)) for r in routes)
    assert p.length <= best + 1e-9
    if len(set(p.route)) == len(p.route):
        assert p.length == pytest.approx(best, abs=1e-9)
    assert_checkpoints_on_shared_boundaries(p)
