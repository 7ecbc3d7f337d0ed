"""DAMN, the Distributed Architecture for Mobile Navigation (Rosenblatt 1995; Arkin, *Behavior-Based
Robotics*, §3.4.3 and §4.5.5): behaviours vote over a fixed set of candidate turns and, separately, of
speeds; two independent winner-take-all arbiters choose one of each.

**The candidates** (Arkin: "a predefined set of discrete motor responses"; Rosenblatt's steering set
{hard-left, soft-left, straight-ahead, soft-right, hard-right}):

- turns: ``turns`` (24) headings φ_k evenly around the robot (15° apart; φ = 0 straight ahead), each
  enacted as the turn rate ω_k = clip(``turn_gain`` · φ_k, ±``turn_max``) — with the defaults 0, ±1.05,
  ±2.09 and ±3 rad/s: straight ahead, soft, medium and hard left and right. A car's DAMN votes over
  curvatures; this robot turns on the spot, so a heading behind it is a candidate too;
- speeds v_j: 0 and ``speeds`` − 1 more halving down from c*: 0, 0.01, 0.02, 0.04, 0.08, 0.16 m/s with the
  defaults.

The command is the pair of winners (v_j, ω_k) (:func:`~robots.controllers.discrete.wheels`): a zero speed
with a non-zero turn turns on the spot.

**The behaviours and their votes** (each in [−1, 1], weighted by the behaviour's ``*_weight``):

- **avoid** (obstacle points: the IR memory and the declared movers, :func:`~robots.controllers.discrete.sense`):
  heading k gets −(1 − min(1, f_k / ``look``)), f_k the free distance the body would drive along φ_k before
  coming within ``clearance`` of a point (:func:`~robots.controllers.discrete.free_ahead`) — with ``avoid=nearer``
  (an extension, issue 35) the heading nearest the checkpoint's direction looks only as far as the checkpoint,
  min(``look``, d), and at the goal the points beyond it are left out: nothing beyond the checkpoint
  blocks the way to it (a checkpoint 5 cm behind the robot at a corridor's bend, the bend's wall 9 cm behind,
  held the way to it closed and the robot stood); speed j gets
  −min(1, (v_j ``brake_s`` − f_0) / (v_j ``brake_s``)) when driving straight on at v_j for ``brake_s``
  would pass the free distance f_0 straight ahead (0 otherwise). A declared mover is also projected
  along its velocity: heading k (driven at c*) and speed j (straight on) get −(1 − τ / ``mover_s``) when
  the bodies would come within ``clearance`` at τ ≤ ``mover_s`` — standing in a mover's way too;
- **go to checkpoint** (u_p = (α, d)): heading k gets 1 − |α − φ_k| / π; speed j gets 1 − |v_j − v*| / c*
  with v* = min(c*, d / ``brake_s``) · max(0, cos α) — zero at the goal (within ``stop_within``) and
  while it lies beside or behind;
- **keep heading**: heading k gets 1 − |θ + φ_k − ψ| / π, ψ the world heading chosen last tick (Rosenblatt's
  smoothing behaviour: a change of course needs more votes than staying on it).

**The arbiters**: heading = argmax_k Σ weight · vote, speed = argmax_j Σ weight · vote, independently
(Arkin Table 4.7: "multiple winner-take-all arbiters"); ties go to the first candidate (the lower speed).

Parameters were chosen on generated worlds (tuning seeds), never on the named ones
(``docs/reproduce/discrete.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, avoid_option, on_ring, ring
from ekm.angles import wrap
from robots.controllers.discrete import free_ahead, rotate, sense, wheels
from robots.params import KHEPERA, RobotParams

@dataclass(frozen=True)
class DamnParams:
    """The candidate sets, the behaviours' distances (m), times (s) and weights."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm) or short "
                                                           "(8 Khepera sensors, 5 cm)", "choices": ("short", "long")})
    turns: int = field(default=24, metadata={"help": "heading candidates, evenly around the robot"})
    turn_gain: float = field(default=4.0, metadata={"help": "rad/s of turn per rad of a heading candidate"})
    turn_max: float = field(default=3.0, metadata={"help": "rad/s of the hardest turns"})
    speeds: int = field(default=6, metadata={"help": "speed candidates: 0, then halving down from c*"})
    look: float = field(default=0.12, metadata={"help": "avoid: m along each heading that it checks"})
    clearance: float = field(default=0.01, metadata={"help": "avoid: m from the body surface that blocks a heading"})
    mover_s: float = field(default=1.5, metadata={"help": "avoid: s ahead a declared mover is projected along its "
                                                          "velocity"})
    brake_s: float = field(default=0.5, metadata={"help": "avoid and goto: s of travel a speed must have room for; "
                                                          "goto's speed is d / brake_s"})
    stop_within: float = field(default=0.003, metadata={"help": "goto: m from the goal within which it votes to stop"})
    avoid_weight: float = field(default=3.0, metadata={"help": "weight of avoid's votes"})
    goal_weight: float = field(default=1.0, metadata={"help": "weight of go-to-checkpoint's votes"})
    keep_weight: float = field(default=0.2, metadata={"help": "weight of keep-heading's votes"})
    memory_s: float = mem.option("memory_s", 30.0)
    memory_points: int = mem.option("memory_points", 128)
    merge: float = mem.option("merge", 0.01)
    see_through: float = mem.option("see_through", 0.005, why="the points' radius, merge / 2, as the fields'")
    avoid: str = avoid_option("avoid: all, or nearer (the way to the checkpoint looks only as far as the checkpoint, "
                              "and at the goal no point beyond it counts; an extension)")

    def __post_init__(self):
        for name in ("turn_gain", "turn_max", "look", "mover_s", "brake_s", "stop_within", "memory_s", "merge",
                     "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("clearance", "avoid_weight", "goal_weight", "keep_weight"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        for name, least in (("turns", 4), ("speeds", 2), ("memory_points", 1)):
            if not (isinstance(getattr(self, name), int) and getattr(self, name) >= least):
                raise ValueError(f"{name} must be a whole number >= {least}, got {getattr(self, name)}")

    def headings(self):
        """φ_k ``(turns,)`` rad, from straight behind (−π) round by the right to the left."""
        return (2.0 * jnp.pi * jnp.arange(self.turns, dtype=jnp.float32) / self.turns - jnp.pi).astype(jnp.float32)

    def turn_rates(self):
        """ω_k ``(turns,)`` rad/s, the turn rate that enacts each heading."""
        return jnp.clip(self.turn_gain * self.headings(), -self.turn_max, self.turn_max)

    def speed_set(self, robot: RobotParams = KHEPERA):
        """v_j ``(speeds,)`` m/s: 0, then c* / 2^(speeds − 2), …, c* / 2, c*."""
        halvings = jnp.arange(self.speeds - 2, -1, -1, dtype=jnp.float32)
        return jnp.concatenate([jnp.zeros(1, jnp.float32), robot.max_wheel_speed / 2.0 ** halvings])


class DamnState(NamedTuple):
    """The remembered IR points and the world heading chosen last tick (rad; nan before the first)."""

    memory: mem.Memory
    heading: jax.Array


class Votes(NamedTuple):
    """One tick's votes ``(behaviours, candidates)`` — rows avoid, goto, keep (keep casts no speed votes) —
    their weighted sums and the winners (indices)."""

    turn: jax.Array
    speed: jax.Array
    turn_total: jax.Array
    speed_total: jax.Array
    turn_winner: jax.Array
    speed_winner: jax.Array


@cache
def init(p: DamnParams) -> DamnState:
    return DamnState(mem.empty(p.memory_points), jnp.asarray(jnp.nan, jnp.float32))


def free_along(points, valid, p: DamnParams, radius: float):
    """f_k ``(turns,)``: the free distance along each heading (m; inf when nothing is in the way)."""
    return jax.vmap(lambda phi: free_ahead(rotate(points, phi), valid, radius, p.clearance))(p.headings())


def meets(movers, heading, speed, p: DamnParams, radius: float):
    """When (s) a robot driving at ``speed`` along ``heading`` (robot frame) first comes within ``clearance`` of a
    mover ``movers`` ``(k, 5)`` (robot frame: x, y, vx, vy, radius) moving on at its velocity, within
    ``mover_s`` (inf: never). Eight instants, evenly up to ``mover_s``."""
    tau = p.mover_s * jnp.arange(1, 9, dtype=jnp.float32) / 8
    me = speed * tau[:, None] * jnp.stack([jnp.cos(heading), jnp.sin(heading)])[None, :]
    them = movers[None, :, :2] + tau[:, None, None] * movers[None, :, 2:4]
    gap = jnp.sqrt(jnp.sum(jnp.square(them - me[:, None, :]), axis=-1)) - movers[None, :, 4] - radius
    hit = jnp.any(gap < p.clearance, axis=1)
    return jnp.where(jnp.any(hit), tau[jnp.argmax(hit)], jnp.inf)


def vote(points, valid, target, final, theta, last, p: DamnParams, robot: RobotParams,
         movers=jnp.zeros((0, 5), jnp.float32)) -> Votes:
    """Every behaviour's votes and the two arbiters (the module docstring), for a robot heading ``theta`` (rad,
    world) that chose the world heading ``last`` last tick (nan: none)."""
    phi, v = p.headings(), p.speed_set(robot)
    c = robot.max_wheel_speed
    free = free_along(points, valid, p, robot.radius)
    # avoid
    # with avoid=nearer, nothing beyond the checkpoint blocks the way to it: the heading nearest its direction (both,
    # midway between two) needs room only as far as the checkpoint
    toward = jnp.abs(wrap(phi - target[0])) <= jnp.pi / p.turns
    reach = jnp.where(toward & (p.avoid == "nearer"), jnp.minimum(p.look, target[1]), p.look)
    blocked = -(1.0 - jnp.minimum(free / reach, 1.0))
    travel = v * p.brake_s
    slow_down = -jnp.clip((travel - free_ahead(points, valid, robot.radius, p.clearance)) / jnp.maximum(travel, 1e-9),
                          0.0, 1.0)
    if movers.shape[0]:
        soon = lambda tau: -(1.0 - jnp.minimum(tau / p.mover_s, 1.0))  # noqa: E731
        blocked = jnp.minimum(blocked, soon(jax.vmap(lambda h: meets(movers, h, c, p, robot.radius))(phi)))
        slow_down = jnp.minimum(slow_down, soon(jax.vmap(lambda u: meets(movers, 0.0, u, p, robot.radius))(v)))
    # go to checkpoint
    alpha, d = target[0], target[1]
    aim = 1.0 - jnp.abs(wrap(alpha - phi)) / jnp.pi
    want = jnp.minimum(c, d / p.brake_s) * jnp.maximum(0.0, jnp.cos(alpha))
    want = jnp.where(final & (d < p.stop_within), 0.0, want)
    pace = 1.0 - jnp.abs(v - want) / c
    # keep heading
    keep = jnp.where(jnp.isnan(last), 0.0, 1.0 - jnp.abs(wrap(theta + phi - last)) / jnp.pi)

    turn = jnp.stack([blocked, aim, keep])
    speed = jnp.stack([slow_down, pace, jnp.zeros_like(pace)])
    weights = jnp.asarray([p.avoid_weight, p.goal_weight, p.keep_weight], jnp.float32)[:, None]
    turn_total, speed_total = jnp.sum(weights * turn, axis=0), jnp.sum(weights * speed, axis=0)
    return Votes(turn, speed, turn_total, speed_total, jnp.argmax(turn_total), jnp.argmax(speed_total))


def votes(state: DamnState, obs: Observation, angles, p: DamnParams, robot: RobotParams):
    """The state after this tick's sensing and the tick's :class:`Votes`."""
    sensors = ring(robot, p.sensors)
    memory, points, valid = sense(state.memory, obs, angles, radius=robot.radius, range_m=sensors.range_m,
                                  merge=p.merge, memory_s=p.memory_s, through=p.see_through,
                                  nearer=p.avoid == "nearer")
    pose = jnp.asarray(obs.pose, jnp.float32)
    theta = pose[2]
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    movers = jnp.concatenate([rotate(markers[:, :2] - pose[:2], theta), rotate(markers[:, 2:4], theta), markers[:, 4:]],
                             axis=1)
    tick = vote(points, valid, obs.target, jnp.asarray(obs.final), theta, state.heading, p, robot, movers)
    return DamnState(memory, wrap(theta + p.headings()[tick.turn_winner]).astype(jnp.float32)), tick


@partial(jax.jit, static_argnames=("p", "robot"))
def step(state: DamnState, obs: Observation, angles, *, p: DamnParams, robot: RobotParams):
    """One tick: votes, arbiters, and the winning (speed, turn) as wheel speeds."""
    state, tick = votes(state, obs, angles, p, robot)
    return state, wheels(p.speed_set(robot)[tick.speed_winner], p.turn_rates()[tick.turn_winner], robot)


def build(params: DamnParams, ekm=None, cfg=None, robot: RobotParams = KHEPERA, spec: str = "damn") -> Controller:
    """DAMN on ``robot`` (it drives no EKM: ``ekm`` and ``cfg`` are None)."""
    return on_ring("damn", spec, params, init, step, robot)
