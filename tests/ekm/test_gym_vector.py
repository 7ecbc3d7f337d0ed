"""The vector environment on the JAX engine (ekm.gym_vector) and its pure-JAX task (robots.jaxworld.task):
``make_vec`` with the vector entry point, seeds, next-step autoreset, and rewards worked out by hand."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import ekm.gym  # noqa: F401
from ekm.errors import InputError
from ekm.gym_vector import KheperaVectorEnv
from robots.jaxworld import task as jt
from robots.worldfile import parse_world


def test_make_vec_with_the_vector_entry_point_gives_the_jax_environment():
    envs = gymnasium.make_vec("ekm/Khepera-v0", num_envs=3, vectorization_mode="vector_entry_point",
                              world="open-arena")
    assert isinstance(envs, KheperaVectorEnv) and envs.num_envs == 3
    assert envs.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.NEXT_STEP
    obs, _ = envs.reset(seed=0)
    assert obs.shape == (3, 14) and obs.dtype == np.float32 and envs.observation_space.contains(obs)
    obs, reward, terminated, truncated, _ = envs.step(np.zeros((3, 2), np.float32))
    assert reward.shape == terminated.shape == truncated.shape == (3,) and envs.observation_space.contains(obs)


def test_a_seed_gives_each_sub_environment_its_own_run_whatever_runs_beside_it():
    two, three = KheperaVectorEnv(2, world="open-arena"), KheperaVectorEnv(3, world="open-arena")
    a, _ = two.reset(seed=7)
    b, _ = three.reset(seed=7)
    assert np.array_equal(a, b[:2])
    actions = np.full((3, 2), 0.1, np.float32)
    a = two.step(actions[:2])[0]
    b = three.step(actions)[0]
    assert np.array_equal(a, b[:2])
    assert len({tuple(row) for row in b[:, -2:].tolist()}) == 3  # each its own slip: three different poses


@pytest.mark.parametrize("n", [2, 17])  # 17: a whole block of 16 and one run in a padded block
def test_next_step_autoreset_after_the_time_limit(n):
    # a 2-tick limit (0.256 s): the 2nd step truncates every run; the 3rd resets it — reward 0, neither flag, and
    # the first observation of a new run (at the start: the first checkpoint where it was at the first reset)
    envs = KheperaVectorEnv(n, world="open-arena", time_limit=0.256)
    first, _ = envs.reset(seed=0)
    go = np.full((n, 2), 0.12, np.float32)
    _, _, terminated, truncated, _ = envs.step(go)
    assert not truncated.any() and not terminated.any()
    moved, _, terminated, truncated, _ = envs.step(go)
    assert truncated.all() and not terminated.any()
    assert not np.allclose(moved[:, -2:], first[:, -2:])
    again, reward, terminated, truncated, _ = envs.step(go)
    assert reward.tolist() == [0.0] * n and not terminated.any() and not truncated.any()
    assert again[:, -2:] == pytest.approx(first[:, -2:], abs=1e-6)
    _, reward, _, _, _ = envs.step(go)
    assert (reward != 0).all()  # the new run goes on


def _task(world, time_limit=5.0):
    config = jt.config_for(time_limit=time_limit)
    return jax.tree.map(jnp.asarray, jt.make_task(world, config)), config


def test_standing_still_costs_the_time_term_alone():
    task, config = _task(parse_world({"name": "w", "size": [1.0, 0.5], "start": [0.2, 0.25, 0.0],
                                      "goal": [0.8, 0.25]}, "w.json"))
    state, obs = jt.reset(jax.random.key(0), task, config)
    # start to goal: 0.6 m straight ahead, one checkpoint (the goal): the observation's target is (0, 0.6)
    assert np.asarray(obs[-2:]) == pytest.approx([0.0, 0.6], abs=1e-6)
    state, obs, reward, terminated, truncated = jax.jit(jt.step, static_argnums=3)(state, jnp.zeros(2), task, config)
    assert float(reward) == pytest.approx(-0.01, abs=1e-7) and not terminated and not truncated


def test_stopping_at_the_goal_ends_the_run_with_the_goal_bonus():
    # start 2 mm from the goal: within the 5 mm tolerance, a stop command ends the run; the route (2 mm) is
    # unchanged, so the reward is 10 * 0 - 0.01 + 10 = 9.99
    task, config = _task(parse_world({"name": "w", "size": [1.0, 0.5], "start": [0.5, 0.25, 0.0],
                                      "goal": [0.502, 0.25]}, "w.json"))
    state, obs = jt.reset(jax.random.key(1), task, config)
    assert float(obs[-1]) == pytest.approx(0.002, abs=1e-6)
    state, _, reward, terminated, truncated = jt.step(state, jnp.zeros(2), task, config)
    assert bool(terminated) and not bool(truncated)
    assert float(reward) == pytest.approx(9.99, abs=1e-5)


def test_driving_towards_the_goal_pays_ten_per_metre():
    # 0.08 m/s straight at the goal, noise-free motors would move 8 sub-steps of the lagged speed; whatever the
    # slip, the reward is 10 x (the metres the robot came closer) - 0.01
    task, config = _task(parse_world({"name": "w", "size": [1.0, 0.5], "start": [0.2, 0.25, 0.0],
                                      "goal": [0.8, 0.25]}, "w.json"))
    state, _ = jt.reset(jax.random.key(2), task, config)
    x0 = float(state.engine.robot.pose[0])
    state, _, reward, _, _ = jt.step(state, jnp.array([0.08, 0.08]), task, config)
    pose = np.asarray(state.engine.robot.pose)
    closer = 0.6 - math.hypot(0.8 - pose[0], 0.25 - pose[1])
    assert pose[0] - x0 > 0.005
    assert float(reward) == pytest.approx(10 * closer - 0.01, abs=1e-5)


def test_bad_input_is_refused_in_one_line():
    with pytest.raises(InputError, match=r"^num_envs: must be a positive integer, got 0$"):
        KheperaVectorEnv(0)
    with pytest.raises(InputError, match=r"^sensors: must be long or short"):
        KheperaVectorEnv(1, sensors="mid")
    with pytest.raises(InputError, match=r"^engine jax: world 'three-rooms-changed' has timed events the planner is "
                                          r"told of, and the JAX environment does not replan"):
        KheperaVectorEnv(1, world="three-rooms-changed")
    with pytest.raises(InputError, match=r"^engine jax: world 'moving-target' has a moving goal"):
        KheperaVectorEnv(1, world="moving-target")
