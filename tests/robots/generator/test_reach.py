"""The independent route search (robots.generator.reach) on worlds whose answers are worked out by hand."""

import math

import numpy as np
import pytest

from robots.generator.reach import MARGIN, STEP, count_turns, reach
from robots.params import KHEPERA
from robots.worldfile import parse_world

R = KHEPERA.radius


def wall_with_gap(gap, **extra):
    e = (gap + 0.01) / 2  # segment ends gap + thickness apart: a gap between surfaces of `gap`
    walls = [[0.5, 0.0, 0.5, 0.3 - e], [0.5, 0.3 + e, 0.5, 0.6]]
    return parse_world({"name": "gap", "size": [1.0, 0.6], "walls": walls, "start": [0.2, 0.15, 0.0],
                        "goal": [0.8, 0.45], **extra})


def test_reach_measures_a_10_cm_gap():
    found = reach(wall_with_gap(0.10))
    assert found.solvable
    assert abs(found.narrowest_passage_m - 0.10) <= STEP  # within a grid cell (refined: to about a mm)
    assert abs(found.narrowest_passage_m - 0.10) <= 0.002
    assert found.route_length_m == pytest.approx(math.hypot(0.6, 0.3))  # the straight line passes the gap
    assert found.turns == 0 and found.route_ratio == 1.0


def test_reach_finds_no_way_through_a_4_cm_gap():
    found = reach(wall_with_gap(0.04))
    assert not found.solvable and len(found.route) == 0
    assert reach(wall_with_gap(0.04), known_only=True).solvable is False


def test_reach_on_an_l_shaped_route_of_known_length():
    # A 1 m square with the box [0, 0.8] x [0.2, 1.0]: an L-shaped way 0.2 m wide round its corner C.
    w = parse_world({"name": "L", "size": [1.0, 1.0], "obstacles": [{"type": "box", "center": [0.4, 0.6],
                                                                    "size": [0.8, 0.8]}],
                     "start": [0.1, 0.1, 0.0], "goal": [0.9, 0.9]})
    a, b, c = np.array([0.1, 0.1]), np.array([0.9, 0.9]), np.array([0.8, 0.2])

    def taut(rho):  # A to B round a disc of radius rho at C: two tangents and the arc between them
        ca, cb = np.hypot(*(a - c)), np.hypot(*(b - c))
        free = 2 * math.pi - math.acos(np.dot(a - c, b - c) / (ca * cb))  # the angle at C on the free side
        return (math.sqrt(ca ** 2 - rho ** 2) + math.sqrt(cb ** 2 - rho ** 2)
                + rho * (free - math.acos(rho / ca) - math.acos(rho / cb)))

    found = reach(w)
    usable = R + 0.5 * math.hypot(STEP, STEP) + MARGIN
    assert taut(R) <= found.route_length_m <= taut(usable + STEP)
    assert found.turns == 1 and found.straight_m == pytest.approx(math.hypot(0.8, 0.8))
    assert abs(found.narrowest_passage_m - 0.195) < 0.002  # the way is 0.2 m less the border's half thickness


def test_reach_ignores_movers_unless_asked():
    mover = {"shape": {"type": "circle", "radius": 0.04},
             "path": {"type": "line", "from": [0.5, 0.25], "to": [0.5, 0.35], "speed_mps": 0.02}}
    w = wall_with_gap(0.10, moving=[mover])
    assert reach(w).solvable and not reach(w, movers_at=0.0).solvable


def test_count_turns():
    assert count_turns([[0, 0], [1, 0], [1, 1]]) == 1
    assert count_turns([[0, 0], [1, 0], [2, 0.2]]) == 0  # 11 degrees
    assert count_turns([[0, 0], [1, 0], [1.04, 0.04], [1.04, 1]]) == 1  # one corner cut in two
    assert count_turns([[0, 0], [1, 0], [1, 1], [2, 1], [2, 2]]) == 3
