"""Cognizant failure (thesis ch. 7.1.1): a monitor that notices when the robot stops making progress.

"The robot must be able to detect ... and recognize on its own any failures to complete its task via
monitor routines (e.g., time-out)". :class:`TrapMonitor` is that time-out: it keeps the closest the
robot has come to its current checkpoint, and reports a trap when that has not improved by
``progress`` metres for ``after`` seconds. Going round an obstacle moves the robot away from its
checkpoint for a while, so ``after`` must be longer than a detour takes (30 s by default, about
three metres at the robot's top speed; :class:`evaluation.scenario.ScenarioConfig`).
"""

from __future__ import annotations

import math


class TrapMonitor:
    """Time-out on progress towards a checkpoint; :meth:`reset` when the checkpoint changes."""

    def __init__(self, after: float, progress: float):
        self.after, self.progress = after, progress
        self.reset(0.0)

    def reset(self, t: float) -> None:
        """A new checkpoint (or a new plan) at time ``t``: start measuring afresh."""
        self.best, self.since = math.inf, t

    def update(self, t: float, distance: float) -> bool:
        """Record the robot's ``distance`` (m) to its checkpoint at ``t`` (s); True when it is trapped."""
        if distance < self.best - self.progress:
            self.best, self.since = distance, t
        return t - self.since >= self.after
