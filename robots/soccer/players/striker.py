"""The striker: any navigation architecture plays soccer by reaching a point the striker moves about the ball.

How the EKM player (``ekm``: the trained indirect EKM with neural-field avoidance, :mod:`robots.controllers.fields`)
and the motor-schema player (``schema``, :mod:`robots.controllers.schema`) play: the architecture drives, as it
drives through a room, towards a *target point* that this module chooses every tick from where the ball is
(the player's own frame, :mod:`robots.soccer.play`: it attacks the goal at x = length, centre g):

with u the unit vector from the ball b to g, n = u turned +90°, c = body radius + ball radius, and the robot's
centre p seen from the ball as ``along = (p − b)·u`` (negative: behind the ball) and ``across = (p − b)·n``:

========== ================================================= =============================================
mode       when                                              target point
========== ================================================= =============================================
push (2)   lined up: ``along < −c/2`` and ``|across| <       ``b + push · u``: through the ball towards the
           lateral`` (``1.5 · lateral`` once pushing)        goal — the robot pushes it (it has no kicker)
go round   not behind the ball, ``along > −c``, and close     ``b + (c + clear) · side · n − (c + behind) · u``:
(1)        across it, ``|across| < c + clear``               beside the ball on the robot's side, behind it
approach   otherwise                                         ``b − (c + behind) · u``: on the line from the
(0)                                                          goal through the ball, behind it
========== ================================================= =============================================

The architecture gets that point as its checkpoint u_p = (α, d), ``final`` False (it is never the goal of a
route, so no architecture slows to stop at it), ``target_id`` the mode (a new mode is a new checkpoint), and
the opponent as its one declared mover (``markers``: what the motor schemas and the fields' memory treat as
a moving obstacle). Its IR sees the walls and the opponent, not the ball. Why a point behind the ball: a
robot that drives straight at the ball pushes it wherever it happens to hit it; from behind, along the line
to the goal, it pushes it at the goal (the issue's "point behind the ball on the line to the goal").
"""

from __future__ import annotations

from dataclasses import dataclass, field

import jax
import jax.numpy as jnp

from robots.controllers.base import Controller, Observation
from robots.kinematics import egocentric
from robots.params import KHEPERA, RobotParams
from robots.soccer.ball import BallParams
from robots.soccer.field import Field
from robots.soccer.play import Play

APPROACH, GO_ROUND, PUSH = 0, 1, 2
"""The striker's modes (module docstring)."""

#: navigation architectures a striker can drive with (continuous ones that read a checkpoint and the IR)
DRIVES = ("fields", "fusion", "schema")


