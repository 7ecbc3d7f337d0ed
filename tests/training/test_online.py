"""Known answers for one step of online training (training.online, thesis ch. 4.3 and 6.1; issue 12, item 5).

A map whose every M_i is zero commands c_p = 0, so what the robot does in a training step is the
exploration noise alone: c = quantize(0 + explore(t) · c* · ξ). With ξ = (+1, -1) and the default
explore = 0.2, each wheel is sent ±0.032 m/s (4 speed units) and the noise-free robot turns on the
spot by a heading change computed here from the closed form of the motion model.
"""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm import indirect
from ekm.config import EKMConfig
from robots.kinematics import RobotState
from robots.params import KHEPERA
from ekm.learning import fresh_trace
from training.online import TrainConfig, Trainee, draw_noise, next_target, start, train_chunk, train_step
from training.schedules import Schedule, Schedules

PARAMS = dataclasses.replace(KHEPERA, actuator_noise=0.0)
N = PARAMS.substeps(PARAMS.target_period)
Q = math.exp(-PARAMS.dt / PARAMS.motor_tau)
CFG = EKMConfig(neurons=3, forward_init=0.0)  # M_i = 0: c_p = 0 everywhere


def zero_map_trainee(target=(0.9, 0.5), age=0, pose=(0.5, 0.5, 0.0)):
    return Trainee(indirect.init(CFG), RobotState(jnp.asarray(pose, jnp.float32), jnp.zeros(2, jnp.float32)),
                   jnp.asarray(target, jnp.float32), jnp.asarray(age, jnp.int32), fresh_trace())


def draws(explore=(0.0, 0.0), target_draw=(0.5, 0.5)):
    return (jnp.zeros(PARAMS.noise_shape(PARAMS.target_period)), jnp.asarray(explore, jnp.float32),
            jnp.asarray(target_draw, jnp.float32))


def spin(wheel):
    """Heading change (rad) of one step from rest with wheels sent (-wheel, +wheel): ω_j = 2·wheel(1 - Q^j)/b
    held through sub-step j, summed by Euler: 2·wheel·dt·(N - (1 - Q^N)/(1 - Q)) / b."""
    return 2.0 * wheel * PARAMS.dt * (N - (1.0 - Q**N) / (1.0 - Q)) / PARAMS.wheel_base


def test_the_default_protocol_is_thesis_ch_6_1():
    t = TrainConfig()
    assert (t.steps, t.trials, t.arena, t.margin) == (100_000, 5, (1.0, 1.0), 0.1)
    assert (t.target_range, t.reach, t.patience) == (None, 0.0, 25)
    assert t.schedules == Schedules()


def test_exploration_noise_is_added_to_the_command_scaled_by_c_star_and_the_schedule():
    tcfg = TrainConfig(steps=1000)
    s = train_step(zero_map_trainee(), draws(explore=(-1.0, 1.0)), 0.0, CFG, tcfg, PARAMS)
    # explore(0) = 0.2: wheels sent (-0.032, +0.032) m/s, 4 speed units each: a turn to the left on the spot.
    np.testing.assert_allclose(np.asarray(s.robot.pose[:2]), [0.5, 0.5], atol=1e-6)
    assert float(s.robot.pose[2]) == pytest.approx(spin(0.2 * CFG.c_max), rel=1e-4)
    np.testing.assert_allclose(np.asarray(s.robot.wheels), [-0.032, 0.032], rtol=1e-4)


def test_exploration_follows_its_schedule_in_time():
    tcfg = TrainConfig(steps=1000, schedules=Schedules(explore=Schedule(0.4, 0.1, 0.5)))
    for t, scale in ((0.0, 0.4), (250.0, 0.2), (900.0, 0.1)):  # 0.4·(1/4)^(t/500), then 0.1
        s = train_step(zero_map_trainee(), draws(explore=(-1.0, 1.0)), t, CFG, tcfg, PARAMS)
        sent = round(scale * CFG.c_max / PARAMS.speed_unit) * PARAMS.speed_unit  # 8, 4, 2 speed units
        assert float(s.robot.pose[2]) == pytest.approx(spin(sent), rel=1e-4), t


