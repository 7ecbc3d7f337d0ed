"""What every controller shares (robots.controllers.base): proximity from IR readings, and the holonomic
velocity turned into wheel speeds."""

import numpy as np
import pytest

from robots.controllers.base import beyond_the_goal, proximity
from robots.params import KHEPERA, SHORT_RANGE


def test_proximity_is_zero_for_nothing_seen_and_one_at_contact():
    u = np.asarray(proximity(np.array([np.inf, 0.0, 0.025, 0.05]), SHORT_RANGE))
    assert u.tolist() == pytest.approx([0.0, 1.0, 0.5, 0.0])


def test_velocity_to_wheels_drives_ahead_turns_towards_the_side_and_turns_on_the_spot_for_behind():
    from robots.controllers.base import velocity_to_wheels

    ahead = np.asarray(velocity_to_wheels(0.0, 0.1))
    assert ahead == pytest.approx([0.1, 0.1])
    left = np.asarray(velocity_to_wheels(0.5, 0.1))
    assert left[1] > left[0] > 0  # forward and turning left
    behind = np.asarray(velocity_to_wheels(3.0, 0.1))
    assert behind[0] == pytest.approx(-behind[1]) and behind[1] > 0  # on the spot, left about
    fast = np.asarray(velocity_to_wheels(1.0, 1.0))
    assert np.max(np.abs(fast)) == pytest.approx(KHEPERA.max_wheel_speed)  # scaled, not clipped
    v, omega = np.cos(1.0), 4.0 * 1.0  # unscaled: forward speed and turn rate
    assert (fast[1] - fast[0]) / (fast[1] + fast[0]) == pytest.approx(omega * KHEPERA.wheel_base / (2 * v), rel=1e-5)


@pytest.mark.parametrize("final, expected", [
    (True, [False, True, True, True]),      # the goal 3 cm away: 4 cm and 3 cm lie beyond it, 2 cm does not
    (False, [False, False, False, False]),  # a checkpoint on the way: nothing is beyond it
])
def test_obstacles_lie_beyond_the_goal_only_when_the_checkpoint_is_the_goal(final, expected):
    assert np.asarray(beyond_the_goal(np.array([0.02, 0.04, 0.03, np.inf]), (0.0, 0.03), final)).tolist() == expected
