"""Braitenberg avoidance (robots.controllers.braitenberg, Eq. 4.10)."""

import numpy as np
import pytest

from robots.controllers import braitenberg
from robots.controllers.base import proximity
from robots.params import LONG_RANGE, SHORT_RANGE


@pytest.mark.parametrize("sensors", [SHORT_RANGE, LONG_RANGE], ids=["short", "long"])
def test_an_obstacle_ahead_left_turns_the_robot_right(sensors):
    """Ch. 4.4: "the right motor will rotate backward faster than the left motor's rotation forward"."""
    z = braitenberg.z_matrix(sensors, cross=4.0, same=0.4)
    angles = np.degrees(np.asarray(sensors.angles))
    ahead_left = np.argmin(np.where(angles > 0, np.abs(angles - 30.0), np.inf))  # the forward sensor nearest 30° left
    ir = np.full(len(angles), np.inf)
    ir[ahead_left] = 0.4 * sensors.range_m
    left, right = np.asarray(braitenberg.avoid(z, proximity(ir, sensors)))
    assert right < 0 < left and abs(right) > abs(left)


def test_z_has_large_negative_cross_weights_from_forward_sensors_and_small_positive_others():
    z = braitenberg.z_matrix(SHORT_RANGE, cross=4.0, same=0.4)
    # Khepera order: 85, 45, 10, -10, -45, -85, -160, 160 degrees.
    assert z[1, 1] == z[1, 2] == -4.0 and z[0, 3] == z[0, 4] == -4.0  # forward-left -> right motor, and mirrored
    assert z[0, 1] == z[0, 2] == 0.4 and z[1, 3] == z[1, 4] == 0.4
    others = np.r_[z[:, [0, 5, 6, 7]].ravel()]
    assert np.all(others > 0) and np.all(others <= 0.4)
    long = braitenberg.z_matrix(LONG_RANGE, cross=4.0, same=0.4)
    assert long[0, 0] == long[1, 0] == pytest.approx(-1.8)  # straight ahead: both motors, split evenly
