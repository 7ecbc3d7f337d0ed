"""Remembered obstacles for the extended neural fields: IR hits kept in the world frame and seen again
from wherever the robot is (a departure from thesis ch. 5, whose obstacle fields last one tick).

The robot's pose — the localisation that already turns the planner's checkpoints into u_p — carries the
memory: each remembered point is a world position, re-expressed each tick as (α_j, d_j) from the robot,
d_j from the body surface like a reading. The memory is a small occupancy map kept up to date the way
range rays keep one: a hit within ``merge`` of a remembered point refreshes it, any other takes the
oldest slot of a fixed ring (so shapes stay static under ``jit``); a remembered point that a ray now
passes through, short of what the ray hit, is forgotten — the space is free again (a moving obstacle
has gone) — and so is every point older than ``memory_s``. How near the ray must pass is the caller's choice
(:func:`forget`): a ray proves free its own line, so a wide margin forgets the end of a wall beside a ray that
just missed it, and a narrow one is slow to clear the trail a moving obstacle leaves; given the declared movers'
markers, the memory tells the two apart (``moving``).

Pure functions over a :class:`Memory` pytree; ``jnp`` only.
"""

from __future__ import annotations

from dataclasses import field
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.angles import wrap, wrap_near
from robots.controllers.actionmaps import travel_to_touch
from robots.controllers.base import hit_points


class Memory(NamedTuple):
    """``points`` ``(K, 2)`` world positions; ``seen`` ``(K,)`` when each was last sensed (−inf: empty);
    ``slot`` the next slot of the ring to fill; ``moving`` ``(K,)`` whether each was last sensed on a declared
    mover (:func:`near_movers`; only when :func:`update` is given the markers)."""

    points: jax.Array
    seen: jax.Array
    slot: jax.Array
    moving: jax.Array


#: What each of the memory's parameters means, for the architectures that remember (:func:`option`).
MEANING = {"memory_s": "s an IR obstacle point is remembered",
           "memory_points": "IR obstacle points remembered at most",
           "merge": "m within which a hit refreshes a remembered point",
           "see_through": "m from a ray within which a remembered point it passes, short of its hit, is forgotten"}


def option(name: str, default, when: str = "", why: str = ""):
    """The memory parameter ``name`` (a key of :data:`MEANING`) of an architecture's parameters (a dataclass field):
    ``default``, and the help text — prefixed by ``when`` it applies, followed by ``why`` its default."""
    return field(default=default, metadata={"help": (f"{when}: " if when else "") + MEANING[name]
                                            + (f" ({why})" if why else "")})


def empty(size: int) -> Memory:
    """A memory of ``size`` slots, all empty."""
    return Memory(jnp.zeros((size, 2), jnp.float32), jnp.full((size,), -jnp.inf, jnp.float32),
                  jnp.asarray(0, jnp.int32), jnp.zeros((size,), bool))


def update(memory: Memory, pose, readings, angles, t, *, radius: float, range_m: float, merge: float,
           forget_after: float, through: float | None = None, markers=None) -> Memory:
    """The memory after one tick's ``readings`` ``(m,)`` (sensor directions ``angles``, robot frame) at ``pose``.

    First forget what the rays see through (``through``: see :func:`forget`) and what is older than
    ``forget_after`` seconds, then add the hits (see the module docstring). With the declared movers'
    ``markers`` ``(k, 5)`` a hit on one (:func:`near_movers`) is remembered as ``moving``: a ray forgets it
    within ``merge`` of its line, as before ``through`` — the trail a mover leaves must clear as it goes.
    """
    moving = memory.moving
    seen = forget(memory.points, memory.seen, pose, readings, angles, t, radius=radius, range_m=range_m, merge=merge,
                  forget_after=forget_after, through=through if markers is None or through is None
                  else jnp.where(moving, merge, through))
    hits, valid = hit_points(pose, readings, angles, radius, jnp)
    on_mover = jnp.zeros(hits.shape[0], bool) if markers is None else near_movers(hits, markers)
    add = _add_hits if hits.shape[0] <= memory.points.shape[0] else _add_hits_in_turn
    pts, seen, slot, moving = add(memory.points, seen, memory.slot, moving, hits, valid, on_mover, t, merge)
    return Memory(pts, seen, slot, moving)


