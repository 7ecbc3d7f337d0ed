"""What the reactive architectures share (robots.controllers.discrete)."""

import math

import numpy as np

from robots.controllers.discrete import as_readings
from robots.params import KHEPERA_IR_ANGLES

R = 0.025  # the Khepera's radius, m


def at(degrees, gap):
    """A point ``gap`` m from the body surface at ``degrees`` from the heading (robot frame)."""
    a = math.radians(degrees)
    return ((R + gap) * math.cos(a), (R + gap) * math.sin(a))


def test_each_sensor_reads_the_nearer_of_its_return_and_the_points_nearest_its_direction():
    """The short ring at 85, 45, 10, -10, -45, -85, -160, 160 degrees. By hand: 70 deg is 15 from the 85 deg sensor
    and 25 from the 45 deg one; 130 deg is 30 from 160 and 45 from 85; -100 deg is 15 from -85; -12 deg is 2 from
    -10. A point left out (``valid`` false) or beyond ``within`` counts for nobody; a point inside the body reads 0."""
    ir = np.full(8, np.inf)
    ir[2], ir[3] = 0.04, 0.01
    points = np.array([at(70, 0.02), at(130, 0.03), at(10, 0.005), at(-12, 0.03), at(-100, 0.01), at(-45, -0.01),
                       at(45, 0.004)])
    valid = np.array([True, True, False, True, True, True, True])
    got = np.asarray(as_readings(points, valid, KHEPERA_IR_ANGLES, ir, radius=R, within=0.035))
    want = [0.02, 0.004, 0.04, 0.01, 0.0, 0.01, np.inf, 0.03]
    np.testing.assert_allclose(got, want, atol=1e-6)
    # within 2.5 cm: the 3 cm points (130 and -12 deg) are left out
    got = np.asarray(as_readings(points, valid, KHEPERA_IR_ANGLES, ir, radius=R, within=0.025))
    np.testing.assert_allclose(got, [0.02, 0.004, 0.04, 0.01, 0.0, 0.01, np.inf, np.inf], atol=1e-6)
