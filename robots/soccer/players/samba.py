"""Samba for Soccer (Riekki 1999, ch. 5) on a Khepera: action maps for the ball, the goals and the opponent,
combined by MAV and arbitrated as his player's tasks, the heaviest action sent to the wheels.

**Contract** (:mod:`robots.soccer.play`): ``step(state, play) -> (state, wheels)``, jitted; ``play`` is the
game in the player's own frame — it defends the goal at x = 0 and attacks the goal at x = ``field.length``
— and ``wheels`` are ``(2,)`` speeds (m/s, left and right) within ±c*. Metres, seconds, radians throughout.
:func:`maps` is the tick without the wheels (pure: a recorded ``(state, play)`` gives the maps the game used).
The object markers, the primitive and composite maps, the arbiter's tasks and the defaults are specified in
docs/reproduce/soccer.md ("The players, specified").
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.angles import wrap
from robots.controllers import actionmaps as am
from robots.controllers import escape as esc
from robots.controllers import samba as nav
from robots.controllers.base import Controller, ring, velocity_to_wheels
from robots.params import KHEPERA, RobotParams
from robots.soccer.field import Field
from robots.soccer.play import Play

#: The tasks in the arbiter's order (docs/reproduce/soccer.md); a state's ``task`` indexes this (−1 before the first).
TASKS = ("make_goal", "dribble", "catch_ball", "defloc", "turn_to_ball")


@dataclass(frozen=True)
class SoccerSambaParams:
    """Parameters of the Samba soccer player (docs/reproduce/soccer.md: what each does and why its default)."""

    sensors: str = field(default="long", metadata={"help": "IR ring carried (no map reads it): long or short",
                                                   "choices": ("short", "long")})
    directions: int = field(default=36, metadata={"help": "directions of the velocity maps (count; 36 = 10° apart)"})
    speeds: int = field(default=4, metadata={"help": "speeds of the velocity maps, evenly up to c* (count)"})
    full_s: float = field(default=am.FULL_S, metadata={"help": "weight curve: full weight up to this time (s)"})
    tau_s: float = field(default=am.TAU_S, metadata={"help": "weight curve: exponential fall's time constant (s)"})
    ball_radius: float = field(default=0.02, metadata={"help": "the ball's radius (m)"})
    restitution: float = field(default=0.7, metadata={"help": "ball–robot restitution the kick maps assume (ratio)"})
    aim_margin: float = field(default=0.02, metadata={"help": "make_goal: the ball's line must pass this far "
                                                              "inside the posts (m)"})
    dribble_sector: float = field(default=0.7853981633974483,
                                  metadata={"help": "dribble: the ball's direction within this of the direction "
                                                    "to the goal's centre (rad)"})
    kick_s: float = field(default=1.0, metadata={"help": "a kick task is valid when a positive action touches "
                                                         "the ball within this time (s)"})
    gap: float = field(default=0.02, metadata={"help": "kick point: this far behind the touching distance (m)"})
    avoid_ttc: float = field(default=1.0, metadata={"help": "AvoidOpp filter: collisions later than this are not "
                                                            "inhibited (s)"})
    clearance: float = field(default=0.005, metadata={"help": "added to the radii in the Avoid maps (m)"})
    ball_ttc: float = field(default=1.5, metadata={"help": "AvoidBall filter: touches later than this are not "
                                                           "inhibited (s; Riekki's MovetoSpecloc)"})
    defend_frac: float = field(default=0.5, metadata={"help": "defensive location: this fraction of the way from "
                                                              "the home goal's centre to the ball (ratio)"})
    defend_min: float = field(default=0.06, metadata={"help": "defensive location: at least this far from the "
                                                             "home goal's centre (m)"})
    rolling_friction: float = field(default=0.15, metadata={"help": "the ball's rolling deceleration the markers "
                                                                   "assume (m/s²)"})
    threat_s: float = field(default=1.0, metadata={"help": "the opponent has the ball when it can be at its kick "
                                                           "point within this, before the player (s)"})
    defend_range: float = field(default=0.6, metadata={"help": "the player defends only a ball within this of the "
                                                               "home goal's centre (m)"})
    stay_s: float = field(default=0.5, metadata={"help": "task hysteresis: the last tick's task keeps its "
                                                         "conditions looser by this (s)"})
    brake_s: float = field(default=0.2, metadata={"help": "defensive location: speeds above distance / brake_s "
                                                          "are filtered (s)"})
    tie: float = field(default=0.1, metadata={"help": "arbiter hysteresis: actions near the last one's direction "
                                                      "count their time shorter by this (fraction)"})
    keep: float = field(default=0.2, metadata={"help": "arbiter hysteresis: either side of the last action's "
                                                       "direction that counts as near it (rad)"})
    refine: bool = field(default=True, metadata={"help": "arbiter: refine the chosen direction between its "
                                                         "neighbours (on/off)"})
    guard: bool = field(default=True, metadata={"help": "arbiter: slow a turn's straight-ahead motion to what the "
                                                        "composite map does not inhibit (on/off)"})

    def __post_init__(self):
        if self.sensors not in ("short", "long"):
            raise ValueError(f"sensors must be short or long, got {self.sensors!r}")
        for name in ("tau_s", "ball_radius", "dribble_sector", "kick_s", "avoid_ttc", "ball_ttc", "brake_s"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("full_s", "aim_margin", "gap", "clearance", "defend_min", "stay_s", "keep", "rolling_friction",
                     "threat_s", "defend_range"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not 0 <= self.restitution <= 1 or not 0 <= self.defend_frac <= 1 or not 0 <= self.tie < 1:
            raise ValueError("restitution and defend_frac must be in [0, 1] and tie in [0, 1)")
        if self.directions < 4 or self.speeds < 1:
            raise ValueError("directions >= 4 and speeds >= 1 are needed")

    def grid(self, robot: RobotParams = KHEPERA) -> am.VelocityGrid:
        """The velocity maps' actions: ``directions`` × ``speeds`` up to the robot's c*."""
        return am.VelocityGrid(self.directions, self.speeds, robot.max_wheel_speed)


class SoccerSambaState(NamedTuple):
    """What the player carries between ticks: the task performed last (index into :data:`TASKS`, −1 before
    the first) and the world direction of the last action sent (NaN before the first), for the hysteresis."""

    task: jax.Array
    heading: jax.Array


class Tick(NamedTuple):
    """One tick (:func:`maps`): the state after it; the primitive maps ``(n_dir, n_speed)`` of
    docs/reproduce/soccer.md (``avoid_opp`` before its filtering to the collisions before the touch); ``composite``
    ``(4, n_dir, n_speed)``, the composite maps of tasks 0–3; ``valid`` ``(5,)``, which tasks could be
    performed; the ``task`` performed, its action (indices ``i, j``, ``direction`` in the robot frame,
    ``speed``); the ``kick_point`` and ``defloc`` ``(2,)`` (field, own frame) and the times ``t_me`` and
    ``t_opp`` (s) each player needs to its kick point."""

    state: SoccerSambaState
    goto_ball: jax.Array
    make_goal: jax.Array
    dont_kick_opp: jax.Array
    dribble: jax.Array
    goto_kick: jax.Array
    goto_defloc: jax.Array
    avoid_opp: jax.Array
    avoid_ball: jax.Array
    composite: jax.Array
    valid: jax.Array
    task: jax.Array
    i: jax.Array
    j: jax.Array
    direction: jax.Array
    speed: jax.Array
    kick_point: jax.Array
    defloc: jax.Array
    t_me: jax.Array
    t_opp: jax.Array


@cache
def init(p: SoccerSambaParams) -> SoccerSambaState:
    return SoccerSambaState(jnp.asarray(-1, jnp.int32), jnp.asarray(jnp.nan, jnp.float32))


def _unit(v):
    return v / jnp.maximum(jnp.linalg.norm(v, axis=-1, keepdims=True), 1e-9)


def _inside(point, field: Field, margin: float):
    """``point`` moved into the field, ``margin`` from its edges."""
    return jnp.stack([jnp.clip(point[0], margin, field.length - margin),
                      jnp.clip(point[1], margin, field.width - margin)])


def task_points(ball, p: SoccerSambaParams, field: Field, robot: RobotParams):
    """The task markers (field frame): our kick point, the opponent's (its mirror: behind the ball as seen
    from our goal) and the defensive location (docs/reproduce/soccer.md)."""
    b = ball[:2]
    ours, home = jnp.asarray([field.length, 0.5 * field.width]), jnp.asarray([0.0, 0.5 * field.width])
    behind = robot.radius + p.ball_radius + p.gap
    margin = robot.radius + p.clearance
    kick = _inside(b - behind * _unit(ours - b), field, margin)
    theirs = _inside(b + behind * _unit(b - home), field, margin)
    d = jnp.linalg.norm(b - home)
    along = jnp.maximum(jnp.minimum(jnp.maximum(p.defend_frac * d, p.defend_min), d - behind), 0.0)
    defloc = _inside(home + along * _unit(b - home), field, margin)
    return kick, theirs, defloc


def chased(ball, chaser, p: SoccerSambaParams, robot: RobotParams):
    """The ball marker ``(4,)`` as a player at ``chaser`` (field frame) chases it: at its velocity when the player,
    at c*, can touch it before its rolling friction stops it (after |v| / ``rolling_friction`` s), else at
    rest where it will stop, |v|² / (2 ``rolling_friction``) further on (docs/reproduce/soccer.md)."""
    if p.rolling_friction == 0:
        return ball
    b, v = ball[:2], ball[2:4]
    speed = jnp.linalg.norm(v)
    t = am.earliest_collision(b - chaser, v, robot.radius + p.ball_radius, robot.max_wheel_speed)
    early = t <= speed / p.rolling_friction
    stop = b + v * speed / (2.0 * p.rolling_friction)
    return jnp.where(early, ball, jnp.concatenate([stop, jnp.zeros(2)]))


def touches(play: Play, p: SoccerSambaParams, robot: RobotParams):
    """Every action's touch on the ball: the time ``(n_dir, n_speed)`` until the robot's disc first touches the
    moving ball (``inf``: never), where the ball's centre is then and its velocity after the touch
    ``(n_dir, n_speed, 2)`` (field frame) — v_b + (1 + e)·max((v − v_b)·n, 0)·n with n the line of centres."""
    grid = p.grid(robot)
    pose = jnp.asarray(play.pose, jnp.float32)
    ball = jnp.asarray(play.ball, jnp.float32)
    theta = pose[2]
    b = esc.to_robot(ball[:2] - pose[:2], theta)
    vb = esc.to_robot(ball[2:4], theta)
    t = am.collision_times(b[None], vb[None], jnp.asarray([robot.radius + p.ball_radius]), grid)
    tt = jnp.where(jnp.isfinite(t), t, 0.0)[..., None]
    v = jnp.asarray(grid.velocities())
    centre = b + vb * tt  # the ball at the touch, robot frame (the robot is at v·t)
    n = _unit(centre - v * tt)
    push = jnp.maximum(jnp.sum((v - vb) * n, axis=-1, keepdims=True), 0.0)
    out = vb + (1.0 + p.restitution) * push * n
    # back to the field frame: to_robot by −θ turns by +θ
    return t, pose[:2] + esc.to_robot(centre, -theta), esc.to_robot(out, -theta)


def kicks(play: Play, p: SoccerSambaParams, field: Field, robot: RobotParams):
    """The kick maps' times and masks ``(n_dir, n_speed)`` (docs/reproduce/soccer.md): each action's time to touch the
    ball; the time the ball then takes, at its speed after the touch, to the goal line (``inf`` if it does not
    go that way); whether it crosses the line between the posts less ``aim_margin`` (make_goal) and whether it
    leaves within ``dribble_sector`` of the direction to the goal's centre (dribble)."""
    t, at, out = touches(play, p, robot)
    hit = jnp.isfinite(t) & (jnp.linalg.norm(out - jnp.asarray(play.ball[2:4], jnp.float32), axis=-1) > 1e-6)
    y0, y1 = field.mouth
    forward = out[..., 0] > 1e-6
    flight = jnp.where(forward, (field.length - at[..., 0]) / jnp.where(forward, out[..., 0], 1.0), jnp.inf)
    cross = at[..., 1] + out[..., 1] * jnp.where(forward, flight, 0.0)
    goal = hit & forward & (cross >= y0 + p.aim_margin) & (cross <= y1 - p.aim_margin)
    to_goal = jnp.asarray([field.length, 0.5 * field.width]) - at
    off = wrap(jnp.arctan2(out[..., 1], out[..., 0]) - jnp.arctan2(to_goal[..., 1], to_goal[..., 0]))
    dribble = hit & (jnp.abs(off) <= p.dribble_sector)
    return t, at, out, flight, goal, dribble