def forget(pts, seen, pose, readings, angles, t, *, radius: float, range_m: float, merge: float, forget_after: float,
           through: float | None = None):
    """``seen`` ``(K,)`` after forgetting the points ``pts`` ``(K, 2)`` that a ray of this tick passes through, short
    of what it hit (farther than ``merge`` before it, within ``through`` of the ray — m, or ``(K,)`` one for each
    point; ``merge`` when None), and those older than ``forget_after`` s: −inf for them (see :func:`update`).

    A ray passing *beside* a point proves free only the ray's own line: at the end of a wall (or any convex
    corner) a ray that just misses the end passes within a few millimetres of the point the IR saw on the end, and
    with a wide ``through`` it forgets the end while the wall is still there."""
    phi = pose[2] + angles
    cos, sin = jnp.cos(phi), jnp.sin(phi)  # (m,) each ray's direction; it starts on the rim
    ox, oy = pose[0] + radius * cos, pose[1] + radius * sin
    # Computed once, not once per point and ray: left to itself XLA fuses the cos and sin into the (K, m)
    # loop below and evaluates them K times over; the values are the same either way.
    cos, sin, ox, oy = jax.lax.optimization_barrier((cos, sin, ox, oy))
    rx, ry = pts[:, 0:1] - ox[None, :], pts[:, 1:2] - oy[None, :]  # (K, m) from each ray's start
    along = rx * cos[None, :] + ry * sin[None, :]
    across = jnp.abs(rx * sin[None, :] - ry * cos[None, :])
    free_to = jnp.where(jnp.isfinite(readings), readings, range_m) - merge
    width = jnp.broadcast_to(jnp.asarray(merge if through is None else through, jnp.float32), seen.shape)
    through = (along >= 0) & (along < free_to[None, :]) & (across < width[:, None])
    return jnp.where(jnp.any(through, axis=1) | (t - seen > forget_after), -jnp.inf, seen)


def _add_hits_in_turn(pts, seen, slot, moving, hits, ok, on_mover, t, merge: float):
    """Add the hits ``(m, 2)`` where ``ok`` ``(m,)`` one after the other (the definition): a hit within ``merge``
    of a remembered point refreshes it, any other takes the ring's next slot; either way the point is ``moving``
    as the hit is ``on_mover`` ``(m,)``. Returns ``(pts, seen, slot, moving)``."""
    def add(carry, x):
        pts, seen, slot, moving = carry
        q, ok, mv = x
        near = jnp.isfinite(seen) & (_distance(pts[:, 0], pts[:, 1], q[0], q[1]) < merge)
        seen = jnp.where(ok & near, t, seen)  # refresh the points it merges with
        moving = jnp.where(ok & near, mv, moving)
        put = ok & ~jnp.any(near)
        pts = jnp.where(put, pts.at[slot].set(q), pts)
        seen = jnp.where(put, seen.at[slot].set(t), seen)
        moving = jnp.where(put, moving.at[slot].set(mv), moving)
        return (pts, seen, jnp.where(put, (slot + 1) % pts.shape[0], slot), moving), None

    return jax.lax.scan(add, (pts, seen, slot, moving), (hits, ok, on_mover))[0]


