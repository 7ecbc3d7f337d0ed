"""The trap monitor (:class:`evaluation.monitor.TrapMonitor`) as pure functions over arrays, for runs on the JAX
engine (:mod:`evaluation.jaxrun`): the same rule, step for step, in a pytree one ``vmap`` holds for every run.

Progress is coming ``progress`` m closer to the checkpoint than ever before, or entering a square of side
``ground`` never visited; the robot is trapped after ``after`` s without either, or once it has driven ``loop`` m
on ground visited before without coming closer (:mod:`evaluation.monitor`'s docstring says why). The visited
squares, a Python set there, are a boolean grid here, ``(gx, gy)`` squares from the origin — the world's extent,
fixed for a batch (:func:`init`). A world's robot stays inside its border walls, so every square it enters is on
the grid (indices are clipped, so a position off the grid reads the nearest edge square).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import jax.numpy as jnp


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
    ``last`` ``(2,)`` the last position and ``has_last`` whether there is one, ``visited`` ``(gx, gy)`` bool."""

    best: object
    since: object
    looped: object
    square: object
    old: object
    last: object
    has_last: object
    visited: object


def grid_size(extent, ground: float) -> tuple[int, int]:
    """``(gx, gy)``: squares of side ``ground`` covering ``extent`` = (w, h) m from the origin, one spare each way."""
    return tuple(int(e // ground) + 2 for e in extent)


def init(grid: tuple[int, int]) -> MonitorState:
    """A monitor at t = 0 that has seen nothing (``TrapMonitor.__init__``)."""
    return MonitorState(best=jnp.float32(jnp.inf), since=jnp.float32(0.0), looped=jnp.float32(0.0),
                        square=jnp.full(2, -1, jnp.int32), old=jnp.bool_(False), last=jnp.zeros(2, jnp.float32),
                        has_last=jnp.bool_(False), visited=jnp.zeros(grid, bool))


def reset(m: MonitorState, t, when=True) -> MonitorState:
    """Where ``when``: a new checkpoint or plan at ``t`` s — distance and loop measured afresh, visited ground kept
    (``TrapMonitor.reset``). Elementwise: ``t`` and ``when`` may be ``(B,)`` for a batch's monitors."""
    return m._replace(best=jnp.where(when, jnp.inf, m.best).astype(jnp.float32),
                      since=jnp.where(when, t, m.since).astype(jnp.float32),
                      looped=jnp.where(when, 0.0, m.looped).astype(jnp.float32))


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
    m = MonitorState(best=best.astype(jnp.float32), since=since.astype(jnp.float32), looped=looped.astype(jnp.float32),
                     square=square, old=old, last=position.astype(jnp.float32), has_last=jnp.bool_(True),
                     visited=visited)
    looping = (looped >= rule.loop) if rule.loop is not None else jnp.bool_(False)
    return m, looping | (t - since >= rule.after)
