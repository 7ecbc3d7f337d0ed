"""Sahota's reactive-deliberation soccer player (Sahota 1993, §4.2, Tables 3 and 4) and the two weaker controllers
of his LCI Cup (§4.3, §5.1): the behaviours of Table 4 bid for the executor; the deliberator runs at its own,
slower rate and can interrupt the executor, which runs the one enabled action schema of Table 3 every tick.

**Contract** (:mod:`robots.soccer.play`): ``step(state, play) -> (state, wheels)``, jitted; ``play`` is the game in
the player's own frame — it defends the goal at x = 0 and attacks the goal at x = ``field.length`` — and
``wheels`` are ``(2,)`` speeds (m/s, left and right) within ±c*. Metres, seconds, radians throughout; the IR ring
is carried but not read (the camera sees everything). The executor's schemas, the behaviours' plans and bids,
the three levels and the defaults are specified in docs/reproduce/soccer.md ("The players, specified"), in its
notation: b the ball's centre, r the player's, o the opponent's, G and H the opponent's and the home goal's
centres, R the body radius, c = R + ``ball_radius``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from robots.controllers.base import Controller, ring
from robots.controllers.deliberation import drive_to
from ekm.angles import wrap
from robots.controllers.discrete import bearing, in_the_way, rotate, wheels
from robots.params import KHEPERA, RobotParams
from robots.soccer.field import Field
from robots.soccer.play import Play

#: Action schemas (Table 3), by index.
SCHEMAS = ("idle", "stop", "servo", "defend", "follow path")
IDLE, STOP, SERVO, DEFEND, PATH = range(len(SCHEMAS))
#: Behaviours (Table 4), by index, in his order.
BEHAVIOURS = ("shoot", "clear", "servo at ball", "wait", "go red line", "defend red line", "go home line",
              "defend home line")
SHOOT, CLEAR, AT_BALL, WAIT, GO_RED, DEFEND_RED, GO_HOME, DEFEND_HOME = range(len(BEHAVIOURS))
#: No-wit's cycle: offensive and defensive behaviours in turn (§4.3).
NO_WIT = (SHOOT, DEFEND_RED, AT_BALL, DEFEND_HOME)
#: Sahota's levels (§4.3).
LEVELS = ("full", "half", "none")
_EPS = 1e-3  # s: a clock within this of a deadline has reached it (float32 game time)


@dataclass(frozen=True)
class SoccerDeliberationParams:
    """The level, the deliberator's rate, the schemas' control law and the plans' and bids' sizes
    (docs/reproduce/soccer.md: what each does and why its default)."""

    sensors: str = field(default="long", metadata={"help": "IR ring carried (not read: the camera sees the "
                                                           "opponent): long or short", "choices": ("short", "long")})
    level: str = field(default="full", metadata={
        "help": "Sahota 4.3: full (reactive deliberation), half (half-wit: deliberates only when idle) or none "
                "(no-wit: alternates offence and defence without looking)", "choices": LEVELS})
    period: float = field(default=0.512, metadata={"help": "full: time between deliberations; the executor runs "
                                                           "every tick (s)"})
    max_s: float = field(default=4.096, metadata={"help": "half and none: how long a schema runs before it hands "
                                                          "over to stop (s)"})
    stability: float = field(default=1.0, metadata={"help": "bid added to the ruling behaviour's while its schema "
                                                            "runs (bid)"})
    turn_gain: float = field(default=4.0, metadata={"help": "rad/s of turn per rad of heading error (1/s)"})
    brake_s: float = field(default=0.5, metadata={"help": "where it must stop, speed is distance / brake_s, at "
                                                          "most c* (s)"})
    waypoint: float = field(default=0.015, metadata={"help": "follow path, defend: within this of a point it is "
                                                             "there (m)"})
    behind: float = field(default=0.08, metadata={"help": "push paths: approach point this far behind the ball's "
                                                          "centre (m)"})
    through: float = field(default=0.15, metadata={"help": "push paths: end this far past the ball's centre (m)"})
    around: float = field(default=0.08, metadata={"help": "paths: the waypoint beside the ball this far from its "
                                                          "centre (m)"})
    home_line: float = field(default=0.05, metadata={"help": "x of the home line the goalie defends (m)"})
    band: float = field(default=0.1, metadata={"help": "bids: within this of a line the player is on it (m)"})
    reach: float = field(default=0.3, metadata={"help": "bids: a player within this of the ball is near it (m)"})
    fast_ball: float = field(default=0.3, metadata={"help": "bids: a ball this fast counts as fast (m/s)"})
    horizon_s: float = field(default=8.0, metadata={"help": "bids: a plan this long counts as slow (s)"})
    touch: float = field(default=0.02, metadata={"help": "servo: within this of touching, a ball moving away "
                                                         "has been struck (m)"})
    still: float = field(default=0.005, metadata={"help": "stop: below this speed the player is still (m/s)"})
    halt: float = field(default=0.01, metadata={"help": "collision detection: the opponent's body this near on "
                                                        "the side it drives to stops it (m)"})
    margin: float = field(default=0.005, metadata={"help": "added to the radii: the swept corridor, the way past "
                                                           "the ball (m)"})
    ball_radius: float = field(default=0.02, metadata={"help": "the ball's radius (m)"})
    ball_friction: float = field(default=0.15, metadata={"help": "the ball's rolling deceleration the predictions "
                                                                 "assume (m/s²)"})

    def __post_init__(self):
        if self.sensors not in ("short", "long"):
            raise ValueError(f"sensors must be short or long, got {self.sensors!r}")
        if self.level not in LEVELS:
            raise ValueError(f"level must be one of {', '.join(LEVELS)}, got {self.level!r}")
        for name in ("period", "max_s", "turn_gain", "brake_s", "waypoint", "behind", "through", "around", "band",
                     "reach", "fast_ball", "horizon_s", "touch", "still", "halt", "ball_radius", "ball_friction"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("stability", "home_line", "margin"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")


class Action(NamedTuple):
    """A schema with its run-time parameters: ``schema`` index; ``path`` ``(4, 2)`` — where it was planned from,
    then the waypoints (beside the ball, approach, end); ``first``, the first waypoint to drive to (1 with the
    way round the ball, else 2; 3 when it is already past the approach point); ``line``, defend's x."""

    schema: jax.Array
    path: jax.Array
    first: jax.Array
    line: jax.Array


