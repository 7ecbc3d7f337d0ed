"""The motion model's actuator noise (robots.kinematics.slip): Webots' slip noise, the 10 % of thesis ch. 6.1."""

import dataclasses

import numpy as np
import pytest

from robots import kinematics
from robots.params import KHEPERA

C = KHEPERA.max_wheel_speed
N = KHEPERA.substeps(KHEPERA.target_period)


def wheel_distances(noise, params=KHEPERA):
    """Distance each wheel rolls in one full-speed 1.024 s step from full speed, for slip draws ``noise``."""
    speeds, _ = kinematics.wheel_speeds(np.full(2, C), np.full(2, C), N, params)
    return kinematics.slip(np.broadcast_to(speeds, noise.shape[:-2] + speeds.shape), noise, params).sum(-2) * params.dt


def test_slip_is_redrawn_every_32_ms_per_wheel_and_bounded_by_10_percent():
    assert KHEPERA.noise_shape(KHEPERA.target_period) == (32, 2)
    assert KHEPERA.noise_shape(KHEPERA.avoid_period) == (4, 2)
    noise = np.random.default_rng(0).uniform(-1, 1, (20_000,) + KHEPERA.noise_shape(KHEPERA.target_period))
    ratio = wheel_distances(noise) / (C * KHEPERA.target_period) - 1.0
    assert np.abs(ratio).max() <= 0.10 + 1e-12
    # 32 independent U(-0.1, 0.1) factors averaged over the step: std 0.1 / sqrt(3 * 32) = 1.02 %.
    assert ratio.std() == pytest.approx(0.1 / np.sqrt(3 * 32), rel=0.03)
    assert abs(np.corrcoef(ratio[:, 0], ratio[:, 1])[0, 1]) < 0.03  # the wheels slip independently


def test_one_draw_per_command_is_the_harsher_model():
    per_command = dataclasses.replace(KHEPERA, noise_period=KHEPERA.target_period)
    assert per_command.noise_shape(per_command.target_period) == (1, 2)
    noise = np.random.default_rng(1).uniform(-1, 1, (20_000, 1, 2))
    ratio = wheel_distances(noise, per_command) / (C * KHEPERA.target_period) - 1.0
    assert ratio.std() == pytest.approx(0.1 / np.sqrt(3), rel=0.03)


def test_zero_slip_is_the_noise_free_model_and_stopped_wheels_do_not_slip():
    state = kinematics.initial_state(np.array([0.0, 0.0, 0.0]))
    moved, _ = kinematics.step(state, np.array([C, C]), np.zeros((32, 2)), N)
    speeds, _ = kinematics.wheel_speeds(np.zeros(2), np.full(2, C), N)  # from rest, with the 20 ms lag
    assert moved.pose[0] == pytest.approx(speeds[:, 0].sum() * KHEPERA.dt, abs=1e-12)
    assert abs(moved.pose[1]) < 1e-12 and abs(moved.pose[2]) < 1e-12
    still, _ = kinematics.step(state, np.zeros(2), np.ones((32, 2)), N)
    np.testing.assert_array_equal(still.pose, state.pose)


def test_slip_draws_must_divide_the_control_period():
    with pytest.raises(ValueError, match="slip draws"):
        kinematics.slip(np.zeros((64, 2)), np.zeros((3, 2)))
    with pytest.raises(ValueError, match="noise periods"):
        dataclasses.replace(KHEPERA, noise_period=0.048).noise_shape(KHEPERA.avoid_period)


def test_advance_pose_is_advances_new_state():
    """To the last bits of the position (a sum against the last of a cumulative sum); heading and wheels exact."""
    import jax
    import jax.numpy as jnp

    rng = np.random.default_rng(3)
    pose = np.stack([rng.uniform(0, 1, 200), rng.uniform(0, 1, 200), rng.uniform(-np.pi, np.pi, 200)], -1)
    state = kinematics.RobotState(pose, rng.uniform(-C, C, (200, 2)))
    setpoint = kinematics.quantize_command(rng.uniform(-C, C, (200, 2)))
    noise = rng.uniform(-1, 1, (200,) + KHEPERA.noise_shape(KHEPERA.target_period))
    for xp, cast, call in [(np, np.asarray, lambda f: f), (jnp, lambda a: jnp.asarray(a, jnp.float32), jax.jit)]:
        s = kinematics.RobotState(cast(state.pose), cast(state.wheels))
        full = call(lambda s, c, z: kinematics.advance(s, c, z, N, KHEPERA, xp)[0])(s, cast(setpoint), cast(noise))
        end = call(lambda s, c, z: kinematics.advance_pose(s, c, z, N, KHEPERA, xp))(s, cast(setpoint), cast(noise))
        tol = 1e-12 if xp is np else 1e-6
        np.testing.assert_allclose(np.asarray(end.pose[:, :2]), np.asarray(full.pose[:, :2]), rtol=0, atol=tol)
        np.testing.assert_array_equal(np.asarray(end.pose[:, 2]), np.asarray(full.pose[:, 2]))
        np.testing.assert_array_equal(np.asarray(end.wheels), np.asarray(full.wheels))


