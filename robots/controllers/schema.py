"""Motor schemas (Arkin, *Behavior-Based Robotics*, ch. 3.3.2 and 4.4): the classic potential-field baseline.

Each schema maps what it perceives to one action vector (direction and magnitude, m/s) in the robot's
frame; the vectors are multiplied by their gains and **summed**, the sum is normalised by clipping its
magnitude to c* (Arkin: "often merely by clipping the magnitude") and driven with
:func:`~robots.controllers.base.velocity_to_wheels` — the one mapping from a holonomic (direction, speed)
to the differential drive that Samba uses too. No field is computed anywhere: each tick only the vectors
at the robot's current position are (Arkin ch. 3.3.2: "the only computation needed is that required to
assess the forces from the robot's current position"). The schemas, as Arkin encodes them (Fig. 4.10):

- **move-to-goal** towards the current checkpoint u_p = (α, d): direction α; magnitude
  ``goal_gain · min(1, d / slow)`` — Arkin's ballistic schema (a fixed gain) far from the checkpoint,
  falling linearly to zero within ``slow`` of it (his *controlled* version), so the robot stops at the
  goal: the move-to-goal speed is below half a Khepera speed unit within ``slow · 4 mm/s / goal_gain``
  of it (0.6 mm with the defaults), well inside the 5 mm that ch. 6.2.1 asks for;
- **avoid-static-obstacle**, once per IR hit (every sensed point is an obstacle of radius 0, placed at
  the reading along its sensor's ray, :func:`~robots.controllers.base.hit_points`): directed from the
  point through the robot's centre, with Arkin's magnitude law written in the gap g between the body
  surface and the point (the reading itself; Arkin's d − R with the robot's radius on the point)::

      0                                  for g > S          (outside the sphere of influence)
      avoid_gain · (S − g) / (S − R)     for R < g <= S     (rising linearly as the obstacle nears)
      margin_gain                        for g <= R         (Arkin's ∞ inside the safety margin)

  with S = ``influence`` and R = ``margin``. Arkin's ∞ becomes a finite ``margin_gain`` that no sum of
  move-to-goal and noise can outweigh, so within the margin the robot moves away first;
- **avoid-static-obstacle for the declared moving obstacles** (``obs.markers``, Samba's object markers):
  the same law from each marker's *current* position, with g the gap between the two bodies (centre
  distance − marker radius − body radius) — Arkin instantiates the schema "differently for either
  environmental obstacles or other robots"; it reacts to where a mover is, not where it will be;
- **avoid-static-obstacle for the lane ahead** (``lane``, an extension): the IR hits are also remembered in the
  world frame (:mod:`~robots.controllers.memory`, as Samba remembers them), and of the remembered points that no
  ray reads this tick, the nearest ahead of the robot within ``lane`` of the strip its body sweeps pushes by the
  same law as a reading there would. The long ring's rays are 30° apart: a doorway's jamb or a pillar the robot
  drives at slips between them and goes unread for the ticks before the contact (traced in
  ``docs/reproduce/every-kind.md``). Only the lane counts, and only its nearest point: every remembered point
  pushing (the same law, summed) holds the robot off narrow doorways and niches;
- **what the body passes pushes it aside, not back** (``beside``, an extension): a sensed point ahead of the robot
  and at least ``beside`` clear of the strip its body sweeps keeps only the sideways part of its push. Radial
  pushes from the two walls of a passage barely wider than the robot cancel across and add up backwards, so the
  robot stood at a niche's mouth for good — the potential fields' known failure between closely spaced
  obstacles (Koren and Borenstein, 1991). What lies in the strip, or behind, pushes straight away as before;
- **noise**: magnitude ``noise_gain``, direction a random compass direction redrawn every
  ``persistence`` s (Arkin's p, the persistence) — his "reactive grease" against local minima. The
  direction is fixed in the world frame (a compass direction, as in Fig. 4.10D), so it does not turn
  with the robot. Its gain falls with move-to-goal's within ``slow`` of the checkpoint (Arkin's
  foraging robots reduce the noise "greatly upon encountering an attractor"), so that it can never hold
  the robot off the goal.

**Randomness and purity.** The noise schema's PRNG key lives in the controller state, seeded from
``seed``; at each redraw the robot's pose (its float32 bits) is folded into the key. A run is therefore
still a pure function of (world, controller, run seed) — same seed, same record — while runs with other
seeds, whose motor noise has moved the robot elsewhere by the second draw, draw other directions.

**The small-vector dead band.** ``velocity_to_wheels`` turns towards the vector's direction at a rate
that does not fall with its length, so a vanishing sum pointing behind would spin the robot on the spot.
A sum shorter than half a Khepera speed unit (4 mm/s, what rounds to a zero wheel speed anyway) is sent
as no motion at all: at the goal, and where the schemas balance exactly, the robot stands still. (Where
they balance, the motor lag carries it a millimetre or two on; the sum then points back, and this robot,
which cannot reverse, turns on the spot: a balance on a convex obstacle straight ahead breaks by
itself, one on a flat obstacle across the way does not — ``docs/reproduce/architectures.md``.)

**The defaults, and why** (SI units: m/s, m, s; the measurements are in ``docs/reproduce/architectures.md``):

- ``goal_gain`` 0.16 m/s: c*, the wheels' top speed — the EKM architectures' largest step, so every
  architecture cruises alike;
- ``slow`` 0.025 m: move-to-goal is linear within 2.5 cm, a gain of 6.4 /s, so one 0.128 s tick closes
  0.82 of the remaining distance: the robot closes on a checkpoint without overshooting it (a gain of
  more than 1/0.128 s would overshoot, more than 2/0.128 s never settle). 5 cm reached as often but
  took longer per run in the rooms: the robot crawls up to every checkpoint;
- ``influence`` S 0.05 m and ``margin`` R 0.01 m from the body surface: the planner puts checkpoints
  2.8 cm from a doorway's wall end, so a wide sphere keeps pushing the robot round them: 8 cm reached as
  often but took much longer (and, with a stronger gain and a wider ``slow``, held it off the
  checkpoints for good); 3 cm leaves too little room to turn at 2 cm a tick and it grazed walls. 5 cm
  is also all the Khepera's short-range ring can see, so both rings feel the same law;
- ``avoid_gain`` G 0.24 m/s = 1.5 × ``goal_gain``: a single point straight ahead balances move-to-goal
  at g* = S − (S − R)/1.5 = 2.3 cm, outside the margin; 0.16 let the short-range ring graze doorway
  edges that only one of its sparse rays sees;
- ``margin_gain`` 1.0 m/s: Arkin's ∞, six times c*, more than move-to-goal and noise together;
- ``marker_gain`` 0.24 m/s: the declared movers get the same law and gain as any sensed point (with
  the long-range ring, 0.16 and 0.32 gave the same outcomes; no run touched the mover);
- ``lane`` 0.01 m beside the body's strip: the best of 0–2 cm on the generated families' tuning seeds; wider
  lanes lose narrow niches (the measurements: ``docs/reproduce/every-kind.md``);
- ``beside`` 0.01 m: the best of 0.2–2 cm on the generated families' tuning seeds (the measurements:
  ``docs/reproduce/every-kind.md``);
- ``noise_gain`` 0.04 m/s (a quarter of move-to-goal) with ``persistence`` 2.048 s (16 ticks):
  Arkin's "small amount of noise"; it frees the robot from a balance on a small obstacle straight across
  its way, but not from the long wall or the U (much more noise gets round the wall in some runs but
  loses runs in the rooms).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from robots.controllers import memory as mem
from robots.controllers.base import (Controller, Observation, avoid_option, beyond_the_goal, on_ring,
                                     readings_to_the_goal, ring, velocity_to_wheels)
from robots.params import KHEPERA, RobotParams


@dataclass(frozen=True)
class SchemaParams:
    """Gains of the motor schemas (m/s at full strength), their distances (m) and the noise's persistence (s).
    The defaults serve every world (``docs/reproduce/architectures.md``)."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm) or short "
                                                           "(8 Khepera sensors, 5 cm)", "choices": ("short", "long")})
    goal_gain: float = field(default=0.16, metadata={
        "help": "move-to-goal: m/s far from the checkpoint (c*, the wheels' top speed)"})
    slow: float = field(default=0.025, metadata={
        "help": "move-to-goal: m from the checkpoint within which its magnitude falls linearly to 0"})
    avoid_gain: float = field(default=0.24, metadata={
        "help": "avoid-static-obstacle: G, m/s per sensed point at the safety margin (falls linearly to 0 at "
                "the sphere of influence)"})
    influence: float = field(default=0.05, metadata={
        "help": "avoid-static-obstacle: S, the sphere of influence, m from the body surface"})
    margin: float = field(default=0.01, metadata={
        "help": "avoid-static-obstacle: R, the safety margin, m from the body surface (Arkin's obstacle radius)"})
    margin_gain: float = field(default=1.0, metadata={
        "help": "avoid-static-obstacle: m/s per point inside the safety margin (Arkin's infinity)"})
    marker_gain: float = field(default=0.24, metadata={
        "help": "avoid the declared moving obstacles: G, m/s at the safety margin (same law, same S and R)"})
    noise_gain: float = field(default=0.04, metadata={"help": "noise: m/s of the random direction"})
    persistence: float = field(default=2.048, metadata={
        "help": "noise: s a random direction persists before the next is drawn (Arkin's p)"})
    seed: int = field(default=0, metadata={"help": "noise: seed of the PRNG key"})
    avoid: str = avoid_option("which readings avoid-static-obstacle answers: all (Arkin) or nearer (at the goal, none "
                              "beyond it; an extension)")
    lane: float = field(default=0.01, metadata={"help": "avoid-static-obstacle also answers the nearest remembered IR "
                                                        "point no ray reads this tick in the lane the body sweeps "
                                                        "ahead, this many m beside it (0: off; an extension)"})
    memory_points: int = mem.option("memory_points", 128)
    memory_s: float = mem.option("memory_s", 30.0)
    merge: float = mem.option("merge", 0.01)
    see_through: float = mem.option("see_through", 0.005, why="the points' radius, merge / 2, as Samba's")
    beside: float = field(default=0.01, metadata={"help": "avoid-static-obstacle: a point ahead that the strip the body "
                                                         "sweeps passes by this many m or more pushes only sideways, "
                                                         "not back (0: every point pushes straight away, Arkin; an "
                                                         "extension)"})

    def __post_init__(self):
        for name in ("goal_gain", "slow", "influence", "persistence", "memory_s", "merge", "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("avoid_gain", "margin", "margin_gain", "marker_gain", "noise_gain", "lane", "beside"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if self.memory_points < 1:
            raise ValueError(f"memory_points must be >= 1, got {self.memory_points}")
        if not self.margin < self.influence:
            raise ValueError(f"margin must be < influence, got {self.margin} >= {self.influence}")


class SchemaState(NamedTuple):
    """The noise schema's state: its PRNG key, its current direction (rad, world frame) and when it is redrawn (s)."""

    key: jax.Array
    heading: jax.Array
    due: jax.Array
    memory: mem.Memory


@cache
def init(p: SchemaParams) -> SchemaState:
    """A fresh state: the first tick draws the first noise direction."""
    return SchemaState(jax.random.PRNGKey(p.seed), jnp.zeros((), jnp.float32), jnp.asarray(-jnp.inf, jnp.float32),
                       mem.empty(p.memory_points))


# ------------------------------------------------------------------------------------------ the schemas

def polar(direction, magnitude):
    """A vector ``(..., 2)`` from its direction (rad) and magnitude."""
    return jnp.stack([magnitude * jnp.cos(direction), magnitude * jnp.sin(direction)], axis=-1)


def move_to_goal(target, p: SchemaParams):
    """Move-to-goal ``(2,)`` m/s, robot frame: towards u_p = (α, d), ``goal_gain · min(1, d / slow)`` long."""
    return polar(target[0], p.goal_gain * jnp.minimum(1.0, target[1] / p.slow))


def repulsion(gap, gain: float, p: SchemaParams):
    """Arkin's avoid-static-obstacle magnitude (m/s) at ``gap`` m from the body surface: 0 beyond S, ``gain ·
    (S − g) / (S − R)`` between, ``margin_gain`` within R; 0 for ``inf`` (nothing sensed)."""
    linear = gain * (p.influence - gap) / (p.influence - p.margin)
    return jnp.where(gap > p.influence, 0.0, jnp.where(gap > p.margin, linear, p.margin_gain))


def avoid_static(readings, angles, p: SchemaParams, radius: float = KHEPERA.radius):
    """Avoid-static-obstacle summed over the IR hits ``(2,)`` m/s, robot frame: each sensed point at ``readings``
    (m from the body surface; ``inf`` = nothing) along its sensor's direction ``angles`` pushes the robot
    straight away from it — or, with ``beside``, only sideways (its backward part dropped) when it lies ahead and
    at least ``radius + beside`` to the side of the line of travel: the body passes it."""
    seen = jnp.isfinite(readings)
    magnitude = jnp.where(seen, repulsion(jnp.where(seen, readings, jnp.inf), p.avoid_gain, p), 0.0)
    push = -polar(angles, magnitude)
    if p.beside > 0:
        reach = jnp.where(seen, readings, 0.0) + radius
        clear = (jnp.cos(angles) > 0) & (jnp.abs(reach * jnp.sin(angles)) >= radius + p.beside)
        push = push.at[:, 0].set(jnp.where(clear, 0.0, push[:, 0]))
    return jnp.sum(push, axis=0)


def avoid_markers(markers, pose, radius: float, p: SchemaParams):
    """Avoid-static-obstacle for the declared moving obstacles ``(2,)`` m/s, robot frame, from their current
    positions: ``markers`` ``(k, 5)`` rows (x, y, vx, vy, r), world frame; the gap is between the two bodies."""
    rel = markers[:, :2] - pose[None, :2]
    dist = jnp.sqrt(jnp.sum(jnp.square(rel), axis=1))
    gap = dist - markers[:, 4] - radius
    direction = jnp.arctan2(rel[:, 1], rel[:, 0]) - pose[2]
    return -jnp.sum(polar(direction, repulsion(gap, p.marker_gain, p)), axis=0)


def noise(state: SchemaState, obs: Observation, p: SchemaParams):
    """The noise schema: the state with the direction redrawn if its persistence is up, and the vector ``(2,)``
    m/s (robot frame), ``noise_gain`` long, its gain falling with move-to-goal's within ``slow`` of the checkpoint."""
    redraw = obs.t >= state.due - 1e-3  # 1 ms: float32 time drifts by microseconds over a run
    key = state.key
    for bits in jax.lax.bitcast_convert_type(jnp.asarray(obs.pose, jnp.float32), jnp.uint32):
        key = jax.random.fold_in(key, bits)
    key, sub = jax.random.split(key)
    heading = jnp.where(redraw, jax.random.uniform(sub, (), jnp.float32, -math.pi, math.pi), state.heading)
    state = SchemaState(jnp.where(redraw, key, state.key), heading,
                        jnp.where(redraw, obs.t + p.persistence, state.due).astype(jnp.float32), state.memory)
    fade = jnp.minimum(1.0, obs.target[1] / p.slow)
    return state, polar(heading - obs.pose[2], p.noise_gain * fade)


class Vectors(NamedTuple):
    """One tick's schema outputs ``(2,)`` each (m/s, robot frame: x ahead, y left) and their sum."""

    goal: jax.Array
    avoid: jax.Array
    markers: jax.Array
    noise: jax.Array
    total: jax.Array


def avoid_lane(memory: mem.Memory, obs: Observation, p: SchemaParams, radius: float):
    """Avoid-static-obstacle for the nearest remembered point in the lane ahead ``(2,)`` m/s, robot frame: of the
    points no ray read this tick (and not on a declared mover), the nearest ahead of the robot within ``lane`` of
    the strip its body sweeps, pushing as a reading there would. The ring's rays are 30° apart: a wall's end the
    robot drives at passes between them, unread, the ticks before the contact."""
    u, valid = mem.egocentric(memory, obs.pose, radius=radius)
    reach = u[:, 1] + radius
    ahead, across = reach * jnp.cos(u[:, 0]), reach * jnp.sin(u[:, 0])
    unread = valid & (memory.seen < obs.t - 1e-3) & ~memory.moving
    inside = unread & (ahead > 0) & (jnp.abs(across) < radius + p.lane)
    if p.avoid == "nearer":
        inside = inside & ~beyond_the_goal(u[:, 1], obs.target, obs.final)
    gap = jnp.where(inside, u[:, 1], jnp.inf)
    k = jnp.argmin(gap)
    return -polar(u[k, 0], jnp.where(jnp.isfinite(gap[k]), repulsion(gap[k], p.avoid_gain, p), 0.0))


def schemas(state: SchemaState, obs: Observation, angles, p: SchemaParams,
            robot: RobotParams = KHEPERA) -> tuple[SchemaState, Vectors]:
    """Every schema's vector for one tick and their sum (Arkin ch. 4.4.2: vector summation); with ``lane`` the
    memory takes this tick's IR hits and ``avoid`` includes the lane's push (:func:`avoid_lane`)."""
    radius = robot.radius
    goal = move_to_goal(obs.target, p)
    avoid = avoid_static(readings_to_the_goal(obs) if p.avoid == "nearer" else obs.ir, angles, p, radius)
    if p.lane > 0:
        memory = mem.update(state.memory, obs.pose, obs.ir, angles, obs.t, radius=radius,
                            range_m=ring(robot, p.sensors).range_m,
                            merge=p.merge, forget_after=p.memory_s, through=p.see_through, markers=obs.markers)
        state = state._replace(memory=memory)
        avoid = avoid + avoid_lane(memory, obs, p, radius)
    markers = avoid_markers(obs.markers, obs.pose, radius, p)
    state, wander = noise(state, obs, p)
    return state, Vectors(goal, avoid, markers, wander, goal + avoid + markers + wander)


def to_wheels(total, robot: RobotParams = KHEPERA):
    """The summed vector ``(2,)`` as wheel speeds: its magnitude clipped to c*, driven by ``velocity_to_wheels``;
    shorter than half a speed unit it is no motion (see the module docstring)."""
    length = jnp.sqrt(jnp.sum(jnp.square(total)))
    moving = length >= 0.5 * robot.speed_unit
    direction = jnp.where(moving, jnp.arctan2(total[1], total[0]), 0.0)
    speed = jnp.where(moving, jnp.minimum(length, robot.max_wheel_speed), 0.0)
    return velocity_to_wheels(direction, speed, robot)


@partial(jax.jit, static_argnames=("p", "robot"))
def step(state: SchemaState, obs: Observation, angles, *, p: SchemaParams, robot: RobotParams):
    """One tick: every schema's vector, summed, clipped to c* and turned into wheel speeds."""
    state, v = schemas(state, obs, angles, p, robot)
    return state, to_wheels(v.total, robot)


def build(params: SchemaParams, ekm=None, cfg=None, robot: RobotParams = KHEPERA, spec: str = "schema") -> Controller:
    """Motor schemas on ``robot`` (they drive no EKM: ``ekm`` and ``cfg`` are None)."""
    return on_ring("schema", spec, params, init, step, robot)