class PlayerState(NamedTuple):
    """The executor (enabled action, next waypoint, since when it runs) and the deliberator (ruling behaviour,
    −1 before the first; next deliberation; no-wit's place in its cycle)."""

    action: Action
    waypoint: jax.Array
    since: jax.Array
    ruling: jax.Array
    due: jax.Array
    cycle: jax.Array


class Bids(NamedTuple):
    """One deliberation: each behaviour's bid ``(8,)`` (before ``stability``), its action (stacked, leading axis
    8) and its plan's expected time ``(8,)`` (s; 0 for those that do not plan a path)."""

    bids: jax.Array
    actions: Action
    times: jax.Array


def _f32(x):
    return jnp.asarray(x, jnp.float32)


def _unit(v):
    return v / jnp.maximum(jnp.linalg.norm(v), 1e-9)


def _action(schema, path=None, first=2, line=0.0) -> Action:
    path = jnp.zeros((4, 2), jnp.float32) if path is None else _f32(path)
    return Action(jnp.int32(schema), path, jnp.int32(first), _f32(line))


@cache
def init(p: SoccerDeliberationParams) -> PlayerState:
    return PlayerState(_action(IDLE), jnp.int32(0), _f32(0.0), jnp.int32(-1), _f32(-jnp.inf), jnp.int32(0))


# ------------------------------------------------------------------------------------------ plans

def ahead(ball, tau, p: SoccerDeliberationParams, field: Field):
    """Where the ball ``(4,)`` will be in ``tau`` s: straight on, its speed falling by ``ball_friction`` until it
    stops; walls ignored, so kept on the field (no further out than it is now)."""
    b, v = ball[:2], ball[2:4]
    speed = jnp.linalg.norm(v)
    t = jnp.minimum(tau, speed / p.ball_friction)
    pos = b + _unit(v) * (speed * t - 0.5 * p.ball_friction * t * t)
    r = p.ball_radius
    return jnp.clip(pos, jnp.minimum(b, _f32([r, r])), jnp.maximum(b, _f32([field.length - r, field.width - r])))


