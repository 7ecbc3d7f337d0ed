"""The ball and the pitch it rolls on: ball parameters (pure data) and :class:`Pitch`, the pymunk shell.

The field is seen from above: no gravity, and the ball's roll is a deceleration of constant size
``rolling_friction`` f against its velocity,

    |v| ← max(|v| − f·dt, 0)      (direction kept: friction stops the ball, never turns it round)

taken half before and half after each physics step, so the ball moves by its mean speed over the step: a ball
kicked at v0 stops after v0/f seconds (rounded up to a whole step), having rolled v0²/(2f) metres to within
f·dt²/8 (5 µm at the defaults).

A wall returns the ball's normal velocity times ``restitution`` and keeps its tangential velocity (no
contact friction).

The ball
--------
* ``radius`` 0.02 m: a table-tennis ball (40 mm; ITTF), the size of a table-top ball next to a robot 5.5 cm
  across, as Sahota's ball was small beside his 22 cm cars (ch. 4.1.1, Fig. 8).
* ``mass`` 0.0027 kg: the same ball (2.7 g; ITTF). Only collisions with moving robots feel it.
* ``restitution`` 0.7: our choice, a lively but not a ping-pong bounce off the walls (a table-tennis ball
  on a table gives about 0.9); the ratio of outgoing to incoming normal speed at a wall.
* ``rolling_friction`` 0.15 m/s²: our choice, a rolling resistance of about 1.5 % of g on a hard table
  top, so a ball kicked at 0.3 m/s rolls 0.3 m and one kicked at 0.5 m/s rolls 0.83 m (most of the field).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from ekm.errors import InputError
from robots.params import KHEPERA
from robots.soccer.field import Field

BALL_COLLISION_TYPE = 2
"""Collision type of the ball's shape, for collision handlers added later (robots kicking it)."""
WALL_COLLISION_TYPE = 3
"""Collision type of the field's wall shapes."""
_SLOP = 1e-4  # m of overlap pymunk tolerates (its default, 0.1, is in pixels); as in robots.world


