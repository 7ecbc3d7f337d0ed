"""Out of a declared mover's way (robots.controllers.escape): times of the straight motions, and the choice."""

import numpy as np

from robots.controllers import actionmaps as am
from robots.controllers import escape as esc


def test_a_still_point_ahead_is_reached_after_its_distance_over_the_speed_and_never_going_back():
    """A still point 10 cm straight ahead, discs grown by 3.5 cm: contact after 10 − 3.5 = 6.5 cm, 0.065 / v s
    (v = 0.08 and 0.16 m/s on a two-speed grid: 0.8125 and 0.40625 s); driving back, never."""
    objects = np.array([[0.10, 0.0, 0.0, 0.0, 0.0]], np.float32)
    grid = am.VelocityGrid(72, 2, 0.16)
    t = np.asarray(esc.straight_times(objects, np.array([True]), 1, 0.035, grid))
    np.testing.assert_allclose(t[0], [0.8125, 0.40625], rtol=1e-5)
    assert np.all(np.isinf(t[1]))


def test_a_mover_coming_from_ahead_is_escaped_backwards_at_the_speed_that_is_never_caught():
    """A mover 20 cm ahead coming at 0.1 m/s, discs grown by 6 cm in all: standing, hit after (0.2 − 0.06) / 0.1 =
    1.4 s < 1.5 s. Ahead it is met sooner; back at v < 0.1 m/s it catches up after 0.14 / (0.1 − v) s and at 0.12
    or 0.16 m/s never: the first of those, 0.12 m/s back, both wheels −0.12. With escape_s = 1 (1.4 s is not
    within it) the command stands."""
    objects = np.array([[0.2, 0.0, -0.1, 0.0, 0.025]], np.float32)
    valid = np.array([True])
    grid = am.VelocityGrid(72, 4, 0.16)  # speeds 0.04, 0.08, 0.12, 0.16
    t_stand = float(esc.standing_time(objects, valid, 0, 0.035))
    np.testing.assert_allclose(t_stand, 1.4, atol=1e-4)  # standing: a vanishing speed of 1e-6 m/s
    straight = esc.straight_times(objects, valid, 0, 0.035, grid)
    np.testing.assert_allclose(np.asarray(straight[1, :2]), [0.14 / 0.06, 0.14 / 0.02], rtol=1e-4)
    wheels = np.array([0.05, 0.07], np.float32)
    np.testing.assert_allclose(np.asarray(esc.escape(wheels, t_stand, straight, grid, 1.5)), [-0.12, -0.12], atol=1e-6)
    np.testing.assert_allclose(np.asarray(esc.escape(wheels, t_stand, straight, grid, 1.0)), wheels)
