"""Remembered obstacles for the extended neural fields: IR hits kept in the world frame and seen again
from wherever the robot is (a departure from thesis ch. 5, whose obstacle fields last one tick).

The robot's pose — the localisation that already turns the planner's checkpoints into u_p — carries the
memory: each remembered point is a world position, re-expressed each tick as (α_j, d_j) from the robot,
d_j from the body surface like a reading. The memory is a small occupancy map kept up to date the way
range rays keep one: a hit within ``merge`` of a remembered point refreshes it, any other takes the
oldest slot of a fixed ring (so shapes stay static under ``jit``); a remembered point that a ray now
passes through, short of what the ray hit, is forgotten — the space is free again (a moving obstacle
has gone) — and so is every point older than ``memory_s``.

Pure functions over a :class:`Memory` pytree; ``jnp`` only.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.kohonen import wrap, wrap_near
from robots.controllers.base import hit_points


class Memory(NamedTuple):
    """``points`` ``(K, 2)`` world positions; ``seen`` ``(K,)`` when each was last sensed (−inf: empty);
    ``slot`` the next slot of the ring to fill."""

    points: jax.Array
    seen: jax.Array
    slot: jax.Array


def empty(size: int) -> Memory:
    """A memory of ``size`` slots, all empty."""
    return Memory(jnp.zeros((size, 2), jnp.float32), jnp.full((size,), -jnp.inf, jnp.float32),
                  jnp.asarray(0, jnp.int32))


def update(memory: Memory, pose, readings, angles, t, *, radius: float, range_m: float, merge: float,
           forget_after: float) -> Memory:
    """The memory after one tick's ``readings`` ``(m,)`` (sensor directions ``angles``, robot frame) at ``pose``.

    First forget what the rays see through and what is older than ``forget_after`` seconds, then add the
    hits (see the module docstring).
    """
    pts, seen = memory.points, memory.seen
    phi = pose[2] + angles
    direction = jnp.stack([jnp.cos(phi), jnp.sin(phi)], axis=-1)  # (m, 2)
    origin = pose[:2] + radius * direction  # rays start on the rim
    rel = pts[:, None, :] - origin[None, :, :]  # (K, m, 2)
    along = jnp.sum(rel * direction[None], axis=-1)
    across = jnp.abs(rel[..., 0] * direction[None, :, 1] - rel[..., 1] * direction[None, :, 0])
    free_to = jnp.where(jnp.isfinite(readings), readings, range_m) - merge
    through = (along >= 0) & (along < free_to[None, :]) & (across < merge)
    seen = jnp.where(jnp.any(through, axis=1) | (t - seen > forget_after), -jnp.inf, seen)
    hits, valid = hit_points(pose, readings, angles, radius, jnp)

    def add(carry, x):
        pts, seen, slot = carry
        q, ok = x
        near = jnp.isfinite(seen) & (jnp.linalg.norm(pts - q, axis=-1) < merge)
        seen = jnp.where(ok & near, t, seen)  # refresh the points it merges with
        put = ok & ~jnp.any(near)
        pts = jnp.where(put, pts.at[slot].set(q), pts)
        seen = jnp.where(put, seen.at[slot].set(t), seen)
        return (pts, seen, jnp.where(put, (slot + 1) % pts.shape[0], slot)), None

    (pts, seen, slot), _ = jax.lax.scan(add, (pts, seen, memory.slot), (hits, valid))
    return Memory(pts, seen, slot)


def egocentric(memory: Memory, pose, *, radius: float):
    """The remembered points as obstacle inputs u_j = (α_j, d_j) ``(K, 2)`` from ``pose`` — d_j from the body
    surface, like a reading — and which slots hold a point ``(K,)``."""
    dx, dy = memory.points[:, 0] - pose[0], memory.points[:, 1] - pose[1]
    alpha = wrap(jnp.arctan2(dy, dx) - pose[2])
    d = jnp.maximum(jnp.hypot(dx, dy) - radius, 0.0)
    return jnp.stack([alpha, d], axis=-1), jnp.isfinite(memory.seen)


def cone_half_width(d, *, radius: float, clearance: float):
    """Half the angle (rad) that the robot's body, grown by ``clearance``, subtends at an obstacle ``d`` (m)
    from its surface: the directions in which the robot, driving straight, would pass it too close."""
    return jnp.arcsin(jnp.clip((radius + clearance) / jnp.maximum(d + radius, 1e-6), 0.0, 1.0))


def blocked_along(directions, reach, u_obs, valid, *, radius: float, clearance: float):
    """For each direction ``(n,)`` (rad, robot frame): does an obstacle of ``u_obs`` ``(K, 2)`` (where ``valid``)
    lie in the body-wide cone along it, nearer than ``reach`` (m)?"""
    half = cone_half_width(u_obs[:, 1], radius=radius, clearance=clearance)
    off = jnp.abs(wrap_near(directions[:, None] - u_obs[None, :, 0]))
    return jnp.any(valid[None, :] & (u_obs[None, :, 1] < reach) & (off < half[None, :]), axis=1)