@dataclass(frozen=True)
class StrikerParams:
    """Where the striker puts the target point (module docstring). Sizes in metres."""

    drive: str = field(default="fields", metadata={"help": "the navigation architecture that drives to the point",
                                                     "choices": DRIVES})
    behind: float = field(default=0.04, metadata={"help": "m between the ball's and the body's surfaces at the "
                                                          "approach point"})
    lateral: float = field(default=0.02, metadata={"help": "m off the ball-goal line within which the robot is "
                                                           "lined up to push"})
    clear: float = field(default=0.03, metadata={"help": "m kept between the surfaces going round the ball"})
    arrive: float = field(default=0.01, metadata={"help": "m from the approach point at which the robot pushes "
                                                          "even if not lined up (a ball by a wall)"})
    push: float = field(default=0.2, metadata={"help": "m past the ball, towards the goal, of the push target"})

    def __post_init__(self):
        for name in ("behind", "lateral", "clear", "arrive", "push"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0 m, got {getattr(self, name)}")


@dataclass(frozen=True)
class EkmParams(StrikerParams):
    """The EKM player: the striker driven by the neural fields (the trained indirect EKM, ch. 5). ``arrive`` 0.03 m:
    chosen on tuning games (seeds 0–3 against ``schema``; docs/reproduce/soccer.md) — the EKM slows as it nears a
    point (it maps a target to the step that reaches it), so it pushes from 3 cm off the approach point."""

    arrive: float = field(default=0.03, metadata={"help": "m from the approach point at which the robot pushes "
                                                          "even if not lined up (a ball by a wall)"})


@dataclass(frozen=True)
class SchemaParams(StrikerParams):
    """The motor-schema player: the striker driven by the motor schemas (Arkin ch. 4.4)."""

    drive: str = field(default="schema", metadata={"help": "the navigation architecture that drives to the point",
                                                     "choices": DRIVES})


def aim(pose, ball_xy, mode, p: StrikerParams, field: Field, contact: float, ball_radius: float):
    """The target point ``(2,)`` and the new mode for a robot at ``pose`` ``(3,)`` in its own frame, the ball at
    ``ball_xy`` ``(2,)`` and the last ``mode`` (module docstring's table); ``contact`` = body + ball radius (m).
    Except when pushing, the point is kept ``clear`` from the walls for the body (a wall-shy drive never reaches
    a point against a wall)."""
    b = jnp.asarray(ball_xy, jnp.float32)
    g = jnp.array([field.length, 0.5 * field.width], jnp.float32)
    u = (g - b) / jnp.maximum(jnp.linalg.norm(g - b), 1e-6)
    n = jnp.array([-u[1], u[0]])
    rel = jnp.asarray(pose, jnp.float32)[:2] - b
    along, across = rel @ u, rel @ n
    room = _room(field, contact - ball_radius + p.clear)
    approach = jnp.clip(b - (contact + p.behind) * u, *room)
    arrived = jnp.linalg.norm(jnp.asarray(pose, jnp.float32)[:2] - approach) < p.arrive
    lined = (along < -0.5 * contact) & ((jnp.abs(across) < p.lateral) | ((mode == APPROACH) & arrived))
    lined = lined | ((mode == PUSH) & (along < 0.0) & (jnp.abs(across) < 0.8 * contact))
    in_way = (along > -contact) & (jnp.abs(across) < contact + p.clear)
    side = jnp.where(across >= 0.0, 1.0, -1.0)
    detour = jnp.clip(b + (contact + p.clear) * side * n - (contact + p.behind) * u, *room)
    target = jnp.where(lined, b + p.push * u, jnp.where(in_way, detour, approach))
    return target, jnp.where(lined, PUSH, jnp.where(in_way, GO_ROUND, APPROACH)).astype(jnp.int32)


def _room(field: Field, margin: float):
    """The corners (low, high) of the field shrunk by ``margin`` m: the points a wall-shy drive can reach (a point
    against a wall would hold it off for good)."""
    return (jnp.array([margin, margin], jnp.float32),
            jnp.array([field.length - margin, field.width - margin], jnp.float32))


def build(params: StrikerParams, field: Field = Field(), robot: RobotParams = KHEPERA, spec: str = "ekm",
          ball: BallParams = BallParams()) -> Controller:
    """The striker driven by ``params.drive`` with its default parameters (the shipped map for an EKM drive)."""
    from robots.controllers.spec import ArchitectureSpec

    arch = ArchitectureSpec.make(params.drive, {})
    if arch.uses_map:
        from ekm.data import load_default_map

        maps = load_default_map(arch.default_chart)
        inner = arch.build(jax.tree.map(lambda a: a[0], maps.ekm), maps.cfg, robot=robot)
    else:
        inner = arch.build(robot=robot)
    contact = robot.radius + ball.radius

    @jax.jit
    def step(state, play: Play):
        mode, inner_state = state
        target, mode = aim(play.pose, play.ball[:2], mode, params, field, contact, ball.radius)
        opp = play.opponent
        obs = Observation(t=jnp.float32(play.t), ir=jnp.asarray(play.ir, jnp.float32),
                          target=egocentric(jnp.asarray(play.pose, jnp.float32), target, xp=jnp),
                          target_id=mode, final=jnp.bool_(False), pose=jnp.asarray(play.pose, jnp.float32),
                          target_velocity=jnp.zeros(2, jnp.float32),
                          markers=jnp.array([[opp[0], opp[1], opp[3], opp[4], robot.radius]], jnp.float32))
        inner_state, wheels = inner.step(inner_state, obs)
        return (mode, inner_state), wheels

    def init():
        return (jnp.int32(APPROACH), inner.init())

    return Controller(name=spec.split(":")[0], spec=spec, sensors=inner.sensors, init=init, step=step,
                      params=params, robot=robot)
