"""Reactive deliberation (Sahota 1993, ch. 3 and §4.2–4.3): behaviours bid for the executor; the deliberator
runs at its own, slower rate and can interrupt the executor, which runs the one enabled action schema every
tick.

**The executor** (§3.2, Table 3): exactly one action schema is enabled, with the run-time parameters that
fully define it; it ends by handing over to another (follow path → stop → idle, as Sahota's do):

=============== ============================== ================================================================
schema          parameters                     every tick
=============== ============================== ================================================================
``idle``        none                           sends nothing (zero wheel speeds)
``stop``        none                           sends zero and hands over to idle
``servo``       none                           drives at the current checkpoint (as Sahota's servo drives at
                                               the ball): turn ``turn_gain`` · α, speed min(c*, d / ``brake_s``)
                                               · max(0, cos α); at the goal (within ``stop_within``) → stop
``follow path`` waypoints (world), direction   drives through the waypoints in turn by the same law (backwards
                                               if so set, facing away), each passed within ``waypoint``; after
                                               the last → stop
=============== ============================== ================================================================

Sahota's *collision detection subsystem* runs beside every schema: a point within ``halt`` of the body on
the side it drives to (ahead of the axle, or behind it when backing), or in the corridor the body sweeps
(half-width radius + ``margin``) within ``halt`` + one tick's travel, hands control to stop — unless the servo or
follow path still has more than :data:`FACING` to turn to face its way: then it turns on the spot, which sweeps
nothing, and runs on (an extension, issue 35: in a corridor 8.5 cm wide the robot that had to turn 40° at its
start stood, stopped and re-chosen every tick, until the trap monitor fired).

**The deliberator** (§3.3, Table 4's form): each behaviour selects a schema, computes its parameters and
bids in [0, 10] — a base bid plus and minus weighted factors in [0, 1] (§4.2.3); the highest bid wins, and
the ruling behaviour's bid is raised by ``stability`` (§3.3.2: "behaviours that have terminating actions
bias their bid upward"). b = the share of the way to the checkpoint that is blocked (1 − free / d, free
distance along the line to it, :func:`~robots.controllers.discrete.free_ahead`, over the IR memory and the
declared movers, :func:`~robots.controllers.discrete.sense`):

=================== ================== ===================================== ===================================
behaviour           schema             parameters                            bid
=================== ================== ===================================== ===================================
go to checkpoint    servo              none                                  5 − 5 b
go round            follow path        a detour point ``detour`` (or twice   2 + 6 b
                                       that) beside the blockage, on the
                                       freer side, then the checkpoint
back away           follow path        a point ``backoff`` straight behind   9 when a point is within ``close``
                    (backwards, or     (backwards) or, from a declared       of the body ahead, or a declared
                    facing the way     mover closing within ``wait_within``,  mover closes within
                    out)               out of its line                       ``wait_within``; else 0
wait                stop               none                                  7 − 7 · (s waited / ``patience``)
                                                                             when a declared mover crosses the
                                                                             way within ``wait_within``, else 0
=================== ================== ===================================== ===================================

The winning behaviour's action replaces the executor's when it differs (another behaviour, or the ruling
one's schema has ended); a ruling behaviour that wins again keeps its action running unless the way to its
path's next waypoint has become blocked — then it plans the action afresh (§3.3.1: the ruling behaviour
"may want to modify the current action to reflect changes in the environment"). Wait's bid falls the
longer it waits (§3.3.2: "boredom").

**Sahota's three levels** (§4.3, the LCI Cup's controllers), the parameter ``level``:

- ``full`` — reactive deliberation: the deliberator runs every ``period`` s, concurrently with the
  executor, and interrupts it whenever another behaviour wins;
- ``half`` — half-wit: it deliberates only when the executor is idle (its schema has ended) or the schema
  has run ``max_s``;
- ``none`` — no-wit: at those moments it takes the next behaviour in a fixed cycle (go to checkpoint, go
  round, back away, wait) without evaluating the world.

Parameters were chosen on generated worlds (tuning seeds), never on the named ones
(``docs/reproduce/discrete.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm.angles import wrap
from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, avoid_option, on_ring, ring
from robots.controllers.discrete import bearing, free_ahead, in_the_way, rotate, sense, way_out, wheels, world_point
from robots.params import KHEPERA, RobotParams

#: Action schemas, by index.
SCHEMAS = ("idle", "stop", "servo", "follow path")
IDLE, STOP, SERVO, PATH = range(len(SCHEMAS))
#: rad: a servo or follow path with more than this to turn still turns on the spot where collision detection stops it.
FACING = 0.2
#: Behaviours, by index (also no-wit's fixed cycle).
BEHAVIOURS = ("go to checkpoint", "go round", "back away", "wait")
GOTO, ROUND, BACK, WAIT = range(len(BEHAVIOURS))
#: Sahota's levels (§4.3).
LEVELS = ("full", "half", "none")


@dataclass(frozen=True)
class DeliberationParams:
    """The level, the deliberator's rate, the schemas' control law and the behaviours' distances (m) and times (s)."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm) or short "
                                                           "(8 Khepera sensors, 5 cm)", "choices": ("short", "long")})
    level: str = field(default="full", metadata={
        "help": "Sahota 4.3: full (reactive deliberation), half (half-wit: deliberates when idle) or none (no-wit: "
                "cycles without looking)", "choices": LEVELS})
    period: float = field(default=0.512, metadata={"help": "s between deliberations (the executor runs every tick)"})
    max_s: float = field(default=4.096, metadata={"help": "half and none: s a schema runs before the deliberator "
                                                          "takes over"})
    turn_gain: float = field(default=4.0, metadata={"help": "servo, follow path: rad/s of turn per rad of heading "
                                                            "error"})
    brake_s: float = field(default=0.5, metadata={"help": "servo, follow path: speed is distance / brake_s, at most c*"})
    stop_within: float = field(default=0.003, metadata={"help": "servo: m from the goal within which it stops"})
    waypoint: float = field(default=0.015, metadata={"help": "follow path: m within which a waypoint is passed"})
    halt: float = field(default=0.01, metadata={"help": "collision detection: m from the body (ahead, or behind when "
                                                        "backing) that stops it, plus one tick's travel straight on"})
    margin: float = field(default=0.005, metadata={"help": "collision detection: m added to the body radius for the "
                                                           "half-width of the corridor it sweeps"})
    clearance: float = field(default=0.01, metadata={"help": "bids: m from the body surface that blocks the way"})
    detour: float = field(default=0.08, metadata={"help": "go round: m beside the blockage of the detour point"})
    backoff: float = field(default=0.05, metadata={"help": "back away: m it backs"})
    close: float = field(default=0.01, metadata={"help": "back away: m from the body surface ahead that makes it bid"})
    wait_within: float = field(default=0.1, metadata={"help": "wait: m from the body surface of a mover in the way"})
    patience: float = field(default=4.0, metadata={"help": "wait: s after which its bid has fallen to 0"})
    stability: float = field(default=1.0, metadata={"help": "bid added to the ruling behaviour's"})
    memory_s: float = mem.option("memory_s", 30.0)
    memory_points: int = mem.option("memory_points", 128)
    merge: float = mem.option("merge", 0.01)
    see_through: float = mem.option("see_through", 0.01, why="merge; 5 mm lost more worlds than it gained")
    avoid: str = avoid_option("which remembered points it avoids: all or nearer (at the goal, none beyond it; an "
                              "extension)")

    def __post_init__(self):
        for name in ("period", "max_s", "turn_gain", "brake_s", "stop_within", "waypoint", "halt", "detour",
                     "backoff", "close", "wait_within", "patience", "memory_s", "merge", "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("margin", "clearance", "stability"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if self.level not in LEVELS:
            raise ValueError(f"level must be one of {', '.join(LEVELS)}, got {self.level!r}")
        if not (isinstance(self.memory_points, int) and self.memory_points >= 1):
            raise ValueError(f"memory_points must be a whole number >= 1, got {self.memory_points}")


class Action(NamedTuple):
    """An action schema with its run-time parameters: ``schema`` index, ``path`` ``(2, 2)`` world waypoints,
    ``backwards`` (follow path facing away)."""

    schema: jax.Array
    path: jax.Array
    backwards: jax.Array


class DeliberationState(NamedTuple):
    """The executor (enabled action, next waypoint, since when) and the deliberator (ruling behaviour, next
    deliberation, no-wit's place in its cycle, since when wait rules)."""

    memory: mem.Memory
    action: Action
    waypoint: jax.Array
    since: jax.Array
    ruling: jax.Array
    due: jax.Array
    cycle: jax.Array
    waiting_since: jax.Array


class Bids(NamedTuple):
    """One deliberation: each behaviour's bid ``(4,)`` (before the ruling one's ``stability``) and action, and
    the blocked share b."""

    bids: jax.Array
    actions: Action
    blocked: jax.Array


def _action(schema, path=None, backwards=False) -> Action:
    path = jnp.zeros((2, 2), jnp.float32) if path is None else jnp.asarray(path, jnp.float32)
    return Action(jnp.int32(schema), path, jnp.bool_(backwards))


@cache
def init(p: DeliberationParams) -> DeliberationState:
    f = partial(jnp.asarray, dtype=jnp.float32)
    return DeliberationState(mem.empty(p.memory_points), _action(IDLE), jnp.int32(0), f(0.0), jnp.int32(-1),
                             f(-jnp.inf), jnp.int32(0), f(jnp.inf))


# ------------------------------------------------------------------------------------------ the deliberator

def blocked_share(points, valid, target, p: DeliberationParams, radius: float):
    """b: the share of the way to the checkpoint u_p = ``target`` that is blocked, and the free distance along it."""
    alpha, d = target[0], target[1]
    free = free_ahead(rotate(points, alpha), valid, radius, p.clearance)
    return jnp.clip(1.0 - free / jnp.maximum(d, 1e-6), 0.0, 1.0), free


def detour_point(points, valid, target, free, pose, p: DeliberationParams, radius: float):
    """Go round's detour point (world): ``detour`` m (or twice that) to the side of the line to the checkpoint where
    it is blocked: the first of left, right, twice left, twice right whose straight way from the robot is the
    freest."""
    alpha, d = target[0], target[1]
    along = jnp.minimum(free, d)
    ahead = along * jnp.stack([jnp.cos(alpha), jnp.sin(alpha)])
    side = p.detour * jnp.stack([-jnp.sin(alpha), jnp.cos(alpha)])
    best, best_share = ahead + side, jnp.float32(-1.0)
    for candidate in (ahead + side, ahead - side, ahead + 2 * side, ahead - 2 * side):
        angle, length = jnp.arctan2(candidate[1], candidate[0]), jnp.linalg.norm(candidate)
        share = jnp.minimum(free_ahead(rotate(points, angle), valid, radius, p.clearance) / length, 1.0)
        take = share > best_share
        best, best_share = jnp.where(take, candidate, best), jnp.where(take, share, best_share)
    return world_point(pose, (jnp.arctan2(best[1], best[0]), jnp.linalg.norm(best)))


def mover_in_way(obs: Observation, p: DeliberationParams, radius: float):
    """Whether a declared mover's body is within ``wait_within`` of the robot's, within 60° of the line to the
    checkpoint, and not closing on the robot (it crosses the way, or leaves)."""
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    pose = jnp.asarray(obs.pose, jnp.float32)
    alpha, dist = jax.vmap(lambda m: bearing(pose, m[:2]))(markers)
    gap = dist - markers[:, 4] - radius
    ahead = jnp.abs(wrap(alpha - obs.target[0])) < jnp.pi / 3
    closing = jnp.sum((pose[None, :2] - markers[:, :2]) * markers[:, 2:4], axis=1) > 0.0
    return jnp.any((gap < p.wait_within) & ahead & ~closing)


def bid(points, valid, obs: Observation, waited, p: DeliberationParams, radius: float) -> Bids:
    """Every behaviour's bid and action for one deliberation (the table of the module docstring)."""
    pose = jnp.asarray(obs.pose, jnp.float32)
    b, free = blocked_share(points, valid, obs.target, p, radius)
    goal = world_point(pose, obs.target)
    detour = detour_point(points, valid, obs.target, free, pose, p, radius)
    ahead = valid & (points[:, 0] > 0.0) & (jnp.sqrt(jnp.sum(jnp.square(points), axis=1)) < radius + p.close)
    # back away: straight back, or out of the line of a mover closing on the robot (facing the way out, or away)
    threat, out = way_out(obs, radius, p.wait_within)
    facing = jnp.cos(jnp.arctan2(out[1], out[0]) - pose[2]) >= 0.0
    behind = jnp.where(threat, pose[:2] + p.backoff * out, world_point(pose, (jnp.float32(jnp.pi), jnp.float32(p.backoff))))
    backwards = jnp.where(threat, ~facing, True)
    bids = jnp.stack([5.0 - 5.0 * b, 2.0 + 6.0 * b, jnp.where(jnp.any(ahead) | threat, 9.0, 0.0),
                      jnp.where(mover_in_way(obs, p, radius), 7.0 * jnp.clip(1.0 - waited / p.patience, 0.0, 1.0),
                                0.0)])
    actions = [_action(SERVO), _action(PATH, jnp.stack([detour, goal])), _action(PATH, jnp.stack([behind, behind]), backwards),
               _action(STOP)]
    return Bids(bids.astype(jnp.float32), jax.tree.map(lambda *a: jnp.stack(a), *actions), b)


def leg_blocked(state: DeliberationState, points, valid, obs: Observation, p: DeliberationParams, radius: float):
    """Whether the running follow-path (forwards) is blocked on its way to its next waypoint (free distance
    along the way shorter than the way): its behaviour, ruling still, then plans its action afresh."""
    action = state.action
    alpha, d = bearing(jnp.asarray(obs.pose, jnp.float32), action.path[jnp.minimum(state.waypoint, 1)])
    free = free_ahead(rotate(points, alpha), valid, radius, p.clearance)
    return (action.schema == PATH) & ~action.backwards & (free < d)


def deliberate(state: DeliberationState, points, valid, obs: Observation, p: DeliberationParams, radius: float):
    """The deliberator, when it runs this tick: (behaviour that rules, the executor's action, whether it changed)."""
    t = jnp.asarray(obs.t, jnp.float32)
    waited = jnp.where(state.ruling == WAIT, t - state.waiting_since, 0.0)
    b = bid(points, valid, obs, waited, p, radius)
    ended = state.action.schema == IDLE
    if p.level == "none":
        winner = state.cycle % len(BEHAVIOURS)
    else:
        winner = jnp.argmax(b.bids + jnp.where(jnp.arange(len(BEHAVIOURS)) == state.ruling, p.stability, 0.0))
    new = (winner != state.ruling) | ended | (leg_blocked(state, points, valid, obs, p, radius) & (p.level == "full"))
    chosen = jax.tree.map(lambda a: a[winner], b.actions)
    action = jax.tree.map(lambda n, o: jnp.where(new, n, o), chosen, state.action)
    return winner.astype(jnp.int32), action, new


# ------------------------------------------------------------------------------------------ the executor

def drive_to(pose, point, backwards, slow: bool | jax.Array, p: DeliberationParams, robot: RobotParams):
    """(v, ω) towards a world ``point``: turn ``turn_gain`` · α, speed min(c*, d / ``brake_s``) · max(0, cos α)
    (c* · max(0, cos α) unless ``slow``); backwards, α is measured from the rear and the speed is negative."""
    alpha, d = bearing(pose, point)
    alpha = jnp.where(backwards, wrap(alpha - jnp.pi), alpha)
    speed = jnp.where(slow, jnp.minimum(robot.max_wheel_speed, d / p.brake_s), robot.max_wheel_speed)
    v = speed * jnp.maximum(0.0, jnp.cos(alpha))
    return jnp.where(backwards, -v, v), p.turn_gain * alpha


def execute(state: DeliberationState, points, valid, obs: Observation, p: DeliberationParams, robot: RobotParams):
    """One tick of the enabled schema: (its next action and waypoint, (v, ω))."""
    pose = jnp.asarray(obs.pose, jnp.float32)
    action, i = state.action, state.waypoint
    # servo at the checkpoint
    servo_v, servo_w = drive_to(pose, world_point(pose, obs.target), False, True, p, robot)
    servo_done = jnp.asarray(obs.final) & (obs.target[1] < p.stop_within)
    # follow path: pass waypoints within ``waypoint``
    _, d = bearing(pose, action.path[jnp.minimum(i, 1)])
    i = jnp.where((action.schema == PATH) & (d < p.waypoint), i + 1, i)
    path_v, path_w = drive_to(pose, action.path[jnp.minimum(i, 1)], action.backwards, i >= 1, p, robot)
    path_done = i >= 2
    schema = action.schema
    v = jnp.select([schema == SERVO, schema == PATH], [servo_v, path_v], 0.0)
    w = jnp.select([schema == SERVO, schema == PATH], [servo_w, path_w], 0.0)
    # collision detection: stop before what is within ``halt`` of the body on the side it drives to, or in the
    # corridor it sweeps within ``halt`` + one tick's travel
    way = jnp.where(action.backwards, -1.0, 1.0)[None] * points
    gap = jnp.sqrt(jnp.sum(jnp.square(way), axis=1)) - robot.radius
    reach = p.halt + jnp.abs(v) * robot.avoid_period
    danger = jnp.any(valid & (way[:, 0] > 0.0) & (gap < p.halt)) | jnp.any(
        in_the_way(way, valid, robot.radius, p.margin, reach))
    moving = (schema == SERVO) | (schema == PATH)
    turn = moving & danger & (jnp.abs(w) >= p.turn_gain * FACING)  # still to face its way: turn on the spot
    ends = ((schema == SERVO) & servo_done) | ((schema == PATH) & path_done) | (moving & danger & ~turn)
    v, w = jnp.where(ends | turn, 0.0, v), jnp.where(ends, 0.0, w)
    following = jnp.select([ends, schema == STOP], [STOP, IDLE], schema)  # stop hands over to idle
    return action._replace(schema=jnp.int32(following)), i, (v, w)


def tick(state: DeliberationState, obs: Observation, angles, p: DeliberationParams, robot: RobotParams):
    """Sense, deliberate if it is time (and, below ``full``, if the executor is idle or its schema has run
    ``max_s``), execute: (state, (v, ω))."""
    sensors = ring(robot, p.sensors)
    memory, points, valid = sense(state.memory, obs, angles, radius=robot.radius, range_m=sensors.range_m,
                                  merge=p.merge, memory_s=p.memory_s, through=p.see_through,
                                  nearer=p.avoid == "nearer")
    t = jnp.asarray(obs.t, jnp.float32)
    time = t >= state.due - 1e-3
    if p.level != "full":
        time = time & ((state.action.schema == IDLE) | (t - state.since >= p.max_s - 1e-3))
    ruling, action, new = deliberate(state, points, valid, obs, p, robot.radius)
    ruling = jnp.where(time, ruling, state.ruling)
    new = time & new
    action = jax.tree.map(lambda n, o: jnp.where(time, n, o), action, state.action)
    state = DeliberationState(
        memory, action, jnp.where(new, 0, state.waypoint), jnp.where(new, t, state.since), ruling,
        jnp.where(time, t + p.period, state.due).astype(jnp.float32),
        state.cycle + (time & new).astype(jnp.int32),
        jnp.where(ruling == WAIT, jnp.where(state.ruling == WAIT, state.waiting_since, t), jnp.inf).astype(jnp.float32))
    action, waypoint, command = execute(state, points, valid, obs, p, robot)
    return state._replace(action=action, waypoint=waypoint), command


@partial(jax.jit, static_argnames=("p", "robot"))
def step(state: DeliberationState, obs: Observation, angles, *, p: DeliberationParams, robot: RobotParams):
    """One tick as wheel speeds."""
    state, (v, w) = tick(state, obs, angles, p, robot)
    return state, wheels(v, w, robot)


def build(params: DeliberationParams, ekm=None, cfg=None, robot: RobotParams = KHEPERA,
          spec: str = "deliberation") -> Controller:
    """Reactive deliberation on ``robot`` (it drives no EKM: ``ekm`` and ``cfg`` are None)."""
    return on_ring("deliberation", spec, params, init, step, robot)
