"""One robot in one world, in JAX: the pymunk world's control period as a pure function (docs/jaxworld.md).

:func:`step` is :meth:`robots.world.PymunkWorld.step` without pymunk. The motors are the kinematics' own
(:func:`robots.kinematics.quantize_command`, :func:`~robots.kinematics.motor_twist`: lag, slip noise ξ drawn by
the caller up front); the ``n`` sub-steps of ``dt`` then run in a ``lax.scan`` that does what pymunk's velocity
control and Chipmunk's solver do to the robot's disc:

1. contacts are the primitives the disc (radius ``R``) overlaps, ``gap_i < R`` (:func:`~robots.jaxworld.collide.gaps`);
2. the commanded velocity ``v (cos θ, sin θ)`` loses its part ``(v·n_i) n_i`` pushing into a contact, the two
   deepest contacts in turn (:meth:`robots.body.RobotBody.slide`): the robot slides along walls;
3. Euler step: ``p ← p + v dt + β Σ_i max(0, R - gap_i - slop) (-n_i)``, ``θ ← θ + ω dt``: Chipmunk's position
   bias pushes an overlap out by ``β = 1 - collision_bias^dt`` (pymunk's default bias ``0.9^60``: β ≈ 0.096 a
   16 ms sub-step) of its depth beyond the ``slop`` (:data:`robots.body.SLOP`, 0.1 mm) each sub-step;
4. a contact **episode** begins on a sub-step that ends touching after one that did not, when the last sub-step
   that ended touching is at least :data:`robots.body.REJOIN_S` before it; ``contact_s`` sums the sub-steps that
   end touching (:class:`robots.world.PymunkWorld`).

With movers and timed events (``dynamic``, static: a batch of still worlds pays nothing for them) each sub-step
starting at ``t`` first fires the events due whose shapes are clear of the robot's body
(:func:`robots.jaxworld.moving.due`); contacts are with the shapes then in the world, a mover's velocity over the
sub-step is taken off the push (relative to the mover, so a mover shoves the robot), the gaps at the sub-step's end
are to the scene at ``t + dt``, and a robot a mover has pressed into a still shape deeper than its own motion can
go is set back onto the shape's surface (:meth:`robots.body.RobotBody.unsqueeze`: the wall wins).

A sub-step moves the centre at most ``1.1 c* dt`` ≈ 2.8 mm, far less than the robot's radius: the disc cannot pass
through a wall of any thickness between two sub-steps (no tunnelling), as in pymunk.

Everything is a pure function of arrays and static :class:`~robots.params.RobotParams`; ``jit`` with ``params``
and ``n`` static, ``vmap`` over runs (and scenes).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.angles import wrap
from robots import kinematics
from robots.body import REJOIN_S, SLOP
from robots.jaxworld import moving
from robots.jaxworld.collide import gaps, ray_hit
from robots.jaxworld.scene import Scene
from robots.kinematics import RobotState
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.sensors import ir_readings, sensor_rays

#: pymunk's default ``Space.collision_bias``: the fraction of an overlap left after one second of correction.
COLLISION_BIAS = (1.0 - 0.1) ** 60


def bias_rate(dt: float) -> float:
    """β: the fraction of an overlap (beyond the slop) Chipmunk corrects in one sub-step of ``dt`` s."""
    return 1.0 - COLLISION_BIAS ** dt


class EngineState(NamedTuple):
    """One run's state, a pytree (leading batch axes under ``vmap``).

    ``robot``: pose ``(3,)`` (θ wrapped to (-π, π]) and wheel speeds ``(2,)``; ``k``: sub-steps taken (t = k dt);
    ``touching``: whether the last sub-step ended in contact; ``last_contact``: time (s) of the last sub-step
    that ended in contact (``-inf`` before any); ``collisions``: contact episodes; ``contact_s``: s in contact;
    ``fired`` ``(E,)``: which timed events have added their shapes.
    """

    robot: RobotState
    k: object
    touching: object
    last_contact: object
    collisions: object
    contact_s: object
    fired: object


def reset(pose, scene: Scene, params: RobotParams = KHEPERA) -> EngineState:
    """A robot at rest at ``pose`` ``(3,)`` at t = 0, the events due at 0 fired (if clear of it); ``touching`` if it
    starts overlapping a shape."""
    pose = jnp.asarray(pose, jnp.float32)
    t0 = jnp.float32(0.0)
    gap, _ = gaps(pose[:2], moving.moved(scene, t0))
    fired = moving.due(scene, t0, jnp.zeros(scene.event_at.shape, bool), gap, params.radius)
    gap = jnp.where(moving.live(scene, fired), gap, jnp.inf)
    return EngineState(robot=RobotState(pose=pose, wheels=jnp.zeros(2, jnp.float32)), k=jnp.int32(0),
                       touching=jnp.any(gap < params.radius), last_contact=jnp.float32(-jnp.inf),
                       collisions=jnp.int32(0), contact_s=jnp.float32(0.0), fired=fired)


def _slide(vel, overlap, normal, other=None):
    """``vel`` ``(2,)`` less its push into the two deepest contacts (``overlap > 0``), deepest first (ties: the
    lower index first); relative to the contacts' own velocities ``other`` ``(C + P, 2)`` if given (a mover).

    Two ``argmax`` passes, not ``lax.top_k``: the same pair, and XLA's ``top_k`` on a CPU is slow for a handful of
    elements (docs/performance.md)."""
    for _ in range(2):
        i = jnp.argmax(overlap)
        n = normal[i]
        push = (vel if other is None else vel - other[i]) @ n
        vel = jnp.where((overlap[i] > 0) & (push > 0), vel - push * n, vel)
        overlap = overlap.at[i].set(-jnp.inf)
    return vel


def step(state: EngineState, scene: Scene, command, noise, params: RobotParams = KHEPERA, n: int = 8,
         dynamic: bool = False):
    """Drive with wheel ``command`` ``(2,)`` m/s for one control period of ``n`` sub-steps.

    ``noise`` ``(K, 2)``: slip draws ξ in [-1, 1] (``params.noise_shape(n dt)``; zeros for a noise-free period).
    ``dynamic`` (static): step the scene's movers and timed events (the module docstring); without it they stand
    where they are at t = 0 and events never fire. Returns ``(state, trace)``, ``trace`` ``(n, 3)`` the pose after
    every sub-step, as :meth:`robots.world.PymunkWorld.step` does.
    """
    dt, radius = params.dt, params.radius
    beta = bias_rate(dt)
    max_overlap = (1.0 + params.actuator_noise) * params.max_wheel_speed * dt  # RobotBody.unsqueeze's bound
    setpoint = kinematics.quantize_command(jnp.asarray(command, jnp.float32), params, jnp)
    v, omega, wheels = kinematics.motor_twist(state.robot.wheels, setpoint, jnp.asarray(noise, jnp.float32), n,
                                              params, jnp)

    def at(t):  # every shape where it is at t (movers moved; events' shapes all there, masked by ``fired``)
        return moving.moved(scene, t) if dynamic else scene

    gap0, normal0 = gaps(state.robot.pose[:2], at(state.k.astype(jnp.float32) * dt))

    def substep(carry, vw):
        pos, theta, k, touching, last, collisions, contact_s, gap, normal, fired = carry
        vj, wj = vw
        t = k.astype(jnp.float32) * dt
        t1 = (k + 1).astype(jnp.float32) * dt
        other = None
        if dynamic:
            fired = moving.due(scene, t, fired, gap, radius)
            gap = jnp.where(moving.live(scene, fired), gap, jnp.inf)
            other = moving.primitive_velocities(scene, t, t1)
        overlap = radius - gap
        vel = _slide(vj * jnp.stack([jnp.cos(theta), jnp.sin(theta)]), overlap, normal, other)
        push_out = beta * jnp.maximum(overlap - SLOP, 0.0)
        pos = pos + vel * dt - jnp.sum(push_out[:, None] * normal, axis=0)
        theta = theta + wj * dt
        gap, normal = gaps(pos, at(t1))
        on = True
        if dynamic:
            on = moving.live(scene, fired)
            squeezed = moving.has_movers(scene) & on & moving.is_still(scene) & (radius - gap > max_overlap)
            depth = jnp.where(squeezed, radius - gap - SLOP, 0.0)  # pressed into a wall by a mover: the wall wins
            pos = pos - jnp.sum(depth[:, None] * normal, axis=0)
            gap = gap + depth  # first order: the other gaps move by less than the slop here
        now = jnp.any(on & (gap < radius))
        collisions = collisions + (now & ~touching & (t - last >= REJOIN_S - 1e-6)).astype(jnp.int32)
        contact_s = contact_s + jnp.where(now, jnp.float32(dt), 0.0)
        last = jnp.where(now, t1, last)
        carry = (pos, theta, k + 1, now, last, collisions, contact_s, gap, normal, fired)
        return carry, jnp.concatenate([pos, wrap(theta)[None]])

    s = state
    carry = (s.robot.pose[:2], s.robot.pose[2], s.k, s.touching, s.last_contact, s.collisions, s.contact_s,
             gap0, normal0, s.fired)
    carry, trace = jax.lax.scan(substep, carry, (v, omega))
    pos, theta, k, touching, last, collisions, contact_s, _, _, fired = carry
    robot = RobotState(pose=jnp.concatenate([pos, wrap(theta)[None]]), wheels=wheels)
    return EngineState(robot, k, touching, last, collisions, contact_s, fired), trace


def ranges(pose, scene: Scene, sensors: SensorSet, radius: float = KHEPERA.radius):
    """True distances ``(m,)`` from the body surface along each sensor ray to the first shape, ``inf`` beyond
    ``sensors.range_m`` (:meth:`robots.body.RobotBody.ranges`)."""
    start, end = sensor_rays(pose, sensors, radius, xp=jnp)
    direction = (end - start) / sensors.range_m
    return jax.vmap(ray_hit, in_axes=(0, 0, None, None))(start, direction, sensors.range_m, scene)


def sense(state: EngineState, scene: Scene, sensors: SensorSet, noise, params: RobotParams = KHEPERA,
          dynamic: bool = False):
    """IR readings ``(m,)`` for standard-normal ``noise`` ``(m,)`` (0: noise-free, still quantised):
    :func:`robots.sensors.ir_readings` of :func:`ranges` — in the world as it is at the state's time if
    ``dynamic`` (static; movers moved, the shapes of the events fired)."""
    if dynamic:
        scene = moving.placed(scene, time_of(state, params), state.fired)
    return ir_readings(ranges(state.robot.pose, scene, sensors, params.radius), noise, sensors, xp=jnp)


def time_of(state: EngineState, params: RobotParams = KHEPERA):
    """Simulated time (s) of ``state``."""
    return state.k.astype(jnp.float32) * params.dt
