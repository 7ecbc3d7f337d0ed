"""The chapter 6.1 test: from the arena centre, a fixed sequence of random targets, no learning.

For each target the robot is driven by the map until it stops (every wheel command rounds to zero,
"motor control c = 0", Eq. 6.1) or a step cap is reached, then the next target is presented from
where it stands. Sub-step traces give first-passage times and path lengths at 16 ms resolution.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm import maps
from ekm.config import EKMConfig
from robots.kinematics import RobotState, advance, egocentric, is_stop_command, quantize_command
from robots.params import KHEPERA, RobotParams

#: Tolerances ε of P(ε), T(ε), D(ε), in metres (thesis ch. 6.1; 25 mm is the robot's radius).
EPSILONS = (0.005, 0.010, 0.025)


class TargetRecord(NamedTuple):
    """What happened at one target (arrays gain leading axes under vmap)."""

    error: jax.Array  # m: distance centre → target after stopping (ε_i of Eq. 6.1)
    capped: jax.Array  # bool: the step cap was hit before the robot stopped
    straight: jax.Array  # m: l_i, straight distance from the previous target (or the start)
    hit: jax.Array  # (len(EPSILONS),) bool: came closer than ε, with or without stopping
    time: jax.Array  # (len(EPSILONS),) steps until first closer than ε (t_i(ε) of Eq. 6.2)
    path: jax.Array  # (len(EPSILONS),) m travelled until first closer than ε (d_i(ε) of Eq. 6.3)
    steps: jax.Array  # int: control steps spent on this target
    bearing: jax.Array  # rad: α of u_p when the target is presented (where the robot has to turn)


def _drive_to(control, robot: RobotState, target, previous, noise, params: RobotParams, eps, keep_path: bool = False):
    """Drive to one ``target`` for at most ``len(noise)`` steps. ``previous``: where l_i is measured from.

    Returns ``(robot, (record, xy))`` — the scan carry and output of :func:`drive_test` — where ``xy``
    ``(steps, n, 2)`` is the centre after every sub-step if ``keep_path``, else None."""
    n = params.substeps(params.target_period)
    n_eps = eps.shape[0]

    def body(carry, xi):
        robot, stopped, hit, time, path, travelled, k = carry
        c_p = control(egocentric(robot.pose, target, jnp))
        stop_now = stopped | is_stop_command(c_p, params, jnp)
        # Once stopped the set-point is zero: the wheels spin down (motor lag) and the robot comes to rest.
        setpoint = jnp.where(stop_now, 0.0, quantize_command(c_p, params, jnp))
        before = robot.pose[:2]
        robot, trace = advance(robot, setpoint, xi, n, params, jnp)
        xy = jnp.concatenate([before[None, :], trace[:, :2]], axis=0)  # (n+1, 2)
        seg = jnp.linalg.norm(jnp.diff(xy, axis=0), axis=-1)  # (n,)
        cum = travelled + jnp.cumsum(seg)
        dist = jnp.linalg.norm(trace[:, :2] - target, axis=-1)  # (n,)
        inside = dist[None, :] < eps[:, None]  # (n_eps, n)
        first = jnp.argmax(inside, axis=1)
        new_hit = ~hit & jnp.any(inside, axis=1)
        time = jnp.where(new_hit, k + (first + 1.0) / n, time)
        path = jnp.where(new_hit, cum[first], path)
        travelled = cum[-1]
        k = jnp.where(stop_now, k, k + 1)
        return (robot, stop_now, hit | new_hit, time, path, travelled, k), trace[:, :2] if keep_path else None

    straight = jnp.linalg.norm(target - previous)
    alpha0, d0 = egocentric(robot.pose, target, jnp)
    hit0 = d0 < eps  # already there
    init = (robot, jnp.asarray(False), hit0, jnp.zeros(n_eps), jnp.zeros(n_eps), jnp.asarray(0.0), jnp.asarray(0))
    (robot, stopped, hit, time, path, _, k), xy = jax.lax.scan(body, init, noise)
    error = jnp.linalg.norm(robot.pose[:2] - target)
    return robot, (TargetRecord(error, ~stopped, straight, hit, time, path, k, alpha0), xy)


def drive_test(control, targets, start_pose, key, *, cap: int = 50, params: RobotParams = KHEPERA,
               keep_path: bool = False):
    """The ch. 6.1 test of any controller: visit ``targets`` ``(N, 2)`` in order from ``start_pose``.

    ``control(u_p) -> c`` maps the target input (α, d) to wheel commands; it must be a pure JAX function
    (the whole test is one nested ``lax.scan``). Returns one :class:`TargetRecord` per target (leading
    axis N). Used for the maps (:func:`run_test`) and for analytic reference controllers (benchmarks).
    With ``keep_path`` it returns ``(records, xy)``, ``xy`` ``(N, cap, n, 2)`` the robot's centre after
    every sub-step (it stands still once it has stopped).
    """
    noise = jax.random.uniform(key, (targets.shape[0], cap) + params.noise_shape(params.target_period),
                               minval=-1.0, maxval=1.0)
    eps = jnp.asarray(EPSILONS, jnp.float32)
    robot = RobotState(jnp.asarray(start_pose, jnp.float32), jnp.zeros(2, jnp.float32))
    previous = jnp.concatenate([robot.pose[None, :2], targets[:-1]], axis=0)

    def body(robot, x):
        target, prev, xi = x
        return _drive_to(control, robot, target, prev, xi, params, eps, keep_path)

    records, xy = jax.lax.scan(body, robot, (targets, previous, noise))[1]
    return (records, xy) if keep_path else records


@partial(jax.jit, static_argnames=("cfg", "cap", "params", "keep_path"))
def run_test(ekm, targets, start_pose, key, *, cfg: EKMConfig, cap: int = 50, params: RobotParams = KHEPERA,
             keep_path: bool = False):
    """The ch. 6.1 test of one map (:func:`drive_test` with c_p from Eq. 4.5 or c_k). ``vmap`` it over trials."""
    return drive_test(lambda u: maps.control(ekm, u, cfg)[0], targets, start_pose, key, cap=cap, params=params,
                      keep_path=keep_path)


def test_targets(n: int, arena, *, seed: int = 0, margin: float = 0.1):
    """The fixed test sequence: ``n`` points uniform in the arena, ``margin`` from its border (ch. 6.1)."""
    lo = jnp.asarray([margin, margin], jnp.float32)
    hi = jnp.asarray(arena, jnp.float32) - margin
    return jax.random.uniform(jax.random.PRNGKey(seed), (n, 2), jnp.float32, lo, hi)


def _test_setup(arena, targets: int, seed: int, trials: int):
    """The test's target sequence, start pose (arena centre, heading along x) and per-trial noise keys."""
    pts = test_targets(targets, arena, seed=seed)
    centre = jnp.asarray([0.5 * arena[0], 0.5 * arena[1], 0.0], jnp.float32)
    keys = jax.random.split(jax.random.fold_in(jax.random.PRNGKey(seed), 1), trials)
    return pts, centre, keys


