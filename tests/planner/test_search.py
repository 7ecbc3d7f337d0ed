"""The route search (planner.search; thesis ch. 7.1.2): on graphs built by hand, with the lengths worked out by
hand (issue 12, item 5), and against a brute-force search over all routes."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planner import NoRouteError, plan_bitmap
from planner.bitmap import FREE, OCCUPIED
from planner.checkpoints import greedy_checkpoints, path_length
from planner.examples import fig_3_3
from planner.graph import Graph
from planner.search import shortest_route
from tests.planner.checks import assert_checkpoints_on_shared_boundaries, flood


def graph(boundaries):
    """A :class:`Graph` from ``{(a, b): runs}`` (a < b)."""
    boundary, neighbours = {}, {}
    for (a, b), runs in boundaries.items():
        boundary[(a, b)] = boundary[(b, a)] = tuple(runs)
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    return Graph(n=max(neighbours), edges=np.array(sorted(boundaries)), boundary=boundary,
                 neighbours={k: tuple(sorted(v)) for k, v in neighbours.items()})


# Start (0, 0) in cell 1, goal (4, 0) in cell 3. 1|3 is the segment x = 1, y -1..1; 1|2 the point (0.5, 0);
# 2|3 the point (2, 0). Route 1, 3: checkpoints (1, 0), goal: 1 + 3 = 4. Route 1, 2, 3: (0.5, 0), (2, 0),
# goal: 0.5 + 1.5 + 2 = 4 as well — two routes of the same length, reaching cell 3 with different costs so far.
TIE = graph({(1, 3): [(1.0, -1.0, 1.0, 1.0)], (1, 2): [(0.5, 0.0, 0.5, 0.0)], (2, 3): [(2.0, 0.0, 2.0, 0.0)]})


def test_two_equally_short_routes_give_one_route_of_that_length():
    route = shortest_route(TIE, 1, (0.0, 0.0), 3, (4.0, 0.0))
    assert route.length == pytest.approx(4.0)
    assert route.cells == (1, 3)  # the one completed first (fewer cells); a later one as short does not replace it


def test_the_shorter_of_two_routes_wins_and_its_length_is_its_checkpoint_path():
    # Move 2|3 off the line: route 1, 2, 3 becomes 0.5 + hypot(1.5, 1) + hypot(2, 1) = 4.539 > 4.
    g = graph({(1, 3): [(1.0, -1.0, 1.0, 1.0)], (1, 2): [(0.5, 0.0, 0.5, 0.0)], (2, 3): [(2.0, 1.0, 2.0, 1.0)]})
    route = shortest_route(g, 1, (0.0, 0.0), 3, (4.0, 0.0))
    assert route.cells == (1, 3) and route.length == pytest.approx(4.0)
    # Block 1|3 further out: 1, 3 costs hypot(1, 3) + hypot(3, 3) = 7.405; 1, 2, 3 costs 4.539 and wins.
    g = graph({(1, 3): [(1.0, 3.0, 1.0, 4.0)], (1, 2): [(0.5, 0.0, 0.5, 0.0)], (2, 3): [(2.0, 1.0, 2.0, 1.0)]})
    route = shortest_route(g, 1, (0.0, 0.0), 3, (4.0, 0.0))
    assert route.cells == (1, 2, 3)
    assert route.length == pytest.approx(0.5 + math.hypot(1.5, 1.0) + math.hypot(2.0, 1.0))


def test_start_and_goal_in_one_cell_is_a_route_of_that_cell():
    route = shortest_route(TIE, 2, (0.5, 0.0), 2, (1.5, 1.0))
    assert route.cells == (2,) and route.length == pytest.approx(math.hypot(1.0, 1.0))


def test_no_route_between_cells_that_do_not_connect():
    g = graph({(1, 2): [(0.5, 0.0, 0.5, 0.0)], (3, 4): [(2.0, 0.0, 2.0, 0.0)]})
    assert shortest_route(g, 1, (0.0, 0.0), 4, (3.0, 0.0)) is None


@pytest.mark.parametrize("method", ["slippery", "quadtree", "grid"])
def test_the_reported_length_is_the_greedy_checkpoint_path_of_the_route(method):
    W, robot, goal = fig_3_3()
    start, end = (robot[1] + 0.5, robot[0] + 0.5), (goal[1] + 0.5, goal[0] + 0.5)
    p = plan_bitmap(W, 1.0, start, end, method)
    route = shortest_route(p.graph, p.route[0], start, p.route[-1], end)
    assert route.cells == p.route
    assert route.length == pytest.approx(path_length(start, greedy_checkpoints(p.graph, route.cells, start, end)))
    assert route.length == pytest.approx(p.length)


def test_disconnected_goal_raises_no_route():
    W = np.zeros((3, 5), np.int32)
    W[:, 2] = OCCUPIED
    with pytest.raises(NoRouteError, match="no route from start"):
        plan_bitmap(W, 1.0, (0.5, 0.5), (4.5, 0.5))


# ---------------------------------------------------------------------------------------------- brute force

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