def test_without_exploration_a_zero_map_sends_zero_and_the_robot_stays():
    s = train_step(zero_map_trainee(), draws(), 0.0, CFG, TrainConfig(steps=1000), PARAMS)
    np.testing.assert_allclose(np.asarray(s.robot.pose), [0.5, 0.5, 0.0], atol=1e-7)
    assert int(s.age) == 1  # a stop command does not end the target when reach = 0 (the default)
    np.testing.assert_allclose(np.asarray(s.target), [0.9, 0.5])


def test_a_target_is_kept_for_patience_steps_then_replaced_from_where_the_robot_is():
    tcfg = TrainConfig(steps=1000, patience=4)
    s = train_step(zero_map_trainee(age=2), draws(target_draw=(0.25, 0.75)), 0.0, CFG, tcfg, PARAMS)
    assert int(s.age) == 3 and np.allclose(np.asarray(s.target), [0.9, 0.5])  # 3 steps on it so far
    s = train_step(s, draws(target_draw=(0.25, 0.75)), 1.0, CFG, tcfg, PARAMS)
    assert int(s.age) == 0  # the 4th step ends it
    np.testing.assert_allclose(np.asarray(s.target), [0.1 + 0.25 * 0.8, 0.1 + 0.75 * 0.8], rtol=1e-6)


def test_with_reach_a_target_ends_when_it_is_close_or_the_command_is_a_stop():
    close = TrainConfig(steps=1000, reach=0.5)
    s = train_step(zero_map_trainee(target=(0.8, 0.5)), draws(explore=(1.0, 1.0)), 0.0, CFG, close, PARAMS)
    assert int(s.age) == 0  # 0.3 m away after the step: within 0.5 m
    far = TrainConfig(steps=1000, reach=0.05)
    s = train_step(zero_map_trainee(target=(0.8, 0.5)), draws(explore=(1.0, 1.0)), 0.0, CFG, far, PARAMS)
    assert int(s.age) == 1  # 0.27 m away, still driving
    s = train_step(zero_map_trainee(target=(0.8, 0.5)), draws(), 0.0, CFG, far, PARAMS)
    assert int(s.age) == 0  # a zero command: the robot stopped, the target is done


def test_next_target_is_uniform_over_the_arena_inside_its_margin():
    tcfg = TrainConfig(arena=(2.0, 1.0), margin=0.1)
    pose = jnp.asarray([1.0, 0.5, 0.0])
    for draw, want in (((0.0, 0.0), (0.1, 0.1)), ((1.0, 1.0), (1.9, 0.9)), ((0.5, 0.25), (1.0, 0.3))):
        np.testing.assert_allclose(np.asarray(next_target(pose, jnp.asarray(draw), tcfg)), want, rtol=1e-6)


def test_near_targets_lie_at_the_drawn_direction_and_distance_and_stay_in_the_arena():
    tcfg = TrainConfig(arena=(1.0, 1.0), target_range=0.3)
    pose = jnp.asarray([0.5, 0.5, 1.0])  # the heading does not matter: directions are absolute
    # draw = (direction / 2π, distance / range)
    np.testing.assert_allclose(np.asarray(next_target(pose, jnp.asarray([0.25, 0.5]), tcfg)), [0.5, 0.65], atol=1e-6)
    np.testing.assert_allclose(np.asarray(next_target(pose, jnp.asarray([0.5, 1.0]), tcfg)), [0.2, 0.5], atol=1e-6)
    pose = jnp.asarray([0.85, 0.5, 0.0])
    np.testing.assert_allclose(np.asarray(next_target(pose, jnp.asarray([0.0, 1.0]), tcfg)), [0.9, 0.5], atol=1e-6)


def test_training_starts_at_the_arena_centre_at_rest_heading_along_x():
    tcfg = TrainConfig(arena=(2.0, 1.0))
    s = start(jax.random.PRNGKey(3), CFG, tcfg)
    np.testing.assert_array_equal(np.asarray(s.robot.pose), [1.0, 0.5, 0.0])
    np.testing.assert_array_equal(np.asarray(s.robot.wheels), [0.0, 0.0])
    assert int(s.age) == 0
    draw = jax.random.uniform(jax.random.PRNGKey(3), (2,))
    np.testing.assert_allclose(np.asarray(s.target), 0.1 + np.asarray(draw) * [1.8, 0.8], rtol=1e-6)