# ------------------------------------------------------------------------------ robots that differ (issue 32)

def circumradius(p):
    """Radius of the circle through three points ``(3, 2)`` (the trace of a robot driving an arc)."""
    a, b, c = (np.linalg.norm(p[i] - p[j]) for i, j in ((0, 1), (1, 2), (2, 0)))
    cross = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
    return a * b * c / (2.0 * abs(cross))


@pytest.mark.parametrize("simulator", ["kinematics", "pymunk"])
def test_a_10_percent_smaller_left_wheel_curves_left_on_the_radius_worked_out_by_hand(simulator):
    """Equal commands c on wheels of gain (0.9, 1): v = 0.95 c, ω = 0.1 c / b, so R = v / ω = 9.5 b = 0.5035 m
    to the left — whatever c, and through the motor lag too (both wheels follow the same exponential)."""
    robot = dataclasses.replace(KHEPERA, wheel_gain=(0.9, 1.0), actuator_noise=0.0, speed_unit=0.0)
    c = np.array([0.1, 0.1])
    zero = np.zeros(robot.noise_shape(robot.avoid_period))
    if simulator == "kinematics":
        state, poses = kinematics.initial_state(np.array([0.5, 0.5, 0.0])), []
        for _ in range(40):
            state, trace = kinematics.step(state, c, zero, 8, robot)
            poses.append(trace)
        poses = np.concatenate(poses)
    else:
        from robots.world import PymunkWorld
        from robots.worldfile import parse_world

        world = parse_world({"name": "big", "size": [3.0, 3.0], "start": [1.5, 1.0, 0.0], "goal": [2.5, 2.5]})
        sim = PymunkWorld(world, params=robot)
        poses = np.concatenate([sim.step(c, zero)[1] for _ in range(40)])
    # the chords of explicit Euler at 16 ms lie on a circle of radius (v dt / 2) / sin(ω dt / 2) = R to 1e-6
    assert circumradius(poses[[40, 160, 300], :2]) == pytest.approx(9.5 * 0.053, rel=1e-5)
    assert poses[-1, 2] > 0.5  # it turned left (counter-clockwise), about 0.1 c / b = 0.19 rad/s for 5.1 s


def test_a_motor_that_delivers_80_percent_scales_that_wheel_s_speed_and_nothing_else():
    robot = dataclasses.replace(KHEPERA, wheel_gain=(1.0, 0.8))
    noise = np.random.default_rng(3).uniform(-1, 1, (32, 2))
    wheels, setpoint = np.array([0.05, -0.02]), np.array([0.12, 0.08])
    v, omega, end = kinematics.motor_twist(wheels, setpoint, noise, 64, robot)
    v0, omega0, end0 = kinematics.motor_twist(wheels, setpoint, noise, 64, KHEPERA)
    left, right = v0 - 0.5 * KHEPERA.wheel_base * omega0, v0 + 0.5 * KHEPERA.wheel_base * omega0
    np.testing.assert_allclose(v, 0.5 * (left + 0.8 * right), atol=1e-15)
    np.testing.assert_allclose(omega, (0.8 * right - left) / KHEPERA.wheel_base, atol=1e-12)
    np.testing.assert_array_equal(end, end0)  # the motors are the same; only the wheel turns less


def test_repeating_a_motion_is_the_motion_made_for_that_much_longer():
    """What the learner measures (robots.controllers.learner): one 0.128 s tick repeated 8 times is the 1.024 s
    the same command makes, to rounding; a straight tick goes 8 times as far; a quarter turn on the spot
    repeated 4 times comes back."""
    robot = dataclasses.replace(KHEPERA, actuator_noise=0.0, speed_unit=0.0)
    for c in ([0.1, 0.12], [-0.05, -0.08], [0.16, 0.02]):
        start = kinematics.RobotState(np.array([0.3, 0.4, 0.7]), np.array(c))
        tick, _ = kinematics.advance(start, np.array(c), np.zeros((4, 2)), 8, robot)
        period, _ = kinematics.advance(start, np.array(c), np.zeros((32, 2)), 64, robot)
        np.testing.assert_allclose(kinematics.repeated(start.pose, tick.pose, 8),
                                   kinematics.egocentric(start.pose, period.pose[:2]), atol=1e-12)
    a = np.array([0.0, 0.0, 0.0])
    np.testing.assert_allclose(kinematics.repeated(a, np.array([0.02, 0.0, 0.0]), 8), [0.0, 0.16], atol=1e-15)
    assert kinematics.repeated(a, np.array([0.01, 0.01, np.pi / 2]), 4)[1] == pytest.approx(0.0, abs=1e-15)
