"""The coordinates of the indirect map's linear model (``ekm.charts``): polar ahead, mirrored behind."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from ekm.charts import model_input, polar, signed
from ekm.config import EKMConfig
from ekm.kohonen import initial_weights, units
from robots.kinematics import RobotState, advance, egocentric
from robots.params import KHEPERA as P

CFG = EKMConfig()


def test_signed_chart_is_the_polar_one_ahead_and_its_mirror_image_behind():
    for alpha in np.linspace(-3.1, 3.1, 41):
        u = jnp.asarray([alpha, 0.07])
        got = np.asarray(signed(u, CFG) * units(CFG))
        if abs(alpha) <= np.pi / 2:
            np.testing.assert_allclose(got, np.asarray(polar(u, u, CFG) * units(CFG)), atol=1e-6)
        else:  # the same polar coordinates, measured from the robot's back, distance negative
            np.testing.assert_allclose(got, [alpha - np.sign(alpha) * np.pi, -0.07], atol=1e-6)


def test_signed_chart_is_continuous_behind_the_robot_and_odd_across_its_sides():
    left, right = (np.asarray(signed(jnp.asarray([a, 0.1]), CFG)) for a in (np.pi - 1e-3, -np.pi + 1e-3))
    np.testing.assert_allclose(left, right, atol=1e-3)  # no seam at ±π: a neuron behind is not torn apart
    for side in (np.pi / 2, -np.pi / 2):  # the jump at the sides: ũ → -ũ, so a linear model's c → -c
        front, back = (np.asarray(signed(jnp.asarray([side + s, 0.1]), CFG)) for s in (-np.sign(side) * 1e-3,
                                                                                   np.sign(side) * 1e-3))
        np.testing.assert_allclose(back, -front, atol=1e-3)


def arc_command(u_chart):
    """The exact one-step inverse written once on the chart: arc turning the heading by 2α', chord d'."""
    a, d = float(u_chart[0]), float(u_chart[1])
    speed = d * (a / np.sin(a) if abs(a) > 1e-9 else 1.0) / P.target_period
    omega = 2.0 * a / P.target_period
    return jnp.asarray([speed - omega * P.wheel_base / 2, speed + omega * P.wheel_base / 2], jnp.float32)


@pytest.mark.parametrize("alpha", [0.0, 0.6, -1.2, 1.9, -2.5, 3.0])
def test_one_inverse_on_the_signed_chart_reaches_targets_ahead_and_behind(alpha):
    """The formula that drives forwards to a target ahead reverses onto a target behind, noise-free."""
    d = 0.06
    target = jnp.asarray([d * np.cos(alpha), d * np.sin(alpha)])
    c = arc_command(signed(jnp.asarray([alpha, d]), CFG) * units(CFG))
    assert (float(c.sum()) > 0) == (abs(alpha) < np.pi / 2)  # forwards ahead, backwards behind
    robot = RobotState(jnp.zeros(3), c)  # wheels already at speed: no motor lag in this check
    n = P.substeps(P.target_period)
    moved, _ = advance(robot, c, jnp.zeros(P.noise_shape(P.target_period)), n, P, jnp)
    assert float(egocentric(moved.pose, target, jnp)[1]) < 0.03 * d  # sub-step integration: ≤ 1.2 mm here


def test_model_input_gives_one_row_per_neuron_in_either_chart():
    """The polar chart's input has a row per neuron; the signed chart's is one row, the same for all."""
    w = initial_weights(CFG)
    u = jnp.asarray([2.8, 0.05])
    assert np.broadcast_shapes(model_input(u, w, CFG).shape, w.shape) == w.shape
    np.testing.assert_array_equal(np.asarray(model_input(u, w, CFG)), np.asarray(signed(u, CFG)))
    polar_cfg = EKMConfig(chart="polar")
    assert model_input(u, w, polar_cfg).shape == w.shape
    np.testing.assert_allclose(np.asarray(model_input(u, w[:1], polar_cfg))[0], np.asarray(polar(u, w[0], polar_cfg)))
    with pytest.raises(ValueError, match="chart must be"):
        EKMConfig(chart="cartesian")


PI = math.pi


def test_charts_known_values():
    cfg = EKMConfig(d_scale=0.2)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([0.25 * PI, 0.1]), cfg)), [0.25, 0.5], atol=1e-6)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([0.75 * PI, 0.1]), cfg)), [-0.25, -0.5], atol=1e-6)
    np.testing.assert_allclose(np.asarray(signed(jnp.asarray([-0.75 * PI, 0.1]), cfg)), [0.25, -0.5], atol=1e-6)
    w = jnp.asarray([[3.0, 0.1]])
    np.testing.assert_allclose(np.asarray(polar(jnp.asarray([-3.0, 0.1]), w, cfg)), [[(2 * PI - 3.0) / PI, 0.5]],
                               atol=1e-6)
    np.testing.assert_allclose(np.asarray(model_input(jnp.asarray([-3.0, 0.1]), w, EKMConfig(d_scale=0.2, chart="polar"))),
                               [[(2 * PI - 3.0) / PI, 0.5]], atol=1e-6)
    # the signed chart's input is one row, the same for every neuron
    np.testing.assert_allclose(np.asarray(model_input(jnp.asarray([0.75 * PI, 0.1]), w, cfg)), [-0.25, -0.5], atol=1e-6)
