"""The navigation task of ``ekm/Khepera-v0`` as a pure-JAX ``reset``/``step`` pair a JAX RL loop can ``jit`` and
``vmap`` itself (docs/jaxworld.md).

The task is :mod:`ekm.gym`'s, on the JAX engine (:mod:`robots.jaxworld.engine`): the planner's checkpoints are made
once on the host (:func:`make_task`, the plan ``ekm run`` starts with), then every tick is arrays only:

- **observation** ``(m + 2,)`` float32: the ``m`` IR readings (m from the body surface, the range where nothing is
  seen), then the current checkpoint as (α, d) from the pose;
- **action** ``(2,)`` wheel speeds (m/s), clipped to ±c* and rounded by the motors;
- **checkpoints**: the current one is passed when a sub-step comes within ``tolerance`` (5 mm) of it, or when the
  robot is within ``pass_radius`` of it and sees the next one — the straight line to it keeps ``min(15 mm, the
  robot's own slack) - 3 mm`` from the known shapes beyond the robot's radius (the test of :mod:`planner.visibility`
  with exact segment distances);
- **reward** ``10 Δroute − Δcollisions − 0.01``, and ``+10`` on reaching the goal without a collision, where
  ``route`` is the m still to go along the plan (to the current checkpoint, then leg by leg);
- **terminated** when the robot stands within ``tolerance`` of the goal and is sent a stop command (or has stood
  there ``settle_s``); **truncated** at the time limit.

Unlike ``ekm run`` (and the pymunk environment) there is no trap monitor and no replanning: a run that is stuck
stays stuck until the time limit, and a world whose timed events the planner is told of (``known``: the pymunk
environment replans on them) or whose goal moves is refused in one line. Movers move and unforeseen events fire (``dynamic``). Noise — slip ξ ~ U(-1, 1) ``(K, 2)`` and IR ξ ~ N(0, 1) ``(m,)`` — is drawn from
the state's PRNG key each tick.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from robots import kinematics
from robots.jaxworld import engine, moving
from robots.jaxworld.collide import clearance, gaps
from ekm.errors import InputError
from robots.jaxworld.scene import Scene, has_dynamics, scene_of
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.sensors import ir_readings

PROGRESS, COLLISION, TIME, GOAL = 10.0, 1.0, 0.01, 10.0  # ekm.gym's reward terms


@dataclass(frozen=True)
class TaskConfig:
    """What does not change from run to run (static under ``jit``): the robot, its sensors, the period's
    sub-steps ``n`` and slip draws ``k``, the time limit in ticks, the scenario's tolerances (m, ticks), and
    whether the world has movers or timed events to step (``dynamic``)."""

    params: RobotParams = KHEPERA
    sensors: SensorSet = KHEPERA.long_range
    n: int = 8
    k: int = 4
    ticks: int = 938  # 120 s of 0.128 s ticks, rounded up
    tolerance: float = 0.005
    settle_ticks: int = 8  # 1.024 s
    pass_radius: float = 0.1
    dynamic: bool = False


class Task(NamedTuple):
    """One world's arrays: ``scene`` (every shape) and ``sight`` (the shapes on the planner's map), ``start``
    ``(3,)``, ``checkpoints`` ``(K, 2)`` (goal last, padded by repeating it), ``last`` (the goal's index),
    ``legs`` ``(K,)`` — m along the plan from checkpoint i to the goal — and what every run starts with: the
    checkpoint headed for ``first`` and the true IR ranges ``start_ranges`` ``(m,)`` at the start."""

    scene: Scene
    sight: Scene
    start: object
    checkpoints: object
    last: object
    legs: object
    first: object
    start_ranges: object


class TaskState(NamedTuple):
    """``engine``: the world's state; ``index``: the checkpoint headed for; ``route``: m still to go; ``settled``:
    ticks stood within the goal's tolerance; ``tick``; ``key``: the run's PRNG key; ``ir``: the last readings."""

    engine: engine.EngineState
    index: object
    route: object
    settled: object
    tick: object
    key: object
    ir: object


def make_task(world, config: TaskConfig = TaskConfig(), checkpoints: str = "visible", slots: int | None = None,
              shape=None) -> Task:
    """Plan ``world`` on the host and lay it out as a :class:`Task`: checkpoints padded to ``slots`` (default their
    number), the scene to ``shape`` (``(C, P, V)``, :func:`robots.jaxworld.scene.scene_of`)."""
    from dataclasses import replace as dc_replace

    from planner import plan

    if world.moving_goal:
        raise InputError(f"engine jax: world {world.name!r} has a moving goal, which the JAX environment does not "
                         f"simulate; use the pymunk environment")
    if any(e.known for e in world.events):
        raise InputError(f"engine jax: world {world.name!r} has timed events the planner is told of, and the JAX "
                         f"environment does not replan; use the pymunk environment")
    if has_dynamics(world) and not config.dynamic:
        raise ValueError(f"world {world.name!r} has movers or timed events: make its task with a dynamic config")
    route = plan(world, t=0.0, checkpoints=checkpoints, padding=config.params.radius).checkpoints
    route = np.asarray(route, np.float32)
    slots = len(route) if slots is None else slots
    if len(route) > slots:
        raise ValueError(f"world {world.name!r} has {len(route)} checkpoints, more than {slots} slots")
    padded = np.concatenate([route, np.repeat(route[-1:], slots - len(route), axis=0)])
    leg = np.linalg.norm(np.diff(padded, axis=0), axis=1)
    legs = np.concatenate([np.cumsum(leg[::-1])[::-1], [0.0]]).astype(np.float32)
    known = dc_replace(world, unforeseen=())
    task = Task(scene=scene_of(world, shape), sight=scene_of(known, shape), start=np.asarray(world.start, np.float32),
                checkpoints=padded, last=np.int32(len(route) - 1), legs=legs, first=np.int32(0),
                start_ranges=np.zeros(len(config.sensors.angles), np.float32))
    first = _pass(jnp.asarray(task.start[:2]), jnp.int32(0), task, config)
    fired = engine.reset(task.start, task.scene, config.params).fired  # events due at 0 and clear of the robot
    ranges = engine.ranges(jnp.asarray(task.start), moving.placed(task.scene, jnp.float32(0.0), fired), config.sensors,
                           config.params.radius)
    return task._replace(first=np.int32(first), start_ranges=np.asarray(ranges, np.float32))


def _route(pose, index, task: Task):
    return jnp.linalg.norm(pose[:2] - task.checkpoints[index]) + task.legs[index]


def sight_need(pos, sight: Scene, radius: float):
    """The slack (m) a straight line from ``pos`` ``(2,)`` must keep from the known shapes ``sight`` beyond the
    robot's ``radius`` to count as seen: ``min(MARGIN / 2, the robot's own slack here) - TOLERANCE``
    (:func:`evaluation.scenario._sight_need`, :mod:`planner.visibility`'s constants)."""
    from planner.visibility import MARGIN, TOLERANCE

    return jnp.minimum(0.5 * MARGIN, jnp.min(gaps(pos, sight)[0]) - radius) - TOLERANCE


def sees(pos, point, sight: Scene, radius: float, need):
    """Whether the straight line from ``pos`` to ``point`` ``(2,)`` keeps ``need`` (:func:`sight_need`) beyond the
    robot's ``radius`` from every shape of ``sight`` — exact segment distances, where :mod:`planner.visibility`
    samples the line every 2 mm (so the two may differ by a millimetre of slack)."""
    return clearance(pos, point, sight) - radius >= need


def sees_next(pos, checkpoints, index, sight: Scene, radius: float, pass_radius: float, need):
    """Within ``pass_radius`` of ``checkpoints[index]`` ``(K, 2)`` and seeing the next one (:func:`sees`, with
    ``need`` the :func:`sight_need` at ``pos``, worked out once for every checkpoint asked about): the checkpoint
    was a corner to get round, and from ``pos`` there is nothing left to get round."""
    nxt = checkpoints[jnp.minimum(index + 1, checkpoints.shape[0] - 1)]
    near = jnp.linalg.norm(pos - checkpoints[index]) <= pass_radius
    return near & sees(pos, nxt, sight, radius, need)


def _pass(pos, index, task: Task, config: TaskConfig):
    """The checkpoint headed for after those already within reach or seen past (at most two a tick)."""
    radius = config.params.radius
    need = sight_need(pos, task.sight, radius)
    for _ in range(2):
        within = jnp.linalg.norm(pos - task.checkpoints[index]) < config.tolerance
        seen = sees_next(pos, task.checkpoints, index, task.sight, radius, config.pass_radius, need)
        index = jnp.where((index < task.last) & (within | seen), index + 1, index)
    return index


def _observe(state: TaskState, task: Task, config: TaskConfig):
    ir = jnp.where(jnp.isfinite(state.ir), jnp.minimum(state.ir, config.sensors.range_m), config.sensors.range_m)
    target = kinematics.egocentric(state.engine.robot.pose, task.checkpoints[state.index], xp=jnp)
    return jnp.concatenate([ir, target]).astype(jnp.float32)


def _noise(key, config: TaskConfig):
    return jax.random.normal(key, (len(config.sensors.angles),))


def reset(key, task: Task, config: TaskConfig = TaskConfig()):
    """A run from the world's start: ``(state, observation)``. Only the IR noise is drawn: the rest of the start is
    the same for every run (:func:`make_task` worked it out)."""
    key, sub = jax.random.split(key)
    eng = engine.reset(task.start, task.scene, config.params)
    ir = ir_readings(task.start_ranges, _noise(sub, config), config.sensors, xp=jnp)
    state = TaskState(eng, task.first, _route(task.start, task.first, task), jnp.int32(0), jnp.int32(0), key, ir)
    return state, _observe(state, task, config)


def step(state: TaskState, action, task: Task, config: TaskConfig = TaskConfig()):
    """One 0.128 s tick: ``(state, observation, reward, terminated, truncated)`` (module docstring)."""
    p = config.params
    key, k_slip, k_ir = jax.random.split(state.key, 3)
    pose = state.engine.robot.pose
    final = state.index == task.last
    at_goal = final & (jnp.linalg.norm(pose[:2] - task.checkpoints[task.last]) < config.tolerance)
    settled = jnp.where(at_goal, state.settled + 1, 0)
    stopped = at_goal & (kinematics.is_stop_command(action, p, jnp) | (settled > config.settle_ticks))
    command = jnp.where(stopped, 0.0, jnp.asarray(action, jnp.float32))
    slip = jax.random.uniform(k_slip, (config.k, 2), minval=-1.0, maxval=1.0)
    eng, trace = engine.step(state.engine, task.scene, command, slip, p, config.n, config.dynamic)
    near = jnp.any(jnp.linalg.norm(trace[:, :2] - task.checkpoints[state.index], axis=1) < config.tolerance)
    index = jnp.where(~final & near, state.index + 1, state.index)
    index = _pass(eng.robot.pose[:2], index, task, config)
    route = jnp.where(stopped, jnp.linalg.norm(eng.robot.pose[:2] - task.checkpoints[task.last]),
                      _route(eng.robot.pose, index, task))
    new = eng.collisions - state.engine.collisions
    reward = PROGRESS * (state.route - route) - COLLISION * new - TIME + jnp.where(stopped & (eng.collisions == 0),
                                                                                    GOAL, 0.0)
    ir = engine.sense(eng, task.scene, config.sensors, _noise(k_ir, config), p, config.dynamic)
    state = TaskState(eng, index, route, settled, state.tick + 1, key, ir)
    truncated = ~stopped & (state.tick >= config.ticks)
    return state, _observe(state, task, config), reward.astype(jnp.float32), stopped, truncated


def config_for(robot: RobotParams = KHEPERA, sensors: str = "long", time_limit: float = 120.0,
               dynamic: bool = False) -> TaskConfig:
    """The :class:`TaskConfig` of a robot, its ``"long"`` or ``"short"`` IR ring, a time limit (s), and whether the
    world has movers or timed events."""
    ring = robot.long_range if sensors == "long" else robot.short_range
    n = robot.substeps(robot.avoid_period)
    ticks = int(np.ceil(time_limit / robot.avoid_period - 1e-9))
    return replace(TaskConfig(), params=robot, sensors=ring, n=n, k=robot.noise_shape(robot.avoid_period)[0],
                   ticks=ticks, settle_ticks=robot.substeps(robot.target_period) // n, dynamic=dynamic)