def inside(point, field: Field, margin: float):
    """Whether ``point`` lies ``margin`` inside the field, or inside the channel through both goal mouths."""
    x, y = point[0], point[1]
    y0, y1 = field.mouth
    in_field = (x >= margin) & (x <= field.length - margin) & (y >= margin) & (y <= field.width - margin)
    in_mouths = (x >= margin - field.goal_depth) & (x <= field.length + field.goal_depth - margin) & (
        y >= y0 + margin) & (y <= y1 - margin)
    return in_field | in_mouths


def way_round(start, goal, ball, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """Whether the straight way ``start`` → ``goal`` passes within c + ``margin`` of the ball's centre ``ball``,
    and the waypoint ``around`` beside the ball on the side it passes (the field's centre's side when it passes
    through the centre; the other side when that one is off the field)."""
    seg = goal - start
    s = jnp.clip(jnp.dot(ball - start, seg) / jnp.maximum(jnp.dot(seg, seg), 1e-12), 0.0, 1.0)
    off = start + s * seg - ball
    dist = jnp.linalg.norm(off)
    perp = _unit(jnp.stack([-seg[1], seg[0]]))
    perp = jnp.where(jnp.dot(perp, _f32([0.5 * field.length, 0.5 * field.width]) - ball) < 0.0, -perp, perp)
    n = jnp.where(dist > 1e-6, off / jnp.maximum(dist, 1e-9), perp)
    beside = ball + p.around * n
    beside = jnp.where(inside(beside, field, robot.radius), beside, ball - p.around * n)
    return dist < robot.radius + p.ball_radius + p.margin, beside


def travel_time(pose, points, robot: RobotParams):
    """Expected time (s) to drive from ``pose`` through ``points`` ``(k, 2)``: length / c* plus every turn
    (the first from the heading) / (2 c* / wheel base); zero-length legs are skipped."""
    here, heading = pose[:2], pose[2]
    length = turn = _f32(0.0)
    for point in points:
        leg = point - here
        d = jnp.linalg.norm(leg)
        valid = d > 1e-6
        h = jnp.arctan2(leg[1], leg[0])
        turn = turn + jnp.where(valid, jnp.abs(wrap(h - heading)), 0.0)
        heading = jnp.where(valid, h, heading)
        length, here = length + d, point
    spin = 2.0 * robot.max_wheel_speed / robot.wheel_base
    return length / robot.max_wheel_speed + turn / spin


def _past(r, point, direction, tol):
    """Whether ``r`` is past ``point`` along the unit ``direction`` and within ``tol`` of the line through it."""
    rel = r - point
    return (jnp.dot(rel, direction) >= 0.0) & (jnp.abs(direction[0] * rel[1] - direction[1] * rel[0]) < tol)


def push_path(pose, ball_at, u, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """A push along ``u`` of the ball (to be) at ``ball_at`` (docs/reproduce/soccer.md): (path ``(4, 2)``, first
    waypoint, expected time to the touch, whether A lies on the field)."""
    r = pose[:2]
    a = ball_at - p.behind * u
    lo, hi = _f32([robot.radius, robot.radius]), _f32([field.length - robot.radius, field.width - robot.radius])
    exits = jnp.where(u > 1e-9, (hi - ball_at) / jnp.where(u > 1e-9, u, 1.0),
                      jnp.where(u < -1e-9, (lo - ball_at) / jnp.where(u < -1e-9, u, 1.0), jnp.inf))
    end = ball_at + jnp.clip(jnp.min(exits), 0.0, p.through) * u
    past = _past(r, a, u, p.waypoint) & (jnp.dot(r - a, u) < p.behind)  # lined up between A and the ball
    blocked, beside = way_round(r, a, ball_at, p, field, robot)
    blocked = blocked & ~past
    first = jnp.where(blocked, 1, jnp.where(past, 3, 2)).astype(jnp.int32)
    touch = ball_at - (robot.radius + p.ball_radius) * u
    time = travel_time(pose, [jnp.where(blocked, beside, r), jnp.where(past, r, a), touch], robot)
    return jnp.stack([r, beside, a, end]), first, time, inside(a, field, robot.radius)


def goto_path(pose, ball, point, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """A go to ``point`` (round the ball if it is in the way): (path ``(4, 2)``, first waypoint, expected time)."""
    r = pose[:2]
    blocked, beside = way_round(r, point, ball, p, field, robot)
    time = travel_time(pose, [jnp.where(blocked, beside, r), point], robot)
    return jnp.stack([r, beside, point, point]), jnp.where(blocked, 1, 2).astype(jnp.int32), time


# ------------------------------------------------------------------------------------------ the deliberator

def bid(play: Play, p: SoccerDeliberationParams, field: Field, robot: RobotParams) -> Bids:
    """Every behaviour's bid, action and plan time for one deliberation (the tables of docs/reproduce/soccer.md)."""
    pose = _f32(play.pose)
    ball, opp = _f32(play.ball), _f32(play.opponent)
    r, b = pose[:2], ball[:2]
    L, W = field.length, field.width
    goal, home = _f32([L, 0.5 * W]), _f32([0.0, 0.5 * W])
    half = 0.5 * L

    def clip(x):
        return jnp.clip(x, 0.0, 1.0)

    def slow(t):
        return clip(jnp.log1p(t) / jnp.log1p(p.horizon_s))

    own, theirs = clip(1.0 - b[0] / half), clip(b[0] / half - 1.0)
    pressed = clip(1.0 - jnp.linalg.norm(opp[:2] - b) / p.reach)
    close = clip(1.0 - jnp.linalg.norm(b - r) / p.reach)
    fast = clip(jnp.linalg.norm(ball[2:4]) / p.fast_ball)
    far = clip(jnp.linalg.norm(goal - b) / L)
    lined = jnp.maximum(0.0, jnp.dot(_unit(goal - b), _unit(b - r)))

    def near(x):
        return clip(1.0 - jnp.abs(r[0] - x) / p.band)

    on_field = (b[0] > 0.0) & (b[0] < L)
    b_hat = ahead(ball, jnp.linalg.norm(b - r) / robot.max_wheel_speed, p, field)
    shoot_path, shoot_first, shoot_t, shoot_ok = push_path(pose, b_hat, _unit(goal - b_hat), p, field, robot)
    clear_path, clear_first, clear_t, clear_ok = push_path(pose, b_hat, _unit(b_hat - home), p, field, robot)
    red_point, home_point = _f32([half, 0.5 * W]), _f32([p.home_line, 0.5 * W])
    red_path, red_first, red_t = goto_path(pose, b, red_point, p, field, robot)
    home_path, home_first, home_t = goto_path(pose, b, home_point, p, field, robot)

    want_red, want_home = 1.0 + 5.0 * theirs, 1.0 + 7.0 * own
    bids = jnp.stack([
        jnp.where(on_field & shoot_ok, 8.0 - 3.0 * slow(shoot_t) - 2.0 * pressed - fast - 2.0 * far, 0.0),
        jnp.where(on_field & clear_ok, 3.0 + 6.0 * own - 3.0 * slow(clear_t) - fast, 0.0),
        lined * (2.0 + 3.0 * close + 3.0 * pressed),
        _f32(1.0),
        want_red * (1.0 - near(half)),
        want_red * near(half),
        want_home * (1.0 - near(p.home_line)),
        want_home * near(p.home_line),
    ])
    actions = [_action(PATH, shoot_path, shoot_first), _action(PATH, clear_path, clear_first), _action(SERVO),
               _action(IDLE), _action(PATH, red_path, red_first), _action(DEFEND, line=half),
               _action(PATH, home_path, home_first), _action(DEFEND, line=p.home_line)]
    zero = _f32(0.0)
    times = jnp.stack([shoot_t, clear_t, zero, zero, red_t, zero, home_t, zero])
    return Bids(jnp.clip(bids, 0.0, 10.0).astype(jnp.float32), jax.tree.map(lambda *a: jnp.stack(a), *actions),
                times)


def deliberate(state: PlayerState, play: Play, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """The deliberator's choice when it runs: (winning behaviour, its action). ``full`` and ``half`` take the
    highest bid, the ruling behaviour's raised by ``stability`` while its schema runs; ``none`` the next of its
    cycle."""
    b = bid(play, p, field, robot)
    if p.level == "none":
        winner = jnp.asarray(NO_WIT, jnp.int32)[state.cycle % len(NO_WIT)]
    else:
        running = state.action.schema != IDLE
        bias = jnp.where((jnp.arange(len(BEHAVIOURS)) == state.ruling) & running, p.stability, 0.0)
        winner = jnp.argmax(b.bids + bias).astype(jnp.int32)
    return winner, jax.tree.map(lambda a: a[winner], b.actions)


# ------------------------------------------------------------------------------------------ the executor

def defend_point(play: Play, line, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """Defend's point on the line x = ``line`` (docs/reproduce/soccer.md): between the ball and the home net's
    centre — on the line from one to the other, or, for a ball level with the line or behind it, beside the ball
    on the net's side (touching distance + ``margin`` from it), in its way along the goal line — or where the ball
    rolling home will cross the line when that is past the body's end; kept R inside the field."""
    ball, r = _f32(play.ball), _f32(play.pose)[:2]
    bx, by, vx, vy = ball[0], ball[1], ball[2], ball[3]
    centre = 0.5 * field.width
    side = jnp.where(by >= centre, 1.0, -1.0)
    between = jnp.where(bx > line, centre + (by - centre) * line / jnp.where(bx > line, bx, 1.0),
                        by - side * (robot.radius + p.ball_radius + p.margin))
    speed = jnp.linalg.norm(ball[2:4])
    run = (line - bx) / jnp.where(vx < 0.0, vx, -1.0)  # s to the line at the present speed
    reaches = (vx < 0.0) & (bx > line) & (speed * speed / (2.0 * p.ball_friction) >= run * speed)  # before it stops
    crossing = by + vy * run
    y = jnp.where(reaches & (jnp.abs(crossing - r[1]) > robot.radius), crossing, between)
    return jnp.stack([jnp.asarray(line, jnp.float32), jnp.clip(y, robot.radius, field.width - robot.radius)])


def execute(state: PlayerState, play: Play, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """One tick of the enabled schema: (its schema after the tick, the next waypoint, (v, ω)). Stop hands over
    to idle in :func:`tick`, before the deliberator looks."""
    pose = _f32(play.pose)
    r, theta = pose[:2], pose[2]
    ball = _f32(play.ball)
    b = ball[:2]
    action, schema = state.action, state.action.schema
    goal = _f32([field.length, 0.5 * field.width])

    # follow path: pass waypoints (up to three in a tick), drive to the next, slowing to the approach point
    path, i = action.path, state.waypoint
    for _ in range(3):
        k = jnp.minimum(i, 3)
        point = path[k]
        leg = jnp.where(k < 3, path[jnp.minimum(k + 1, 3)] - point, point - path[k - 1])
        length = jnp.linalg.norm(leg)
        passed = (jnp.linalg.norm(r - point) < p.waypoint) | (
            (length > 1e-6) & _past(r, point, leg / jnp.maximum(length, 1e-9), p.waypoint))
        i = jnp.where((schema == PATH) & (i <= 3) & passed, i + 1, i)
    path_v, path_w = drive_to(pose, path[jnp.minimum(i, 3)], False, i == 2, p, robot)
    path_done = i >= 4

    # servo at where the ball will be, until it is struck or striking it would not advance it
    rel = b - r
    d = jnp.linalg.norm(rel)
    servo_v, servo_w = drive_to(pose, ahead(ball, d / robot.max_wheel_speed, p, field), False, False, p, robot)
    away = jnp.dot(ball[2:4] - _f32(play.velocity), _unit(rel)) > 0.0
    struck = (d < robot.radius + p.ball_radius + p.touch) & away
    servo_done = struck | (jnp.dot(_unit(goal - b), _unit(rel)) <= 0.0)

    # defend: to the point on the line, forwards or backwards; there, face along the line
    target = defend_point(play, action.line, p, field, robot)
    alpha, dist = bearing(pose, target)
    backwards = jnp.cos(alpha) < 0.0
    defend_v, defend_w = drive_to(pose, target, backwards, True, p, robot)
    there = dist < p.waypoint
    defend_v = jnp.where(there, 0.0, defend_v)
    defend_w = jnp.where(there, p.turn_gain * 0.5 * wrap(2.0 * (0.5 * jnp.pi - theta)), defend_w)

    cases = [schema == PATH, schema == SERVO, schema == DEFEND]
    v = jnp.select(cases, [path_v, servo_v, defend_v], 0.0)
    w = jnp.select(cases, [path_w, servo_w, defend_w], 0.0)

    # collision detection: the opponent's nearest surface point on the side it drives to
    opp = _f32(play.opponent)[:2] - r
    gap = jnp.linalg.norm(opp)
    surface = rotate((opp * jnp.maximum(gap - robot.radius, 0.0) / jnp.maximum(gap, 1e-9))[None], theta)
    way = jnp.where(v < 0.0, -1.0, 1.0) * surface
    danger = (jnp.abs(v) > 1e-6) & (way[0, 0] > 0.0) & (
        (gap - 2.0 * robot.radius < p.halt)
        | in_the_way(way, jnp.ones(1, bool), robot.radius, p.margin, p.halt + jnp.abs(v) * robot.avoid_period)[0])

    ends = ((schema == PATH) & path_done) | ((schema == SERVO) & servo_done) | danger
    v, w = jnp.where(ends, 0.0, v), jnp.where(ends, 0.0, w)
    return jnp.where(ends, STOP, schema).astype(jnp.int32), i, (v, w)


def tick(state: PlayerState, play: Play, p: SoccerDeliberationParams, field: Field, robot: RobotParams):
    """Hand a stop whose player is still to idle, stop a schema that has run ``max_s`` (below ``full``),
    deliberate if it is time (``full``: every ``period``; every level: when the executor is idle), execute:
    (state, (v, ω))."""
    t = _f32(play.t)
    stopped = (state.action.schema == STOP) & (jnp.linalg.norm(_f32(play.velocity)) < p.still)
    state = state._replace(action=state.action._replace(schema=jnp.where(stopped, IDLE, state.action.schema)))
    idle = state.action.schema == IDLE
    if p.level == "full":
        time = idle | (t >= state.due - _EPS)
    else:
        time = idle
        expired = ~idle & (t - state.since >= p.max_s - _EPS)  # a stop that never stills ends after max_s too
        schema = state.action.schema
        state = state._replace(action=state.action._replace(
            schema=jnp.where(expired, jnp.where(schema == STOP, IDLE, STOP), schema).astype(jnp.int32)),
            since=jnp.where(expired, t, state.since))
    winner, chosen = deliberate(state, play, p, field, robot)
    action = jax.tree.map(lambda n, o: jnp.where(time, n, o), chosen, state.action)
    state = PlayerState(action, jnp.where(time, action.first, state.waypoint).astype(jnp.int32),
                        jnp.where(time, t, state.since), jnp.where(time, winner, state.ruling).astype(jnp.int32),
                        jnp.where(time, t + p.period, state.due).astype(jnp.float32),
                        state.cycle + time.astype(jnp.int32))
    schema, waypoint, command = execute(state, play, p, field, robot)
    return state._replace(action=action._replace(schema=schema), waypoint=waypoint), command


def step(state: PlayerState, play: Play, *, p: SoccerDeliberationParams, field: Field = Field(),
         robot: RobotParams = KHEPERA):
    """One tick as wheel speeds (m/s, left and right)."""
    state, (v, w) = tick(state, play, p, field, robot)
    return state, wheels(v, w, robot)


def build(params: SoccerDeliberationParams, field: Field = Field(), robot: RobotParams = KHEPERA,
          spec: str = "deliberation") -> Controller:
    """The reactive-deliberation soccer player (at ``params.level``) on ``robot`` for ``field``."""
    return Controller(name="deliberation", spec=spec, sensors=ring(robot, params.sensors),
                      init=partial(init, params), step=jax.jit(partial(step, p=params, field=field, robot=robot)),
                      params=params, robot=robot)