def test_draw_noise_shapes_and_ranges():
    slip, explore, target = draw_noise(jax.random.PRNGKey(0), 500)
    assert slip.shape == (500, 32, 2) and explore.shape == (500, 2) and target.shape == (500, 2)
    assert -1.0 <= float(slip.min()) < -0.99 and 0.99 < float(slip.max()) <= 1.0
    bins = (np.asarray(slip, np.float64) + 1.0) * 32768.0 - 0.5  # centres of 2^16 equal bins of (-1, 1)
    np.testing.assert_array_equal(bins, np.round(bins))
    assert abs(float(slip.mean())) < 0.01 and float(slip.var()) == pytest.approx(1 / 3, abs=0.01)
    assert abs(np.corrcoef(np.asarray(slip[..., 0]).ravel(), np.asarray(slip[..., 1]).ravel())[0, 1]) < 0.02
    assert 0.0 <= float(target.min()) < 0.01 and 0.99 < float(target.max()) < 1.0
    assert abs(float(explore.mean())) < 0.1 and float(explore.std()) == pytest.approx(1.0, abs=0.05)


def test_a_chunk_uses_the_schedules_at_its_own_global_steps():
    """A schedule that has fully decayed by step 4: a chunk of 3 steps from t0 = 5 learns at η = end, which
    the same steps one by one at t = 5, 6, 7 do too (and at t = 0, 1, 2 would not)."""
    cfg = EKMConfig(neurons=3)
    tcfg = TrainConfig(steps=8, arena=(1.0, 1.0),
                       schedules=Schedules(eta=Schedule(0.5, 0.01, 0.5), sigma=Schedule(2.0, 0.5, 0.5)))
    keys = jax.random.split(jax.random.PRNGKey(0), 1)
    s0 = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    chunk = jax.tree.map(lambda a: a[0], train_chunk(s0, keys, 5.0, length=3, cfg=cfg, tcfg=tcfg))
    step = jax.jit(lambda s, d, t: train_step(s, d, t, cfg, tcfg, KHEPERA))
    noise = draw_noise(keys[0], 3)

    def by_steps(times):
        s = jax.tree.map(lambda a: a[0], s0)
        for i, t in enumerate(times):
            s = step(s, tuple(d[i] for d in noise), t)
        return s

    late, early = by_steps([5.0, 6.0, 7.0]), by_steps([0.0, 1.0, 2.0])
    for x, y in zip(jax.tree.leaves(chunk), jax.tree.leaves(late)):
        np.testing.assert_allclose(np.asarray(x), np.asarray(y), atol=1e-6)
    assert not np.allclose(np.asarray(chunk.ekm.M), np.asarray(early.ekm.M), atol=1e-4)


ARENA = (1.0, 1.0)


def test_one_chunk_is_the_same_as_its_steps_one_by_one():
    """train_chunk (lax.scan inside vmap, noise drawn up front) = train_step applied in order."""
    cfg, tcfg = EKMConfig(neurons=5), TrainConfig(steps=1000, trials=2, arena=ARENA)
    keys = jax.random.split(jax.random.PRNGKey(0), 2)
    s0 = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    chunk = train_chunk(s0, keys, 0.0, length=25, cfg=cfg, tcfg=tcfg)
    step = jax.jit(lambda s, d, t: train_step(s, d, t, cfg, tcfg, KHEPERA))  # compiled once for both trials
    for trial in range(2):
        s = jax.tree.map(lambda a: a[trial], s0)
        draws = draw_noise(keys[trial], 25)
        for t in range(25):
            s = step(s, tuple(d[t] for d in draws), float(t))
        for x, y in zip(jax.tree.leaves(s), jax.tree.leaves(jax.tree.map(lambda a: a[trial], chunk))):
            np.testing.assert_allclose(np.asarray(x), np.asarray(y), atol=1e-6)
