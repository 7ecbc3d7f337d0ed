"""Online self-organised training in the obstacle-free arena (thesis ch. 4.3 and 6.1).

One training step is one 1.024 s target-reaching period: sense u_p, command c_p from the map (plus
decaying exploration noise), move the robot (JAX kinematics, 10 % actuator noise), compute the
displacement v, learn. Targets are random points of the arena, one at a time; a new one is drawn when
the robot comes within ``reach`` of the current one, stops, or spends ``patience`` steps on it.

Performance (docs/design.md §7): a chunk of steps is one ``lax.scan``; trials are ``vmap``-ed; every random
number of the chunk is drawn before the scan.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm import maps
from ekm.config import EKMConfig
from ekm.learning import Adaptation, Trace, adapt, fresh_trace
from robots.kinematics import RobotState, advance_pose, egocentric, is_stop_command, quantize_command
from robots.params import KHEPERA, RobotParams
from training.schedules import Schedules


@dataclass(frozen=True)
class TrainConfig:
    """The training protocol of ch. 6.1 (defaults) and the arena it runs in."""

    steps: int = 100_000  # training steps of 1.024 s (ch. 6.1)
    trials: int = 5  # independent trials, averaged (ch. 6.1)
    arena: tuple[float, float] = (1.0, 1.0)  # m; the open-arena world's size
    margin: float = 0.1  # m; targets keep this far from the border
    # Targets anywhere in the arena (ch. 6.1: "a randomly selected sequence of targets"), as in the test.
    # Near targets (a number: within that distance of the robot) exercise M_k u_p more but leave the
    # far-target fallback M_k w_k (Eq. 4.5), which serves most test steps, less trained, so the map
    # reaches the test's targets more slowly.
    target_range: float | None = None  # m; None: anywhere in the arena
    # Dwell: a target stays for `patience` steps even once reached (reach = 0). The robot then sits on
    # it and learns that a zero displacement needs a zero command, which is what makes it *stop* at
    # the target in the test (Eq. 6.1); switching as soon as it is reached (reach > 0) leaves it orbiting.
    # 25 steps: a longer dwell slows reaching; a shorter one makes the polar chart's map stop less precisely.
    reach: float = 0.0  # m; > 0: a target closer than this (or a stop command) is done early
    patience: int = 25  # steps on one target before a new one is drawn
    schedules: Schedules = field(default_factory=Schedules)
    # Fine-tuning a trained map (``ekm train --init``): η and σ from this rule (``ekm.learning``) instead of
    # the decaying schedules, which are for a map that starts from nothing; the exploration stays.
    adapt: Adaptation | None = None

    def to_dict(self) -> dict:
        return asdict(self)


class Trainee(NamedTuple):
    """Per-trial training carry: the map, the robot, the current target, how long it has been on it, and the
    map's recent prediction error (:class:`ekm.learning.Trace`; fine-tuning only)."""

    ekm: object
    robot: RobotState
    target: jax.Array  # (2,)
    age: jax.Array  # int32: steps spent on the current target
    trace: Trace


def start(key, cfg: EKMConfig, tcfg: TrainConfig, ekm=None) -> Trainee:
    """A map — fresh, or ``ekm`` to go on training — and a robot at rest at the arena centre, heading along x,
    with a first target from ``key``."""
    centre = jnp.asarray([0.5 * tcfg.arena[0], 0.5 * tcfg.arena[1], 0.0], jnp.float32)
    robot = RobotState(pose=centre, wheels=jnp.zeros(2, jnp.float32))
    target = next_target(centre, jax.random.uniform(key, (2,)), tcfg)
    return Trainee(maps.init(cfg) if ekm is None else ekm, robot, target, jnp.zeros((), jnp.int32), fresh_trace())


def next_target(robot_pose, draw, tcfg: TrainConfig):
    """A new training target from ``draw`` ~ U[0, 1)²: anywhere in the arena, or — with ``target_range`` —
    at a uniform direction and a uniform distance up to ``target_range`` from the robot, kept in the arena.

    Near targets are what teaches an indirect map: a far target is served by the fallback c = M_k w_k
    (Eq. 4.5), the same command for every far target in that direction, which says nothing about the
    columns of M_k; a target inside the local sensory space is served by c = M_k u_p and varies it.
    """
    lo = jnp.asarray([tcfg.margin, tcfg.margin], jnp.float32)
    hi = jnp.asarray(tcfg.arena, jnp.float32) - tcfg.margin
    if tcfg.target_range is None:
        return lo + draw * (hi - lo)
    angle = 2.0 * jnp.pi * draw[0]
    offset = tcfg.target_range * draw[1] * jnp.stack([jnp.cos(angle), jnp.sin(angle)])
    return jnp.clip(robot_pose[:2] + offset, lo, hi)


