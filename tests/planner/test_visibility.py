"""Checkpoints that see each other (planner.visibility): worked out by hand on a Z-shaped corridor, and the
clearance of every leg measured with the world's own geometry."""

import numpy as np
import pytest

from planner import plan
from planner.bitmap import padded_obstacles
from planner.visibility import segment_slack, slack
from robots.geometry import Box, Circle
from robots.worldfile import parse_world

# A corridor 12 cm wide (between the walls' surfaces) along the centre line (0.06, 0.10) → (0.50, 0.10) →
# (0.50, 0.50) → (0.94, 0.50): east, north, east. Walls are segments 1 cm thick, so their centre lines lie
# 6.5 cm either side of the centre line.
H = 0.065
Z = {"name": "z", "size": [1.0, 0.6], "start": [0.06, 0.10, 0.0], "goal": [0.94, 0.50],
     "walls": [[0.0, 0.10 - H, 0.50 + H, 0.10 - H], [0.50 + H, 0.10 - H, 0.50 + H, 0.50 - H],
               [0.50 + H, 0.50 - H, 1.0, 0.50 - H],
               [0.0, 0.10 + H, 0.50 - H, 0.10 + H], [0.50 - H, 0.10 + H, 0.50 - H, 0.50 + H],
               [0.50 - H, 0.50 + H, 1.0, 0.50 + H]]}


@pytest.fixture(scope="module")
def z():
    return parse_world(Z, "z.json")


def test_the_thesis_rule_gives_one_checkpoint_behind_the_walls(z):
    """The Z is one slippery cell (each of its rows and columns is one run), so ch. 3.2.3 puts no checkpoint
    in it: the leg from start to goal is the straight line through both walls of the middle stretch."""
    p = plan(z, checkpoints="thesis")
    assert len(p.route) == 1 and len(p.checkpoints) == 1
    assert p.length == pytest.approx(np.hypot(0.88, 0.40))
    assert segment_slack(z.start[:2], z.goal, padded_obstacles(z)) < -0.02  # it runs through the walls


def test_visible_checkpoints_are_the_corridors_two_corners(z):
    """By hand: the only way from start to goal turns at the corridor's two bends, (0.50, 0.10) and (0.50, 0.50),
    and goes straight between them. With 6 cm either side of the centre line and 5.5 cm wanted (radius + 3 cm
    margin) the legs keep to the middle, so every checkpoint but the goal lies at a bend — within 3 cm of its
    centre-line corner — one or two per bend (a corner's cell-centre path may take a bend in two steps)."""
    p = plan(z)
    corners = np.array([[0.50, 0.10], [0.50, 0.50]])
    near = np.linalg.norm(p.checkpoints[:-1, None, :] - corners[None], axis=-1) < 0.03  # (k, 2)
    assert p.rule == "visible" and np.all(near.any(axis=1)) and np.all(near.sum(axis=0) >= 1)
    assert 2 <= len(p.checkpoints) - 1 <= 4
    np.testing.assert_array_equal(p.checkpoints[-1], [0.94, 0.50])
    # The legs: start → first corner runs along the bottom stretch, first → second corner up the middle one,
    # second corner → goal along the top one; each keeps the robot radius from every wall's surface.
    pts = np.vstack([[0.06, 0.10], p.checkpoints])
    for a, b in zip(pts[:-1], pts[1:]):
        line = a + np.linspace(0.0, 1.0, 300)[:, None] * (b - a)
        assert z.clearance(line, known_only=True).min() >= 0.025 + 0.015, (a, b)
    # No longer than the centre line (0.44 + 0.40 + 0.44 m); corners drawn to the inner side of the bends
    # shorten it by at most the band's width at each (1.75 cm either side of the centre line, twice per bend).
    assert 1.28 - 4 * 0.0175 <= p.length <= 1.28 + 1e-9


def test_slack_is_the_gap_beyond_the_cushion():
    """Slack of a point 10 cm from a wall's centre line: 10 cm − 0.5 cm half thickness − 2.5 cm cushion."""
    w = parse_world({"name": "wall", "size": [1.0, 1.0], "walls": [[0.5, 0.0, 0.5, 0.4]],
                     "start": [0.2, 0.8, 0.0], "goal": [0.8, 0.8]}, "wall.json")
    obstacles = padded_obstacles(w)
    assert float(slack(np.array([0.4, 0.2]), obstacles)) == pytest.approx(0.10 - 0.005 - 0.025)
    # A segment passing the wall's end at (0.5, 0.4) 4 cm above it: least slack 4 − 0.5 − 2.5 cm.
    assert segment_slack((0.3, 0.44), (0.7, 0.44), obstacles) == pytest.approx(0.04 - 0.005 - 0.025, abs=1e-3)


def test_slack_to_circles_and_boxes_by_hand():
    """Circles (a recovery's sensed points) and boxes are measured apart from walls: by hand, a point 0.5 m from a
    circle's centre has slack 0.5 − radius − clearance; a leg passing 8 cm above the centre, 0.08 − r − c; and a leg
    near both a circle and a box takes the nearer (the box's edge 3 cm above it)."""
    obstacles = [(Circle((0.0, 0.0), 0.05), 0.01)]
    assert float(slack(np.array([0.3, 0.4]), obstacles)) == pytest.approx(0.5 - 0.05 - 0.01)
    np.testing.assert_allclose(slack(np.array([[0.3, 0.4], [0.0, 0.02], [0.06, 0.0]]), obstacles),
                               [0.44, -0.01, 0.0], atol=1e-12)  # inside the disc: distance 0
    assert segment_slack((-1.0, 0.08), (1.0, 0.08), obstacles) == pytest.approx(0.08 - 0.05 - 0.01)
    obstacles = obstacles + [(Box((0.5, 0.16), (0.2, 0.1)), 0.02)]  # bottom edge at y = 0.11
    assert segment_slack((-1.0, 0.08), (1.0, 0.08), obstacles) == pytest.approx(0.03 - 0.02)