def _add_hits(pts, seen, slot, moving, hits, ok, on_mover, t, merge: float):
    """:func:`_add_hits_in_turn` without a loop over the memory (for m ≤ K hits, when a tick's puts cannot wrap
    round the ring onto each other): the same points and times to the bit, at a fraction of the cost — a
    loop of m steps over K slots is m × a few XLA kernels per tick, the costliest part of the fields' step.

    Hit j merges with a remembered point within ``merge`` that no earlier put of this tick has overwritten —
    the n-th put takes slot (slot + n) mod K, so slot i is overwritten by put number (i − slot) mod K — or
    with an earlier hit that was put; only the latter chain (m × m) is followed hit by hit.
    """
    k, m = seen.shape[0], hits.shape[0]
    hx, hy = hits[:, 0:1], hits[:, 1:2]  # (m, 1)
    near = jnp.isfinite(seen)[None, :] & (_distance(pts[None, :, 0], pts[None, :, 1], hx, hy) < merge)  # (m, K)
    turn = jnp.mod(jnp.arange(k) - slot, k)  # the put of this tick that would overwrite each slot
    latest = jnp.max(jnp.where(near, turn[None, :], -1), axis=1)  # (m,) the last-overwritten point each hit is near
    close = _distance(hx.T, hy.T, hx, hy) < merge  # [j, i]: hit i within merge of hit j
    puts, before, count = [], [], jnp.zeros((), jnp.int32)
    for j in range(m):
        earlier = jnp.any(jnp.stack(puts) & close[j, :j]) if puts else False
        put = ok[j] & (latest[j] < count) & ~earlier
        puts.append(put)
        before.append(count)
        count = count + put.astype(jnp.int32)
    put, before = jnp.stack(puts), jnp.stack(before)
    # A point a hit merges with is refreshed to t; if an earlier put had already overwritten it, that put set
    # its slot's time to t too — so whether it was overwritten first does not matter here.
    seen = jnp.where(jnp.any(ok[:, None] & near, axis=0), t, seen)
    into = jnp.where(put, (slot + before) % k, k)  # k: not put (dropped)
    # A slot is ``moving`` as the last hit that touched it: one that refreshed the point there before a put
    # overwrote it (hit j sees the old point while the put that overwrites it, number turn, is still to come), the
    # put itself, or a later hit that merged with what the put left.
    order = jnp.arange(m)
    refreshed = ok[:, None] & near & (before[:, None] <= turn[None, :])  # (m, K) the old points
    later = ok[:, None] & close & (order[:, None] > order[None, :])  # [j, p]: hit j merges with put p after it
    last_put = jnp.maximum(order, jnp.max(jnp.where(later, order[:, None], -1), axis=0))  # (m,) per put
    last = jnp.maximum(jnp.max(jnp.where(refreshed, order[:, None], -1), axis=0),
                       jnp.full(k, -1).at[into].set(last_put, mode="drop"))
    moving = jnp.where(last >= 0, on_mover[jnp.maximum(last, 0)], moving)
    return (pts.at[into].set(hits, mode="drop"), seen.at[into].set(t, mode="drop"), (slot + count) % k, moving)


def _distance(ax, ay, bx, by):
    """|a − b| from components — ``jnp.linalg.norm`` over a trailing axis of 2 to the bit, without the slow
    reduction over that axis on the CPU."""
    dx, dy = ax - bx, ay - by
    return jnp.sqrt(dx * dx + dy * dy)


def egocentric(memory: Memory, pose, *, radius: float):
    """The remembered points as obstacle inputs u_j = (α_j, d_j) ``(K, 2)`` from ``pose`` — d_j from the body
    surface, like a reading — and which slots hold a point ``(K,)``."""
    dx, dy = memory.points[:, 0] - pose[0], memory.points[:, 1] - pose[1]
    alpha = wrap(jnp.arctan2(dy, dx) - pose[2])
    d = jnp.maximum(jnp.hypot(dx, dy) - radius, 0.0)
    return jnp.stack([alpha, d], axis=-1), jnp.isfinite(memory.seen)


#: Sizes the remembered points that count are packed into before the per-neuron work (:func:`over_packed`).
#: Most ticks count only a few dozen of the 128–256 slots, so the work shrinks to the slots that count.
PACK_SIZES = (16, 64)


