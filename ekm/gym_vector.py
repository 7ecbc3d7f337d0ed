"""``ekm/Khepera-v0`` as one vector environment on the JAX engine: N robots per call, one ``jit``-ed ``vmap``.

    import gymnasium
    import ekm.gym                                   # registers ekm/Khepera-v0 (and its vector entry point)
    envs = gymnasium.make_vec("ekm/Khepera-v0", num_envs=4096, vectorization_mode="vector_entry_point",
                              world="three-rooms")
    obs, info = envs.reset(seed=0)                   # (4096, 14) float32
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())

The task — observation, action, reward, checkpoints — is :mod:`robots.jaxworld.task`'s, which is
:mod:`ekm.gym`'s without the trap monitor's replanning. **Autoreset** is Gymnasium's default, next-step
(``metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP``): the step after a sub-environment's episode ends
resets it — its action is ignored, and it returns the new episode's first observation with reward 0 and
``terminated = truncated = False``. ``reset(seed=s)`` gives sub-environment ``i`` the PRNG key ``fold_in(key(s),
i)``: the same seed, the same runs, whatever else runs beside them. Moving obstacles move and unforeseen timed
events fire; worlds with a moving goal or with events the planner is told of (the pymunk environment replans on
them) are refused in one line.
"""

from __future__ import annotations

import math
from functools import partial
from typing import ClassVar

import jax
import jax.numpy as jnp
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from robots.jaxworld import task as jt
from robots.jaxworld.scene import has_dynamics


@partial(jax.jit, static_argnames="config")
def _reset_all(keys, task, config):
    return jax.vmap(jt.reset, in_axes=(0, None, None))(keys, task, config)


#: Runs stepped together inside one call: larger batches go through in blocks of this many (``lax.map`` of a
#: ``vmap``), which keeps a block's arrays in cache: on CPU, one ``vmap`` of thousands of runs is several times
#: slower a run (docs/performance.md has the measurements).
BLOCK = 16


def _where(done, a, b):
    """``a`` where ``done`` ``(B,)``, else ``b``: leaves of two pytrees with a leading axis B."""
    return jax.tree.map(lambda x, y: jnp.where(done.reshape(done.shape + (1,) * (x.ndim - 1)), x, y), a, b)


def _step_block(state, action, done, task, config):
    """Step a block of runs (leading axis B), resetting those whose episode ended on the last call (next-step
    autoreset). The resets are worked out only in a block that has one (``lax.cond`` outside the ``vmap``):
    episodes are hundreds of ticks long, so most blocks have none."""
    stepped, obs, reward, terminated, truncated = jax.vmap(partial(jt.step, task=task, config=config))(state, action)

    def fresh(_):
        new, new_obs = jax.vmap(partial(jt.reset, task=task, config=config))(stepped.key)
        return _where(done, new, stepped), _where(done, new_obs, obs)

    state, obs = jax.lax.cond(jnp.any(done), fresh, lambda _: (stepped, obs), None)
    return state, obs, jnp.where(done, 0.0, reward), terminated & ~done, truncated & ~done


@partial(jax.jit, static_argnames="config")
def _step_all(state, actions, done, task, config):
    """Every run's step in blocks of :data:`BLOCK` (:func:`_step_block`; the last block padded with copies of run 0
    that are dropped)."""
    n = actions.shape[0]
    block = min(BLOCK, n)
    pad = -n % block
    xs = jax.tree.map(lambda a: jnp.concatenate([a, jnp.repeat(a[:1], pad, axis=0)]) if pad else a,
                      (state, actions, done))
    xs = jax.tree.map(lambda a: a.reshape(((n + pad) // block, block) + a.shape[1:]), xs)
    out = jax.lax.map(lambda x: _step_block(*x, task=task, config=config), xs)
    return jax.tree.map(lambda a: a.reshape((n + pad,) + a.shape[2:])[:n], out)


class KheperaVectorEnv(VectorEnv):
    """``num_envs`` robots in one world (module docstring). ``world``: a named world, a world file or
    ``FAMILY:SEED``; ``sensors``: ``"long"`` or ``"short"``; ``time_limit`` (simulated s); ``checkpoints``:
    ``"visible"`` or ``"thesis"``; ``robot``: a named robot or a robot file."""

    metadata: ClassVar[dict] = {"autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, world: str = "three-rooms", sensors: str = "long",
                 time_limit: float = 120.0, checkpoints: str = "visible", robot=None, max_episode_steps=None):
        from ekm.api.worlds import world as load_world
        from ekm.errors import InputError
        from robots.robotfile import load_robot

        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise InputError(f"num_envs: must be a positive integer, got {num_envs!r}")
        if sensors not in ("long", "short"):
            raise InputError(f"sensors: must be long or short, got {sensors!r}")
        if not (isinstance(time_limit, (int, float)) and math.isfinite(time_limit) and time_limit > 0):
            raise InputError(f"time_limit: must be a positive number of seconds, got {time_limit!r}")
        if max_episode_steps is not None:
            time_limit = min(time_limit, max_episode_steps * load_robot(robot).avoid_period)
        self.world = load_world(world)
        self.robot = load_robot(robot)
        self.config = jt.config_for(self.robot, sensors, time_limit, has_dynamics(self.world))
        self.task = jax.tree.map(jnp.asarray, jt.make_task(self.world, self.config, checkpoints))
        self.num_envs = int(num_envs)
        m = len(self.config.sensors.angles)
        far = float(math.hypot(*self.world.size))
        self.single_observation_space = spaces.Box(
            low=np.array([0.0] * m + [-math.pi, 0.0], np.float32),
            high=np.array([self.config.sensors.range_m] * m + [math.pi, far], np.float32), dtype=np.float32)
        c = self.robot.max_wheel_speed
        self.single_action_space = spaces.Box(low=-c, high=c, shape=(2,), dtype=np.float32)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._state, self._done = None, None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start every run; ``seed`` as in the module docstring (without one, drawn from ``np_random``)."""
        super().reset(seed=seed)
        base = int(seed) if seed is not None else int(self.np_random.integers(0, 2**31 - 1))
        keys = jax.vmap(partial(jax.random.fold_in, jax.random.key(base)))(jnp.arange(self.num_envs))
        self._state, obs = _reset_all(keys, self.task, config=self.config)
        self._done = jnp.zeros(self.num_envs, bool)
        return np.asarray(obs), {}

    def step(self, actions):
        if self._state is None:
            raise RuntimeError("ekm/Khepera-v0: call reset() before step()")
        actions = np.asarray(actions, np.float32).reshape(self.num_envs, 2)
        if not np.isfinite(actions).all():
            raise ValueError("ekm/Khepera-v0: every action must be two finite wheel speeds")
        self._state, obs, reward, terminated, truncated = _step_all(self._state, actions, self._done, self.task,
                                                                            config=self.config)
        self._done = terminated | truncated
        return (np.asarray(obs), np.asarray(reward), np.asarray(terminated), np.asarray(truncated), {})

    def close_extras(self, **kwargs):
        self._state = None


def make(num_envs: int = 1, **kwargs) -> KheperaVectorEnv:
    """The vector entry point of ``ekm/Khepera-v0`` (what ``gymnasium.make_vec`` calls)."""
    return KheperaVectorEnv(num_envs=num_envs, **kwargs)