def evaluate(ekm_stack, cfg: EKMConfig, arena, *, targets: int = 50, seed: int = 0, cap: int = 50,
             params: RobotParams = KHEPERA) -> TargetRecord:
    """Run the ch. 6.1 test for every map of ``ekm_stack`` (leading trial axis) on the same target
    sequence (from ``seed``), each trial with its own actuator noise. Returns records ``(trials, targets)``."""
    pts, centre, keys = _test_setup(arena, targets, seed, ekm_stack.w.shape[0])
    return _evaluate_stack(ekm_stack, pts, centre, keys, cfg=cfg, cap=cap, params=params)


def trace_paths(ekm_stack, cfg: EKMConfig, arena, *, targets: int = 50, seed: int = 0, cap: int = 50,
               params: RobotParams = KHEPERA):
    """The paths of the first trial's map in :func:`evaluate`'s test (same targets, same noise).

    Returns ``(targets_xy (N, 2), start (3,), xy (N, cap · n, 2), records)``: the robot's centre after every
    sub-step while it was on each target, and that trial's :class:`TargetRecord`.
    """
    pts, centre, keys = _test_setup(arena, targets, seed, ekm_stack.w.shape[0])
    first = jax.tree.map(lambda a: a[0], ekm_stack)
    records, xy = run_test(first, pts, centre, keys[0], cfg=cfg, cap=cap, params=params, keep_path=True)
    return pts, centre, xy.reshape(xy.shape[0], -1, 2), records


@partial(jax.jit, static_argnames=("cfg", "cap", "params"))
def _evaluate_stack(ekm_stack, pts, centre, keys, *, cfg, cap, params):
    return jax.vmap(lambda m, k: run_test(m, pts, centre, k, cfg=cfg, cap=cap, params=params))(ekm_stack, keys)
