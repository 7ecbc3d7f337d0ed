"""What a soccer player sees and how it is called: the :class:`Play` observation and the side-0 frame.

A player is a :class:`~robots.controllers.base.Controller` whose jitted ``step(state, play) -> (state, wheels)``
takes a :class:`Play` instead of a navigation :class:`~robots.controllers.base.Observation` and returns the
``(2,)`` wheel speeds (m/s; the motors clip and round them, :mod:`robots.kinematics`). The match runner
(:mod:`evaluation.match`) calls every player once per 0.128 s tick, the obstacle-avoidance period.

**Every player plays from the left.** The runner hands each player the game in *its own frame*, in which it
defends the goal at x = 0 and attacks the goal at x = ``field.length`` — side 0's view. For side 1 the
field is turned half round about its centre (:func:`own_frame`): x → length − x, y → width − y, θ → θ + π,
velocities negated. IR readings and wheel commands are the robot's own and do not change. So a player is
written once, for one side, and its known-answer tests need no mirror images.

Where the positions come from: the overhead camera of Sahota's Dynamite testbed (ch. 4.1.2) and the Soccer
Server's vision of Riekki's players (ch. 5.1) — every robot and the ball are seen, exactly and at once.
The IR ring sees the walls and the other robots, not the ball: it rolls below the sensors' plane (a 40 mm
ball beside a Khepera whose sensors sit higher), so avoidance never pushes a player away from the ball.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ekm.angles import wrap
from robots.soccer.field import Field, _side


class Play(NamedTuple):
    """One tick's input to a soccer player, in its own frame (module docstring; metres, radians, m/s).

    ``t``: game time (s). ``ir``: ``(m,)`` the player's IR ring (m from the body surface, ``inf`` = nothing
    within range). ``pose``: ``(3,)`` its own (x, y, θ). ``velocity``: ``(2,)`` its own (vx, vy).
    ``ball``: ``(4,)`` the ball's (x, y, vx, vy). ``opponent``: ``(5,)`` the opponent's (x, y, θ, vx, vy).
    """

    t: Any
    ir: Any
    pose: Any
    velocity: Any
    ball: Any
    opponent: Any


def own_frame(side: int, field: Field, pose, velocity, ball, opponent):
    """Pose ``(3,)``, velocity ``(2,)``, ball ``(4,)`` and opponent ``(5,)`` from the field's frame into the frame
    of the player on ``side`` (module docstring): unchanged for side 0; for side 1 turned half round about
    the centre, ``(x, y) → (length − x, width − y)``, ``θ → θ + π`` wrapped to (−π, π], velocities negated.
    The map is its own inverse. Returns numpy arrays ``(pose, velocity, ball, opponent)``."""
    pose, velocity = np.asarray(pose, float), np.asarray(velocity, float)
    ball, opponent = np.asarray(ball, float), np.asarray(opponent, float)
    if _side(side) == 0:
        return pose, velocity, ball, opponent
    L, W = field.length, field.width

    def turn(theta):
        return wrap(theta + np.pi)

    return (np.array([L - pose[0], W - pose[1], turn(pose[2])]), -velocity,
            np.array([L - ball[0], W - ball[1], -ball[2], -ball[3]]),
            np.array([L - opponent[0], W - opponent[1], turn(opponent[2]), -opponent[3], -opponent[4]]))