def ball_meets(at, out, t, opponent, radius: float):
    """For kicks from ``at`` ``(n_dir, n_speed, 2)`` at velocity ``out`` after touches at times ``t``: how long
    after the touch the ball meets the opponent's disc (``radius``: its radius plus the ball's), the opponent
    ``(5,)`` keeping its velocity (``inf``: never)."""
    vo = opponent[3:5]
    tt = jnp.where(jnp.isfinite(t), t, 0.0)[..., None]
    q = (at - (opponent[:2] + vo * tt)).reshape(-1, 2)
    u = (out - vo).reshape(-1, 2)
    meet = jax.vmap(lambda q, u: am.earliest_collision(q, u, radius, 0.0))(q, u)
    return meet.reshape(t.shape)


def _seen(play: Play, point, velocity):
    """A field-frame point and velocity as seen from the robot (position, velocity in the robot frame)."""
    pose = jnp.asarray(play.pose, jnp.float32)
    return esc.to_robot(point - pose[:2], pose[2]), esc.to_robot(velocity, pose[2])


def maps(state: SoccerSambaState, play: Play, p: SoccerSambaParams, field: Field = Field(),
         robot: RobotParams = KHEPERA) -> Tick:
    """The player's maps, the task and the action of one tick (docs/reproduce/soccer.md); pure."""
    grid = p.grid(robot)
    ball = jnp.asarray(play.ball, jnp.float32)
    opp = jnp.asarray(play.opponent, jnp.float32)
    me = jnp.asarray(play.pose, jnp.float32)
    c = robot.max_wheel_speed
    touch = robot.radius + p.ball_radius
    w = partial(am.weight, full=p.full_s, tau=p.tau_s)

    # primitive maps
    b, vb = _seen(play, ball[:2], ball[2:4])
    goto_ball = am.osa(b, vb, grid, radius=touch, full=p.full_s, tau=p.tau_s)
    t_touch, at, out, flight, goal, aimed = kicks(play, p, field, robot)
    make_goal = jnp.where(goal, w(t_touch + flight), 0.0)
    dribble = am.apply_mask(goto_ball, aimed)
    meet = ball_meets(at, out, t_touch, opp, touch)
    dont_kick_opp = jnp.where(jnp.isfinite(t_touch), -w(t_touch + meet), 0.0)
    mine = chased(ball, me[:2], p, robot)
    kick, _, defloc = task_points(mine, p, field, robot)
    k, vk = _seen(play, kick, mine[2:4])
    goto_kick = am.osa(k, vk, grid, full=p.full_s, tau=p.tau_s)
    dl, _ = _seen(play, defloc, jnp.zeros(2))
    goto_defloc = am.apply_mask(am.osa(dl, jnp.zeros(2), grid, full=p.full_s, tau=p.tau_s),
                                am.speed_mask(grid, jnp.linalg.norm(dl) / p.brake_s))
    o, vo = _seen(play, opp[:2], opp[3:5])
    t_opp_hit = am.collision_times(o[None], vo[None], jnp.asarray([2.0 * robot.radius + p.clearance]), grid)
    avoid_opp = am.filter_times(am.avoid(t_opp_hit, p.full_s, p.tau_s), t_opp_hit, p.avoid_ttc)
    before_touch = am.filter_map(avoid_opp, t_opp_hit >= t_touch)  # for kicks: the collisions before the touch
    t_ball_hit = am.collision_times(b[None], vb[None], jnp.asarray([touch + p.clearance]), grid)
    avoid_ball = am.filter_times(am.avoid(t_ball_hit, p.full_s, p.tau_s), t_ball_hit, p.ball_ttc)

    # composite maps (Table 7) and the arbiter's task
    composite = jnp.stack([am.mav(make_goal, dont_kick_opp, before_touch), am.mav(dribble, before_touch),
                           am.mav(goto_kick, avoid_opp, avoid_ball), am.mav(goto_defloc, avoid_opp, avoid_ball)])
    best = jnp.max(composite, axis=(1, 2))
    t_me = am.earliest_collision(k, vk, 0.0, c)
    yours = chased(ball, opp[:2], p, robot)
    _, theirs, _ = task_points(yours, p, field, robot)
    t_opp = am.earliest_collision(theirs - opp[:2], yours[2:4], 0.0, c)
    last = state.task

    def kick_ok(n):  # a positive action on the composite that touches the ball soon enough
        soon = t_touch <= p.kick_s + jnp.where(last == n, p.stay_s, 0.0)
        return jnp.any((composite[n] > 0) & soon)

    held = jnp.where(last == 3, p.stay_s, 0.0)  # defending: its conditions looser
    band = jnp.where(last == 3, p.stay_s, jnp.where(last == 2, -p.stay_s, 0.0))
    near_home = jnp.linalg.norm(ball[:2] - jnp.asarray([0.0, 0.5 * field.width])) <= p.defend_range + held
    threat = (t_opp <= p.threat_s + held) & (t_opp < t_me + band) & near_home
    valid = jnp.stack([kick_ok(0), kick_ok(1), ~threat & (best[2] > 0), best[3] > 0, jnp.asarray(True)])
    task = jnp.argmax(valid).astype(jnp.int32)

    # the action: the navigation Samba's arbiter on the task's map, or a turn towards the ball
    chosen = composite[jnp.minimum(task, 3)]
    theta = me[2]
    i, j, _ = nav.arbiter(chosen, state.heading, theta, p, grid)
    mapped = task < 4
    direction = jnp.asarray(grid.angles())[i]
    if p.refine:
        direction = direction + jnp.where(mapped, nav.refine(chosen, i, j), 0.0) * grid.step_angle
    speed = jnp.asarray(grid.speed_values())[j]
    if p.guard:
        speed = nav.forward_speed(direction, speed, chosen, grid)
    direction = jnp.where(mapped, direction, jnp.arctan2(b[1], b[0]))
    speed = jnp.where(mapped, speed, 0.0)
    heading = jnp.where(mapped, wrap(theta + direction), state.heading)
    return Tick(SoccerSambaState(task, heading), goto_ball, make_goal, dont_kick_opp, dribble, goto_kick, goto_defloc,
                avoid_opp, avoid_ball, composite, valid, task, i, j, direction, speed, kick, defloc, t_me, t_opp)


def step(state: SoccerSambaState, play: Play, *, p: SoccerSambaParams, field: Field = Field(),
         robot: RobotParams = KHEPERA):
    """One tick: :func:`maps`, then the action as wheel speeds (:func:`velocity_to_wheels`)."""
    tick = maps(state, play, p, field, robot)
    return tick.state, velocity_to_wheels(tick.direction, tick.speed, robot)


def build(params: SoccerSambaParams, field: Field = Field(), robot: RobotParams = KHEPERA,
          spec: str = "samba") -> Controller:
    """The Samba soccer player on ``robot`` for ``field``."""
    return Controller(name="samba", spec=spec, sensors=ring(robot, params.sensors), init=partial(init, params),
                      step=jax.jit(partial(step, p=params, field=field, robot=robot)), params=params, robot=robot)