def train_step(s: Trainee, draws, t, cfg: EKMConfig, tcfg: TrainConfig, params: RobotParams) -> Trainee:
    """One self-organised training step (ch. 4.3, steps 1–6). ``draws``: one step of :func:`draw_noise`;
    ``t`` the global step for the schedules."""
    xi_act, xi_explore, target_draw = draws
    sch = tcfg.schedules
    n = params.substeps(params.target_period)
    u = egocentric(s.robot.pose, s.target, jnp)  # 1. sensory input u_p
    c_p, _ = maps.control(s.ekm, u, cfg)  # 2. motor control (Eq. 4.5, or c_k)
    c_sent = quantize_command(c_p + sch.explore(t, tcfg.steps) * cfg.c_max * xi_explore, params, jnp)
    robot = advance_pose(s.robot, c_sent, xi_act, n, params, jnp)
    v = egocentric(s.robot.pose, robot.pose[:2], jnp)  # 3. actual displacement, seen from the start pose
    if tcfg.adapt is None:  # 4.–6.
        ekm, trace = maps.update(s.ekm, v, c_sent, sch.eta(t, tcfg.steps), sch.sigma(t, tcfg.steps), cfg), s.trace
    else:
        ekm, trace = adapt(s.ekm, v, c_sent, s.trace, tcfg.adapt, cfg)
    done = s.age + 1 >= tcfg.patience
    if tcfg.reach > 0:
        done = done | (egocentric(robot.pose, s.target, jnp)[1] < tcfg.reach) | is_stop_command(c_sent, params, jnp)
    target = jnp.where(done, next_target(robot.pose, target_draw, tcfg), s.target)
    return Trainee(ekm, robot, target, jnp.where(done, 0, s.age + 1), trace)


def draw_noise(key, length: int, params: RobotParams = KHEPERA):
    """All randomness of ``length`` training steps, drawn up front: slip ξ ``(length, K, 2)`` in (-1, 1)
    (:func:`robots.kinematics.slip`), exploration ξ ``(length, 2)`` standard normal, and U[0, 1)²
    ``(length, 2)`` for the next target.

    Each slip ξ is the centre of one of 2¹⁶ equal bins of (-1, 1), from half of a 32-bit draw: the two
    wheels share one draw, which halves the random bits generated, the bulk of the chunk's noise. Its
    resolution, 1.5e-6 of a wheel's speed, is far below the 8 mm/s speed unit.
    """
    k1, k2, k3 = jax.random.split(key, 3)
    draws = (length, params.noise_shape(params.target_period)[0])  # one per noise period, both wheels
    bits = jax.random.bits(k1, draws, jnp.uint32)
    halves = jnp.stack([bits >> 16, bits & 0xFFFF], axis=-1).astype(jnp.float32)
    return ((halves + 0.5) * (2.0 / 65536.0) - 1.0, jax.random.normal(k2, (length, 2)),
            jax.random.uniform(k3, (length, 2)))


@partial(jax.jit, static_argnames=("length", "cfg", "tcfg", "params"))
def train_chunk(trainees: Trainee, keys, t0, *, length: int, cfg: EKMConfig, tcfg: TrainConfig,
                params: RobotParams = KHEPERA) -> Trainee:
    """Advance every trial by ``length`` steps from global step ``t0``: ``vmap`` over trials of one ``lax.scan``.

    ``trainees`` and ``keys`` have a leading trial axis. All noise of the chunk is drawn up front.
    """

    def one_trial(s, key):
        draws = draw_noise(key, length, params)

        def body(s, x):
            draw, t = x
            return train_step(s, draw, t, cfg, tcfg, params), None

        ts = t0 + jnp.arange(length, dtype=jnp.float32)
        return jax.lax.scan(body, s, (draws, ts))[0]

    return jax.vmap(one_trial)(trainees, keys)