def over_packed(fn, u_obs, valid, sizes: tuple[int, ...] = PACK_SIZES):
    """``fn(u, v)`` on ``u_obs`` ``(K, ...)`` and ``valid`` ``(K,)`` packed into the smallest of ``sizes`` (or K)
    that holds every valid row: the valid rows first, in slot order, then empty rows (``v`` False).

    For a ``fn`` on which invalid rows have no effect the result is that of ``fn(u_obs, valid)`` — exactly
    for a min, max or any over the rows, up to the order of the terms for a sum — at the cost of the rows
    that count. One branch per size is compiled (``lax.switch``); the tick takes the one it needs.
    """
    k = valid.shape[0]
    sizes = tuple(s for s in sorted(set(sizes)) if s < k) + (k,)
    count = jnp.sum(valid.astype(jnp.int32))
    slot = jnp.where(valid, jnp.cumsum(valid.astype(jnp.int32)) - 1, k)  # where each valid row goes; k: dropped

    def at(size):
        def run(u):
            packed = jnp.zeros((size,) + u.shape[1:], u.dtype).at[slot].set(u, mode="drop")
            return fn(packed, jnp.arange(size) < count)
        return run

    return jax.lax.switch(jnp.searchsorted(jnp.asarray(sizes), count), [at(s) for s in sizes], u_obs)


def cone_half_width(d, *, radius: float, clearance: float):
    """Half the angle (rad) that the robot's body, grown by ``clearance``, subtends at an obstacle ``d`` (m)
    from its surface: the directions in which the robot, driving straight, would pass it too close."""
    return jnp.arcsin(jnp.clip((radius + clearance) / jnp.maximum(d + radius, 1e-6), 0.0, 1.0))


def blocked_along(directions, reach, u_obs, valid, *, radius: float, clearance):
    """For each direction ``(n,)`` (rad, robot frame): would the body, grown by ``clearance`` (m, or one per obstacle
    ``(K,)``), touch an obstacle of ``u_obs`` ``(K, 2)`` (where ``valid``) driving straight along it before its
    centre has covered ``reach`` (m)? An obstacle r = d + R from the centre and ``off`` from the direction, at
    x = r cos(off) along it and y = r sin(off) across, is in the way if |y| < R + c — the body-wide cone of
    :func:`cone_half_width` — and is touched after s = x − √((R + c)² − y²) (:func:`~robots.controllers.actionmaps.
    travel_to_touch`, Samba's ray distances). Why s and not d: an obstacle beside
    a target, nearer than it from the body's surface but past it along the way (a wall beside a checkpoint at a
    corridor's bend), does not stand between the robot and the target (issue 35, ``corridor:9``)."""
    grown = radius + jnp.broadcast_to(jnp.asarray(clearance, jnp.float32), u_obs[:, 1].shape)
    r = u_obs[None, :, 1] + radius
    along = r * jnp.cos(wrap_near(directions[:, None] - u_obs[None, :, 0]))
    touched = travel_to_touch(along, jnp.square(r) - jnp.square(grown[None, :]))
    return jnp.any(valid[None, :] & (touched < reach), axis=1)


#: m beyond a declared mover's radius within which an IR return is bound to the mover's marker.
BIND_MARGIN = 0.01


def near_movers(points, markers, margin: float = BIND_MARGIN):
    """Which world ``points`` ``(K, 2)`` lie within a declared mover's radius + ``margin`` of one of the ``markers``
    ``(k, 5)`` (x, y, vx, vy, radius): what the IR saw of a mover, not of a still obstacle."""
    markers = jnp.asarray(markers, jnp.float32).reshape(-1, 5)
    gap = _distance(points[:, None, 0], points[:, None, 1], markers[None, :, 0], markers[None, :, 1])
    return jnp.any(gap <= markers[None, :, 4] + margin, axis=1)


def off_movers(pose, readings, angles, markers, *, radius: float, margin: float = BIND_MARGIN):
    """``readings`` ``(m,)`` with those that hit a declared moving obstacle set to ``inf``: a return within the
    mover's radius + ``margin`` of one of the ``markers`` ``(k, 5)`` (x, y, vx, vy, radius; world frame) is the
    mover, which its marker already tracks — kept as a still point it would linger where the mover was."""
    hits, _ = hit_points(pose, readings, angles, radius, jnp)
    return jnp.where(near_movers(hits, markers, margin), jnp.inf, readings)
