"""The trap monitor (:class:`evaluation.monitor.TrapMonitor`) as pure functions over arrays, for runs on the JAX
engine (:mod:`evaluation.jaxrun`): the same rule, step for step, in a pytree one ``vmap`` holds for every run.

Progress is coming ``progress`` m closer to the checkpoint than ever before, or entering a square of side
``ground`` never visited; the robot is trapped after ``after`` s without either, or once it has driven ``loop`` m
on ground visited before without coming closer (:mod:`evaluation.monitor`'s docstring says why). The visited
squares, a Python set there, are a boolean grid here, ``(gx, gy)`` squares from the origin — the world's extent,
fixed for a batch (:func:`init`). A world's robot stays inside its border walls, so every square it enters is on
the grid (indices are clipped, so a position off the grid reads the nearest edge square). The checkpoints aimed at
before (:meth:`~evaluation.monitor.TrapMonitor.aim`), a list there, are a ring of :data:`~evaluation.monitor.REMEMBERED`
(index, best) pairs here, oldest first, index -1 where empty.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import jax
import jax.numpy as jnp

from evaluation.monitor import REMEMBERED


@dataclass(frozen=True)
class MonitorRule:
    """The monitor's parameters (static under ``jit``): ``after`` s, ``progress`` m, ``ground`` m, ``loop`` m or
    None (no loop rule) — :class:`~evaluation.monitor.TrapMonitor`'s."""

    after: float
    progress: float
    ground: float
    loop: float | None


class MonitorState(NamedTuple):
    """One run's monitor: ``best`` distance (m, ``inf`` after a reset), ``since`` the time (s) of the last progress,
    ``looped`` m driven on old ground since the last approach, ``square`` ``(2,)`` int32 the square the robot is in
    (``(-1, -1)`` before the first update), ``old`` whether that square had been visited when the robot entered it,
    ``last`` ``(2,)`` the last position and ``has_last`` whether there is one, ``visited`` ``(gx, gy)`` bool; the
    checkpoint ``index`` aimed at, and the ring of those aimed at before: ``keys`` ``(R,)`` int32 (-1: empty) and
    their ``bests`` ``(R,)``, oldest first."""

    best: object
    since: object
    looped: object
    square: object
    old: object
    last: object
    has_last: object
    visited: object
    index: object
    keys: object
    bests: object


def grid_size(extent, ground: float) -> tuple[int, int]:
    """``(gx, gy)``: squares of side ``ground`` covering ``extent`` = (w, h) m from the origin, one spare each way."""
    return tuple(int(e // ground) + 2 for e in extent)


def init(grid: tuple[int, int]) -> MonitorState:
    """A monitor at t = 0 that has seen nothing (``TrapMonitor.__init__``)."""
    return MonitorState(best=jnp.float32(jnp.inf), since=jnp.float32(0.0), looped=jnp.float32(0.0),
                        square=jnp.full(2, -1, jnp.int32), old=jnp.bool_(False), last=jnp.zeros(2, jnp.float32),
                        has_last=jnp.bool_(False), visited=jnp.zeros(grid, bool), index=jnp.int32(0),
                        keys=jnp.full(REMEMBERED, -1, jnp.int32), bests=jnp.full(REMEMBERED, jnp.inf, jnp.float32))


def reset(m: MonitorState, t, when=True) -> MonitorState:
    """Where ``when``: a new plan at ``t`` s — distance and loop measured afresh, visited ground kept, the
    checkpoints aimed at forgotten (``TrapMonitor.reset``). Elementwise: ``t`` and ``when`` may be ``(B,)`` for a
    batch's monitors."""
    ring = jnp.asarray(when)[..., None]
    return m._replace(best=jnp.where(when, jnp.inf, m.best).astype(jnp.float32),
                      since=jnp.where(when, t, m.since).astype(jnp.float32),
                      looped=jnp.where(when, 0.0, m.looped).astype(jnp.float32),
                      index=jnp.where(when, 0, m.index).astype(jnp.int32),
                      keys=jnp.where(ring, -1, m.keys).astype(jnp.int32),
                      bests=jnp.where(ring, jnp.inf, m.bests).astype(jnp.float32))


def aim(m: MonitorState, index, t, when=True) -> MonitorState:
    """Where ``when``: checkpoint ``index`` aimed at from ``t`` s (``TrapMonitor.aim``, one run's monitor): one in
    the ring has its best distance back and the time-out and loop go on; any other is measured afresh. The ring
    drops ``index`` and the checkpoint left, keeps the rest in order and takes the one left, with its best, last."""
    before = jnp.min(jnp.where(m.keys == index, m.bests, jnp.inf))
    dropped = (m.keys < 0) | (m.keys == index) | (m.keys == m.index)
    order = jnp.argsort(jnp.where(dropped, -1, jnp.arange(REMEMBERED)), stable=True)  # the dropped first
    keys = jnp.where(dropped, -1, m.keys)[order]
    bests = jnp.where(dropped, jnp.inf, m.bests)[order]
    keys = jnp.concatenate([keys[1:], m.index[None]])
    bests = jnp.concatenate([bests[1:], m.best[None]])
    again = jnp.isfinite(before)
    aimed = m._replace(best=jnp.where(again, before, jnp.inf).astype(jnp.float32),
                       since=jnp.where(again, m.since, t).astype(jnp.float32),
                       looped=jnp.where(again, m.looped, 0.0).astype(jnp.float32),
                       index=jnp.asarray(index, jnp.int32), keys=keys.astype(jnp.int32),
                       bests=bests.astype(jnp.float32))
    return jax.tree.map(lambda a, b: jnp.where(when, a, b), aimed, m)


def update(m: MonitorState, t, distance, position, rule: MonitorRule):
    """Record ``distance`` (m) to the checkpoint and ``position`` ``(2,)`` at ``t`` (s): ``(state, trapped)``
    (``TrapMonitor.update`` with a position)."""
    closer = distance < m.best - rule.progress
    best = jnp.where(closer, distance, m.best)
    since = jnp.where(closer, t, m.since)
    looped = jnp.where(closer, 0.0, m.looped)
    square = jnp.floor(position / rule.ground).astype(jnp.int32)
    cell = jnp.clip(square, 0, jnp.array(m.visited.shape) - 1)
    seen = m.visited[cell[0], cell[1]]
    entered = jnp.any(square != m.square)
    old = jnp.where(entered, seen, m.old)
    looped = looped + jnp.where(old & m.has_last, jnp.linalg.norm(position - m.last), 0.0)
    since = jnp.where(seen, since, t)
    visited = m.visited.at[cell[0], cell[1]].set(True)
    m = m._replace(best=best.astype(jnp.float32), since=since.astype(jnp.float32), looped=looped.astype(jnp.float32),
                   square=square, old=old, last=position.astype(jnp.float32), has_last=jnp.bool_(True),
                   visited=visited)
    looping = (looped >= rule.loop) if rule.loop is not None else jnp.bool_(False)
    return m, looping | (t - since >= rule.after)