def _number(where: str, value, low: float, high: float = math.inf, *, open_low: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{where}: must be a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or v < low or v > high or (open_low and v == low):
        bound = f"> {low:g}" if open_low else f">= {low:g}"
        raise InputError(f"{where}: must be {bound}" + (f" and <= {high:g}" if high < math.inf else "")
                         + f", got {value}")
    return v


@dataclass(frozen=True)
class BallParams:
    """The ball: ``radius`` (m, > 0), ``mass`` (kg, > 0), ``restitution`` (in [0, 1]: outgoing over incoming
    normal speed at a wall) and ``rolling_friction`` (m/s², >= 0: the deceleration while it rolls). Defaults
    and their sources in the module docstring. A bad value raises :class:`ekm.errors.InputError`."""

    radius: float = 0.02
    mass: float = 0.0027
    restitution: float = 0.7
    rolling_friction: float = 0.15

    def __post_init__(self):
        _number("BallParams.radius", self.radius, 0.0, open_low=True)
        _number("BallParams.mass", self.mass, 0.0, open_low=True)
        _number("BallParams.restitution", self.restitution, 0.0, 1.0)
        _number("BallParams.rolling_friction", self.rolling_friction, 0.0)

    def stopping_distance(self, speed: float) -> float:
        """How far a ball kicked at ``speed`` (m/s) rolls before it stops: v²/(2f) m (inf without friction)."""
        return math.inf if self.rolling_friction == 0 else speed * speed / (2.0 * self.rolling_friction)


def _xy(where: str, value) -> np.ndarray:
    v = np.asarray(value, dtype=float) if not isinstance(value, str) else None
    if v is None or v.shape != (2,) or not np.all(np.isfinite(v)):
        raise InputError(f"{where}: must be two finite numbers (x, y), got {value!r}")
    return v


class Pitch:
    """The field's walls and the ball in a ``pymunk.Space``: the imperative shell of a soccer game.

    The ball starts still on the centre spot. Robots are added later straight into :attr:`space` (static or
    kinematic bodies): pymunk multiplies the elasticities of two touching shapes, so a shape with elasticity
    1.0 bounces the ball at its ``restitution``, one with 0.0 stops its normal motion dead.

    Parameters
    ----------
    field : Field
        The walls (static segments, :meth:`Field.walls`, thickness ``field.wall_thickness``).
    ball : BallParams
        The ball; it must fit into a goal (radius < ``goal_depth``, diameter < ``goal_mouth``), else no goal
        could ever be scored and :class:`~ekm.errors.InputError` is raised.

    Attributes
    ----------
    field, params : the field and ball this pitch holds.
    space : pymunk.Space
        The physics space (no gravity, no damping).
    ball_body : pymunk.Body, ball_shape : pymunk.Circle
        The ball (collision type :data:`BALL_COLLISION_TYPE`); it does not spin (infinite moment).
    wall_shapes : list of pymunk.Segment
        The walls (collision type :data:`WALL_COLLISION_TYPE`).
    """

    def __init__(self, field: Field = Field(), ball: BallParams = BallParams()):
        if ball.radius >= field.goal_depth or 2.0 * ball.radius >= field.goal_mouth:
            raise InputError(f"Pitch: a ball of radius {ball.radius} m does not fit a goal {field.goal_mouth} m wide "
                             f"and {field.goal_depth} m deep (needs radius < depth and diameter < mouth)")
        self.field = field
        self.params = ball
        self.space = pymunk.Space()
        self.space.collision_slop = _SLOP
        # pymunk bounces two shapes with the product of their elasticities, and rubs them with the product of
        # their frictions: walls 1.0 and ball = restitution gives the ball's restitution; friction 0 on both
        # makes a head-on bounce exact (no spin, no tangential loss).
        self.wall_shapes = []
        for seg in field.walls():
            s = pymunk.Segment(self.space.static_body, seg.start, seg.end, 0.5 * field.wall_thickness)
            s.elasticity, s.friction = 1.0, 0.0
            s.collision_type = WALL_COLLISION_TYPE
            self.wall_shapes.append(s)
        self.space.add(*self.wall_shapes)
        self.ball_body = pymunk.Body(ball.mass, math.inf)
        self.ball_shape = pymunk.Circle(self.ball_body, ball.radius)
        self.ball_shape.elasticity, self.ball_shape.friction = ball.restitution, 0.0
        self.ball_shape.collision_type = BALL_COLLISION_TYPE
        self.space.add(self.ball_body, self.ball_shape)
        self.place(*field.centre_spot)

    @property
    def ball_position(self) -> np.ndarray:
        """Ball centre ``(2,)`` = (x, y), m."""
        return np.array(tuple(self.ball_body.position), dtype=float)

    @property
    def ball_velocity(self) -> np.ndarray:
        """Ball velocity ``(2,)``, m/s."""
        return np.array(tuple(self.ball_body.velocity), dtype=float)

    def place(self, x: float, y: float) -> None:
        """Put the ball, still, with its centre at (x, y) m; it must lie on the pitch clear of every wall
        (:meth:`Field.contains` with margin = radius), else :class:`~ekm.errors.InputError`."""
        p = _xy("Pitch.place", (x, y))
        if not self.field.contains(p, margin=self.params.radius):
            raise InputError(f"Pitch.place: a ball at ({x}, {y}) overlaps a wall or is off the pitch")
        self.ball_body.position = (float(p[0]), float(p[1]))
        self.ball_body.velocity = (0.0, 0.0)
        self.space.reindex_shapes_for_body(self.ball_body)

    def kick(self, velocity) -> None:
        """Set the ball's velocity to ``velocity`` = (vx, vy), m/s (a kick replaces the motion, it does not add)."""
        v = _xy("Pitch.kick", velocity)
        self.ball_body.velocity = (float(v[0]), float(v[1]))

    def step(self, dt: float = KHEPERA.dt) -> None:
        """Advance ``dt`` seconds (default the robot's physics sub-step, 16 ms): take f·dt/2 off the ball's
        speed along −v (clamped at 0), one ``space.step(dt)`` — which moves the ball by that velocity and
        bounces it off whatever it meets — then the other f·dt/2. Over the step the speed falls by f·dt, and
        the ball moves by its mean speed over the step, so it rolls v0²/(2f) to within f·dt²/8."""
        dt = _number("Pitch.step dt", dt, 0.0, open_low=True)
        self._roll(0.5 * dt)
        self.space.step(dt)
        self._roll(0.5 * dt)

    def _roll(self, dt: float) -> None:
        """|v| ← max(|v| − f·dt, 0), direction kept."""
        v = self.ball_body.velocity
        speed = math.hypot(v.x, v.y)
        if speed > 0.0:
            k = max(speed - self.params.rolling_friction * dt, 0.0) / speed
            self.ball_body.velocity = (v.x * k, v.y * k)
