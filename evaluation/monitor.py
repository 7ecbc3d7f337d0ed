"""Cognizant failure (thesis ch. 7.1.1): a monitor that notices when the robot stops making progress.

"The robot must be able to detect ... and recognize on its own any failures to complete its task via
monitor routines (e.g., time-out)". :class:`TrapMonitor` is that time-out. Two things count as progress:

- coming ``progress`` metres closer to the current checkpoint than ever before (the checkpoints see
  each other, :mod:`planner.visibility`, so this is progress along the planned route);
- reaching ground not visited before in the run: a square of side ``ground`` the robot's centre has
  never been in. Going round an unforeseen obstacle, or driving a long detour after a blocked door,
  moves the robot away from its checkpoint for a long while, but always onto new ground.

When neither has happened for ``after`` seconds the robot is trapped: circling or dithering in place
revisits the same squares, and a robot pinned against an obstacle comes no closer.

A robot can also loop (issue 35): pushed off the mouth of a narrow niche, it circles the room and comes back,
again and again, each lap long enough to touch a few new squares at its edges and so reset the time-out. So the
monitor also ends **loops**: once the robot has driven ``loop`` metres on ground it had visited before (a square
it comes back to after leaving it) since it last came closer to its checkpoint, it is trapped however much new
ground it brushes on the way. A detour onto new ground never adds to that count; driving back the way it came
does, and after ``loop`` metres of it without getting closer, recovery's replan is what the robot needs anyway.

A robot may also turn back to a checkpoint it has headed for before (issue 35: the look back of
:func:`evaluation.scenario.pass_checkpoints`, when a wall comes between it and the checkpoint the look ahead took
it on to). Heading for another checkpoint is not progress in itself: :meth:`TrapMonitor.aim` remembers the best
distance to each of the last :data:`REMEMBERED` checkpoints aimed at, and turning back to one of them restores
it and keeps the time-out and the loop running, so turning back and forth cannot hold the monitor off.
"""

from __future__ import annotations

import math

#: Checkpoints whose best distance the monitor remembers, the latest aimed at, for :meth:`TrapMonitor.aim`.
REMEMBERED = 8


class TrapMonitor:
    """Time-out on progress towards the checkpoint and onto new ground; :meth:`aim` when the checkpoint changes,
    :meth:`reset` when the plan does."""

    def __init__(self, after: float, progress: float, ground: float | None = 0.05, loop: float | None = None):
        self.after, self.progress, self.ground, self.loop = after, progress, ground, loop
        self.visited: set[tuple[int, int]] = set()
        self.square: tuple[int, int] | None = None  # the square the robot is in
        self.old = False  # ... and whether it had been there before it last entered
        self.last = None  # the last position (x, y)
        self.reset(0.0)

    def reset(self, t: float) -> None:
        """A new plan at time ``t``: measure the distance and the loop afresh (visited ground stays), and forget
        the checkpoints of the plan before (checkpoint 0 is aimed at)."""
        self.best, self.since, self.looped = math.inf, t, 0.0
        self.index, self.aimed = 0, []

    def aim(self, index: int, t: float) -> None:
        """Checkpoint ``index`` of the plan is aimed at from ``t`` (s). One of the last :data:`REMEMBERED` aimed
        at before: its best distance comes back, and the time-out and the loop go on from where they are; any
        other: measured afresh (as :meth:`reset`)."""
        before = dict(self.aimed).get(index, math.inf)
        kept = [(i, b) for i, b in self.aimed if i not in (index, self.index)]
        self.aimed, self.index = (kept + [(self.index, self.best)])[-REMEMBERED:], index
        if math.isfinite(before):
            self.best = before
        else:
            self.best, self.since, self.looped = math.inf, t, 0.0

    def update(self, t: float, distance: float, position=None) -> bool:
        """Record the robot's ``distance`` (m) to its checkpoint and its ``position`` (x, y) at ``t`` (s); True
        when it is trapped (no progress for ``after`` s, or ``loop`` m driven on old ground without coming closer).
        Without ``position`` (or with ``ground`` None) only the distance counts."""
        if distance < self.best - self.progress:
            self.best, self.since, self.looped = distance, t, 0.0
        if position is not None and self.ground:
            square = (math.floor(position[0] / self.ground), math.floor(position[1] / self.ground))
            if square != self.square:
                self.square, self.old = square, square in self.visited
            if self.old and self.last is not None:
                self.looped += math.dist(position, self.last)
            if square not in self.visited:
                self.visited.add(square)
                self.since = t
            self.last = (float(position[0]), float(position[1]))
        looping = self.loop is not None and self.looped >= self.loop
        return looping or t - self.since >= self.after
