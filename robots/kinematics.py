"""Differential-drive kinematics with motor lag and actuator noise — one model, two array back-ends.

The same functions run on NumPy (the pymunk world, the NumPy references) and on ``jax.numpy`` (the
jitted training loops): pass ``xp=np`` or ``xp=jnp``. They are pure and shape-polymorphic, so they
``jit`` and ``vmap`` without change.

Model (docs/design.md §2), per control period of ``n`` sub-steps of ``dt``:

1. the command ``c = (v_l, v_r)`` is clipped to ``±c*`` and rounded to the speed unit (the set-point);
2. each wheel follows that set-point with a first-order lag,
   ``s_j = c + (s_0 - c) exp(-j dt / τ)``, held constant through sub-step ``j``;
3. each wheel slips: its speed is multiplied by ``1 + σ ξ``, ``ξ ~ U(-1, 1)`` redrawn every
   ``noise_period`` (Webots' slip noise, :class:`~robots.params.RobotParams`), with ξ drawn by the caller
   (noise drawn up front, shape ``params.noise_shape(period)`` per control period);
4. the body integrates by explicit Euler, exactly as pymunk's ``space.step`` integrates a body whose
   velocity is set before each step: ``θ_{j+1} = θ_j + ω_j dt``,
   ``p_{j+1} = p_j + v_j (cos θ_j, sin θ_j) dt`` with ``v = (v_l + v_r)/2``, ``ω = (v_r - v_l)/b``.

Sub-steps are evaluated in closed form with cumulative sums — there is no Python or ``lax`` loop
inside one control period. Training's hot loop (:func:`advance_pose`) evaluates the headings' sines and
cosines with vectorised polynomials in JAX (:func:`robots.trig.sincos`).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import numpy as np

from ekm.angles import wrap
from robots.params import KHEPERA, RobotParams
from robots.trig import sincos


class RobotState(NamedTuple):
    """Robot state pytree. ``pose``: ``(..., 3)`` = (x, y, θ); ``wheels``: ``(..., 2)`` wheel speeds (m/s)."""

    pose: object
    wheels: object


def initial_state(pose, xp=np) -> RobotState:
    """A robot at rest at ``pose`` = (x, y, θ)."""
    pose = xp.asarray(pose, dtype=xp.float32 if xp is not np else np.float64)
    return RobotState(pose=pose, wheels=xp.zeros(pose.shape[:-1] + (2,), dtype=pose.dtype))


def quantize_command(command, params: RobotParams = KHEPERA, xp=np):
    """The command the controller can actually send: clipped to ``±c*`` (wheel limit) and rounded to the
    Khepera speed unit (8 mm/s). A wheel whose command rounds to zero stands still."""
    c = xp.clip(command, -params.max_wheel_speed, params.max_wheel_speed)
    if params.speed_unit > 0:
        c = xp.round(c / params.speed_unit) * params.speed_unit
    return c


def is_stop_command(command, params: RobotParams = KHEPERA, xp=np):
    """True where both wheels of ``command`` ``(..., 2)`` are sent as zero: the robot has stopped (Eq. 6.1)."""
    return xp.all(quantize_command(command, params, xp) == 0, axis=-1)


def wheel_speeds(wheels, setpoint, n: int, params: RobotParams = KHEPERA, xp=np):
    """First-order motor lag: wheel speeds ``(..., n, 2)`` held through each of ``n`` sub-steps, and the
    speeds ``(..., 2)`` at the end of the period.

    ``s_j = c + (s_0 - c) exp(-j dt / τ)`` for set-point ``c``; the pymunk world drives its body with
    exactly these speeds, which is why both simulators agree in free space.
    """
    dt, tau = params.dt, params.motor_tau
    dtype = wheels.dtype
    decay = xp.exp(-dt * xp.arange(n, dtype=dtype) / tau)[:, None]  # (n, 1)
    s0, c = wheels[..., None, :], setpoint[..., None, :]
    end = setpoint + (wheels - setpoint) * xp.exp(xp.asarray(-dt * n / tau, dtype=dtype))
    return c + (s0 - c) * decay, end


def slip(speeds, noise, params: RobotParams = KHEPERA, xp=np):
    """Wheel ``speeds`` ``(..., n, 2)`` with Webots slip noise: times ``1 + σ ξ`` for ``noise`` ξ ``(..., K, 2)``
    in [-1, 1], each draw held for ``n / K`` sub-steps (10 % actuator noise of thesis ch. 6.1)."""
    n, k = speeds.shape[-2], noise.shape[-2]
    if n % k:
        raise ValueError(f"{k} slip draws do not divide {n} sub-steps")
    return speeds * (1.0 + params.actuator_noise * xp.repeat(noise, n // k, axis=-2))


def body_twist(speeds, params: RobotParams = KHEPERA):
    """Forward speed ``v = (v_l + v_r)/2`` and turn rate ``ω = (v_r - v_l)/b`` of wheel ``speeds`` ``(..., 2)``."""
    return 0.5 * (speeds[..., 0] + speeds[..., 1]), (speeds[..., 1] - speeds[..., 0]) / params.wheel_base


def motor_twist(wheels, setpoint, noise, n: int, params: RobotParams = KHEPERA, xp=np):
    """The motors through one control period: forward speed ``v`` and turn rate ``ω`` ``(..., n)`` held in
    each sub-step (lag of :func:`wheel_speeds`, then :func:`slip`, then each wheel's ``wheel_gain``: a wheel
    10 % smaller moves the robot 10 % less for the same motor speed), and the motors' speeds at its end.
    Both simulators move the body with these (:func:`advance` here, ``PymunkWorld.step`` in pymunk)."""
    speeds, wheels = wheel_speeds(wheels, setpoint, n, params, xp)
    speeds = slip(speeds, noise, params, xp)
    if params.gained:  # (a gain of 1 would change no bit; it is left out of the compiled step)
        speeds = speeds * xp.asarray(params.wheel_gain, dtype=speeds.dtype)
    v, omega = body_twist(speeds, params)
    return v, omega, wheels


def advance(state: RobotState, setpoint, noise, n: int, params: RobotParams = KHEPERA, xp=np):
    """Move the robot through ``n`` sub-steps towards wheel ``setpoint`` ``(..., 2)`` (a sent command, see
    :func:`quantize_command`) with slip ``noise`` ``(..., K, 2)`` in [-1, 1] (:func:`slip`).

    Returns ``(new_state, trace)`` where ``trace`` ``(..., n, 3)`` holds the pose after every sub-step
    (``trace[..., -1, :] == new_state.pose``, headings wrapped to (-π, π]); path lengths and
    first-passage times are read from it. Headings' sines and cosines are the array library's own: the ch. 6.1
    test measures with this, and its figures stay comparable from one version to the next.
    """
    dx, dy, heading, wheels = _substeps(state, setpoint, noise, n, params, xp, lambda a: (xp.sin(a), xp.cos(a)))
    x = state.pose[..., 0:1] + xp.cumsum(dx, axis=-1)
    y = state.pose[..., 1:2] + xp.cumsum(dy, axis=-1)
    trace = xp.stack([x, y, wrap(heading)], axis=-1)
    return RobotState(pose=trace[..., -1, :], wheels=wheels), trace


def advance_pose(state: RobotState, setpoint, noise, n: int, params: RobotParams = KHEPERA, xp=np) -> RobotState:
    """:func:`advance`'s new state alone, for training's hot loop, which needs only the pose at the end of the
    period: no trace, the sub-steps' displacements summed rather than accumulated, and in JAX the headings'
    sines and cosines from :func:`robots.trig.sincos`. The end position can differ from :func:`advance`'s
    in the last bits (within 1e-6 m, ``tests/robots/test_kinematics.py``); heading and wheels are the same."""
    dx, dy, heading, wheels = _substeps(state, setpoint, noise, n, params, xp, partial(sincos, xp=xp))
    # Both sums in one reduction: as two, XLA would evaluate the sub-steps' motion (lag, slip, sines,
    # cosines) once for each.
    shift = xp.sum(xp.stack([dx, dy], axis=-2), axis=-1)
    pose = xp.stack([state.pose[..., 0] + shift[..., 0], state.pose[..., 1] + shift[..., 1],
                     wrap(heading[..., -1])], axis=-1)
    return RobotState(pose=pose, wheels=wheels)


def _substeps(state: RobotState, setpoint, noise, n: int, params: RobotParams, xp, sin_cos):
    """Explicit Euler in closed form: the displacements dx, dy ``(..., n)`` of each sub-step, the unwrapped
    headings ``(..., n)`` after each, and the wheel speeds at the end. ``sin_cos(a)`` gives ``(sin a, cos a)``."""
    dt = params.dt
    v, omega, wheels = motor_twist(state.wheels, setpoint, noise, n, params, xp)  # (..., n) each
    theta0 = state.pose[..., 2:3]
    heading_inc = xp.cumsum(omega * dt, axis=-1)  # θ_{j+1} - θ_0
    sin, cos = sin_cos(theta0 + heading_inc - omega * dt)  # θ_j, heading during sub-step j
    return v * cos * dt, v * sin * dt, theta0 + heading_inc, wheels


def step(state: RobotState, command, noise, n: int, params: RobotParams = KHEPERA, xp=np):
    """One control period: send ``command`` and advance ``n`` sub-steps with slip ``noise`` ``(..., K, 2)``."""
    return advance(state, quantize_command(command, params, xp), noise, n, params, xp)


def repeated(start, end, times: int, xp=np):
    """Where a robot that moved from pose ``start`` to pose ``end`` ``(..., 3)`` would be had it made the same
    motion ``times`` times in a row, each turned by the heading change of the one before — seen from ``start``
    as (α, d) (:func:`egocentric`).

    A differential-drive robot that holds its wheel speeds repeats one control period's motion, turned by the
    period's heading change φ: its k-th chord is the first one turned by k φ, so it ends at the first chord
    times Σ_{k<times} e^{i k φ} (a circular arc, sampled as the simulators integrate it). How its wheels make
    that motion — gains, base, speed limit — does not enter.
    """
    phi = wrap(end[..., 2] - start[..., 2])
    dx, dy = end[..., 0] - start[..., 0], end[..., 1] - start[..., 1]
    c, s = xp.cos(start[..., 2]), xp.sin(start[..., 2])
    ahead, left = c * dx + s * dy, -s * dx + c * dy  # the first chord in the start frame
    k = xp.arange(times, dtype=phi.dtype if hasattr(phi, "dtype") else float)
    turns = phi[..., None] * k
    gx, gy = xp.sum(xp.cos(turns), axis=-1), xp.sum(xp.sin(turns), axis=-1)
    x, y = ahead * gx - left * gy, ahead * gy + left * gx
    return xp.stack([xp.arctan2(y, x), xp.hypot(x, y)], axis=-1)


def egocentric(pose, point, xp=np):
    """Target ``point`` ``(..., 2)`` seen from ``pose`` ``(..., 3)`` as u_p = (α, d) (thesis ch. 4.1).

    α is the direction relative to the heading, wrapped to (-π, π]; d the Euclidean distance.
    """
    dx = point[..., 0] - pose[..., 0]
    dy = point[..., 1] - pose[..., 1]
    alpha = wrap(xp.arctan2(dy, dx) - pose[..., 2])
    return xp.stack([alpha, xp.hypot(dx, dy)], axis=-1)
