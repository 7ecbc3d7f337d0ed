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
"""

from __future__ import annotations

import math


class TrapMonitor:
    """Time-out on progress towards the checkpoint and onto new ground; :meth:`reset` when the checkpoint changes."""

    def __init__(self, after: float, progress: float, ground: float | None = 0.05):
        self.after, self.progress, self.ground = after, progress, ground
        self.visited: set[tuple[int, int]] = set()
        self.reset(0.0)

    def reset(self, t: float) -> None:
        """A new checkpoint (or a new plan) at time ``t``: measure the distance afresh (visited ground stays)."""
        self.best, self.since = math.inf, t

    def update(self, t: float, distance: float, position=None) -> bool:
        """Record the robot's ``distance`` (m) to its checkpoint and its ``position`` (x, y) at ``t`` (s); True
        when it is trapped. Without ``position`` (or with ``ground`` None) only the distance counts."""
        if distance < self.best - self.progress:
            self.best, self.since = distance, t
        if position is not None and self.ground:
            square = (math.floor(position[0] / self.ground), math.floor(position[1] / self.ground))
            if square not in self.visited:
                self.visited.add(square)
                self.since = t
        return t - self.since >= self.after
