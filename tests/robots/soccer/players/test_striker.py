"""The striker's target point and mode (robots.soccer.players.striker.aim) on hand-built positions.

Default field 1.2 × 0.8 m (attacked goal centre g = (1.2, 0.4)), body radius 0.025 and ball radius 0.02, so the
contact distance c = 0.045 m; defaults behind 0.04, lateral 0.02, clear 0.03, arrive 0.01, push 0.2. The points
the drive can reach are kept clear + body radius = 0.055 m from the walls.
"""

import numpy as np
import pytest

from robots.soccer.field import Field
from robots.soccer.players.striker import APPROACH, GO_ROUND, PUSH, StrikerParams, aim

P, F, C, RB = StrikerParams(), Field(), 0.045, 0.02


def _aim(pose, ball, mode=APPROACH):
    target, new = aim(np.array(pose, np.float32), np.array(ball, np.float32), mode, P, F, C, RB)
    return np.asarray(target, float), int(new)


def test_lined_up_behind_the_ball_it_pushes_through_it_towards_the_goal():
    # ball (0.6, 0.4): u = (1, 0); robot (0.3, 0.4): along -0.3 < -c/2, across 0 < lateral -> push at b + 0.2 u
    target, mode = _aim((0.3, 0.4, 0.0), (0.6, 0.4))
    assert mode == PUSH
    assert target == pytest.approx([0.8, 0.4], abs=1e-6)


def test_off_the_line_it_goes_to_the_point_behind_the_ball():
    # robot (0.3, 0.5): across 0.1 > lateral, along -0.3 (not in the way) -> b - (c + behind) u = (0.515, 0.4)
    target, mode = _aim((0.3, 0.5, 0.0), (0.6, 0.4))
    assert mode == APPROACH
    assert target == pytest.approx([0.515, 0.4], abs=1e-6)


@pytest.mark.parametrize("y, side", [(0.41, 1.0), (0.39, -1.0)])
def test_on_the_goal_side_of_the_ball_it_goes_round_on_its_own_side(y, side):
    # robot (0.7, y): along 0.1 > -c, |across| 0.01 < c + clear = 0.075 -> beside and behind the ball:
    # b + 0.075 side n - 0.085 u = (0.515, 0.4 + 0.075 side)
    target, mode = _aim((0.7, y, 0.0), (0.6, 0.4))
    assert mode == GO_ROUND
    assert target == pytest.approx([0.515, 0.4 + 0.075 * side], abs=1e-6)


def test_a_ball_by_the_wall_is_approached_from_a_reachable_point_and_then_pushed():
    # ball (0.6, 0.03): g - b = (0.6, 0.37), |.| = 0.70491, u = (0.85117, 0.52489); b - 0.085 u = (0.52765, -0.01462),
    # below the wall: y is raised to 0.055 -> (0.52765, 0.055)
    target, mode = _aim((0.3, 0.5, 0.0), (0.6, 0.03))
    assert mode == APPROACH
    assert target == pytest.approx([0.52765, 0.055], abs=1e-4)
    # there (within arrive): along = (-0.07, 0.02) . u = -0.04908 < -c/2 -> push although |across| = 0.0538 > lateral
    target, mode = _aim((0.53, 0.05, 0.0), (0.6, 0.03), APPROACH)
    assert mode == PUSH
    assert target == pytest.approx([0.6 + 0.2 * 0.85117, 0.03 + 0.2 * 0.52489], abs=1e-4)


def test_once_pushing_it_keeps_pushing_a_little_further_off_the_line():
    # robot (0.3, 0.425): across 0.025 > lateral 0.02 but < 0.8 c = 0.036 and the ball is ahead (along < 0)
    assert _aim((0.3, 0.425, 0.0), (0.6, 0.4), PUSH)[1] == PUSH
    assert _aim((0.3, 0.425, 0.0), (0.6, 0.4), APPROACH)[1] == APPROACH
