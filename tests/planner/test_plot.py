"""What the plan plot draws (planner.plot): the route through the route's cells, which never crosses a wall,
beside the thesis's straight checkpoint legs, which may."""

import numpy as np

from planner.plan import plan
from planner.checkpoints import path_length
from planner.plot import route_through_cells
from robots.worldfile import parse_world

#: Start and goal in one L-shaped slippery cell, a wall between them (the issue's case).
L_WORLD = {"name": "L", "size": [1.0, 1.0], "walls": [[0.3, 0.0, 0.3, 0.7], [0.3, 0.7, 1.0, 0.7]],
           "start": [0.15, 0.15, 1.57], "goal": [0.8, 0.85]}


def crosses(p, q, a, b) -> bool:
    """Whether segments pq and ab properly intersect (orientation test)."""
    def side(u, v, w):
        return np.sign((v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0]))
    return side(p, q, a) != side(p, q, b) and side(a, b, p) != side(a, b, q)


def test_the_route_through_the_cells_goes_round_the_wall_the_thesis_legs_cross():
    world = parse_world(L_WORLD, "L.json")
    p = plan(world, checkpoints="thesis")
    walls = [((0.3, 0.0), (0.3, 0.7)), ((0.3, 0.7), (1.0, 0.7))]
    legs = np.vstack([np.asarray(p.start)[None], p.checkpoints])
    assert any(crosses(legs[i], legs[i + 1], *w) for i in range(len(legs) - 1) for w in walls)
    route = route_through_cells(p)
    assert np.allclose(route[0], (0.15, 0.15)) and np.allclose(route[-1], (0.8, 0.85))
    assert not any(crosses(route[i], route[i + 1], *w) for i in range(len(route) - 1) for w in walls)
    # round the corner at (0.3, 0.7) with the robot's 25 mm: at least up 0.55 m from y 0.15, across 0.5 m
    assert path_length(route[0], route[1:]) > 0.55 + 0.5 - 0.05


def test_the_route_length_is_the_sum_of_its_legs():
    assert path_length((0.0, 0.0), np.array([[3.0, 4.0], [3.0, 5.0]])) == 6.0
