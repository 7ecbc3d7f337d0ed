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


def test_the_backward_vehicle_turns_a_reversing_khepera_away_from_what_is_behind_it():
    """Worked by hand from Eq. 4.10 with the back as the front: the rear sensors (-160°, 160°) are the reversed
    vehicle's forward ones at ±20°. Something behind on the left (160°) drives the right motor forward (+cross) and
    the left one back (-same): the robot turns left, its back swings right, away; equal rear readings push both
    motors forward by cross - same, braking the reversing robot. A front sensor (85°) becomes a small brake."""
    z = braitenberg.z_matrix(SHORT_RANGE, cross=4.0, same=0.4, backward=True)
    # Khepera order: 85, 45, 10, -10, -45, -85, -160, 160 degrees.
    np.testing.assert_allclose(z[:, 7], [-0.4, 4.0])
    np.testing.assert_allclose(z[:, 6], [4.0, -0.4])
    np.testing.assert_allclose(z[:, 0], [-0.4, -0.2])
    np.testing.assert_allclose(z[:, 5], [-0.2, -0.4])
    left, right = np.asarray(braitenberg.avoid(z, np.array([0, 0, 0, 0, 0, 0, 0.5, 0.5], np.float32)))
    assert left == pytest.approx(right) == pytest.approx(0.5 * (4.0 - 0.4))


def test_the_backward_long_ring_vehicle_is_the_forward_one_seen_from_behind():
    """The long ring is symmetric under a half turn: the sensor straight behind (180°) is the reversed vehicle's
    straight-ahead one, -1.8 to both of its motors ((same - cross) / 2) and so +1.8 to both of the robot's; the sensor
    straight ahead is behind the reversed vehicle, +0.3 to both of its motors ((same + same / 2) / 2), -0.3 here."""
    z = braitenberg.z_matrix(LONG_RANGE, cross=4.0, same=0.4, backward=True)
    np.testing.assert_allclose(z[:, 6], [1.8, 1.8])  # 180°
    np.testing.assert_allclose(z[:, 0], [-0.3, -0.3])  # 0°


def test_the_backward_vehicle_with_a_wider_cone_counts_the_khepera_s_sides_as_forward():
    """With ``front`` 100°, the sides (±85°, 95° off the way back) are the reversed vehicle's forward sensors too:
    -85° is its 95° on the left, -cross to its right motor (the robot's left, sign flipped: +4) and +same to its own
    (the robot's right: -0.4)."""
    z = braitenberg.z_matrix(SHORT_RANGE, cross=4.0, same=0.4, front=np.radians(100.0), backward=True)
    np.testing.assert_allclose(z[:, 5], [4.0, -0.4])
    np.testing.assert_allclose(z[:, 0], [-0.4, 4.0])
    np.testing.assert_allclose(z[:, 1], [-0.4, -0.2])  # 45°: 135° off the way back, still a small brake
