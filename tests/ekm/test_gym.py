"""The Gymnasium environment (ekm.gym): it passes Gymnasium's checker, works vectorised, gives the run
``ekm run`` gives for the same seed when a controller drives it, and pays the documented reward."""

import jax
import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import ekm  # noqa: E402
import ekm.gym  # noqa: E402
from ekm.gym import KheperaEnv  # noqa: E402


@pytest.mark.parametrize("sensors", ["long", "short"])
def test_gymnasium_s_checker_passes(sensors):
    from gymnasium.utils.env_checker import check_env

    check_env(KheperaEnv(world="open-arena", sensors=sensors, render_mode="rgb_array"), skip_render_check=False)


def test_make_and_make_vec_give_the_registered_environment():
    env = gymnasium.make("ekm/Khepera-v0", world="three-rooms", sensors="short")
    obs, _ = env.reset(seed=0)
    assert obs.shape == (8 + 2,) and env.action_space.high.tolist() == pytest.approx([0.16, 0.16])
    vec = gymnasium.make_vec("ekm/Khepera-v0", num_envs=2, vectorization_mode="sync", world="open-arena")
    obs, _ = vec.reset(seed=0)
    obs, reward, terminated, truncated, _ = vec.step(np.zeros((2, 2), np.float32))
    assert obs.shape == (2, 14) and reward.shape == (2,) and not terminated.any()


def drive(env, controller, seed):
    """The controller through the environment: the last step's info and the sum of rewards."""
    _, info = env.reset(seed=seed)
    state, total = controller.init(), 0.0
    while True:
        state, command = controller.step(state, info["observation"])
        _, reward, terminated, truncated, info = env.step(np.asarray(command))
        total += reward
        if terminated or truncated:
            return info, total, terminated


@pytest.mark.parametrize("world, seed", [("concave-obstacle", 4), ("three-rooms-changed", 1)])
def test_the_shipped_fields_through_the_environment_end_as_ekm_run_does(world, seed):
    from ekm.data import load_default_map
    from robots.controllers.spec import parse_architecture

    spec = parse_architecture("fields")
    maps = load_default_map(spec.default_chart)
    controller = spec.build(jax.tree.map(lambda a: a[seed % maps.trials], maps.ekm), maps.cfg)
    env = KheperaEnv(world=world)
    info, total, terminated = drive(env, controller, seed)
    skip = ("architecture", "map", "trial", "map_robot")  # the environment drives no named architecture or map
    run = ekm.run(world, "fields", seed=seed).to_dict()
    assert {k: v for k, v in info["outcome"].items() if k not in skip} == \
        {k: run[k] for k in info["outcome"] if k not in skip}
    assert terminated and info["outcome"]["reached"]


def test_the_reward_is_progress_collisions_time_and_the_goal():
    """Standing still earns −0.01 a step (no progress, no collision); driving a run home earns 10 × the route
    it covered, −0.01 a step and +10 at the goal (no collision)."""
    env = KheperaEnv(world="open-arena", time_limit=1.0)
    env.reset(seed=0)
    rewards, done = [], False
    while not done:
        _, reward, terminated, truncated, info = env.step([0.0, 0.0])
        rewards.append(reward)
        done = terminated or truncated
    assert np.allclose(rewards, -0.01) and len(rewards) == 8  # 1 s of 0.128 s ticks
    assert truncated and not terminated and info["outcome"]["ended"] == "time limit"
    with pytest.raises(RuntimeError, match="call reset"):
        env.step([0.0, 0.0])

    from ekm.data import load_default_map
    from robots.controllers.spec import parse_architecture

    spec = parse_architecture("fields")
    maps = load_default_map(spec.default_chart)
    controller = spec.build(jax.tree.map(lambda a: a[0], maps.ekm), maps.cfg)
    env = KheperaEnv(world="open-arena")
    _, first = env.reset(seed=0)
    route = float(np.hypot(*(np.asarray(env.world.goal) - np.asarray(env.world.start[:2]))))  # open arena: a line
    info, total, terminated = drive(env, controller, 0)
    steps = len(info["record"].commands) + 1  # the commands sent, and the step on which the run stopped
    covered = route - info["outcome"]["final_distance_m"]  # it stops within 5 mm of the goal
    assert terminated and total == pytest.approx(10 * covered - 0.01 * steps + 10, abs=1e-3)


def test_the_same_seed_gives_the_same_run_and_rendering_is_an_image():
    env = KheperaEnv(world="three-rooms", render_mode="rgb_array")
    actions = np.random.default_rng(0).uniform(-0.16, 0.16, (30, 2))
    runs = []
    for _ in range(2):
        obs, _ = env.reset(seed=7)
        runs.append([obs] + [env.step(a)[0] for a in actions])
    assert all(np.array_equal(a, b) for a, b in zip(*runs))
    image = env.render()
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
