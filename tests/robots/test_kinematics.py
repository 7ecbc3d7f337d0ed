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
