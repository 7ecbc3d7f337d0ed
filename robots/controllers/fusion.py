"""Command fusion (thesis ch. 4.5, Fig. 1.4a): indirect-EKM target reaching + Braitenberg avoidance.

c = β c_p + (1 − β) c_o (Eq. 4.11): c_p is the indirect map's command towards the current checkpoint
(Eq. 4.5, :func:`ekm.indirect.control`), c_o = Z u_o the type-3C vehicle's (Eq. 4.10,
:mod:`robots.controllers.braitenberg`). The two modules run at their own rates: avoidance every tick
(0.128 s), target reaching every ``period`` (1.024 s in ch. 6.2.1, 0.128 s in ch. 6.2.2) and at once
when the checkpoint changes ("the target reaching module can react immediately to the change of a
checkpoint", Fig. 6.5). Each new module output updates the shared motor state (the last c_p and c_o),
and the fused command is sent whenever it changes; sending an unchanged command changes nothing.

Four readings of ch. 4.4–4.5, chosen by measurement (``docs/reproduce/architectures.md``):

- **β and the stop.** Eq. 4.11 scales target reaching by β even in free space, and the Khepera's
  speed unit (8 mm/s) rounds β c_p to zero 1/β times further from the target than c_p itself: with
  β = 0.5 the robot stops about 5.3 mm from a checkpoint it must reach within 5 mm (ch. 6.2.1). β =
  0.85 keeps it within reach; Z's gains are scaled up to keep (1 − β) Z as strong.
- **When target reaching speaks.** "In the presence of obstacles, additional control signal may be
  sent as and when obstacles are detected" (ch. 4.5): with ``refresh="sensed"`` (the default) target
  reaching also recomputes c_p at every tick on which an obstacle is sensed, because the avoidance has
  moved the robot off the arc that c_p was computed for; in free space it keeps its 1.024 s period.
  ``refresh="clock"`` keeps it strictly periodic.
- **Which way Z faces.** Ch. 4.4's vehicle guards the robot's front, but the indirect map drives backward
  onto a target close behind (c_p,left + c_p,right < 0), and a reversing Khepera meets what is behind it
  with two rear sensors whose weights are Z's small positive ones: it backs into it. With
  ``facing="travel"`` (the default, an extension) the avoidance while c_p reverses is the same vehicle
  turned round (:func:`robots.controllers.braitenberg.z_matrix` with ``backward=True``); ``"front"`` is
  ch. 4.4's. The ring is front-heavy: behind, the Khepera has only its rear pair, 20° off the way back, and
  a reversing robot meets a wall on its flank in the 75° between them and the side sensors. So the turned
  vehicle counts as forward-facing every sensor within ``back_cone`` (100°) of the way back, the side ones
  included; driving ahead, 60° as in ch. 4.4.
- **What the vehicle reads.** Ch. 4.4's vehicle reads its sensors alone. The Khepera's eight leave blind
  angles — 40° between the front-side pairs, 75° between the sides and the rear pair — and a robot that arcs
  round the end of a thin wall meets it there, unsensed since its front pair lost it. With ``remember=true``
  (the default, an extension) the IR hits are remembered in the world frame as Samba and the discrete
  architectures remember them (:func:`robots.controllers.discrete.sense`, with the declared movers' nearest
  points), and each sensor reads the nearer of its own return and the points in its sector within ``within``
  (2 cm) of the body (:func:`robots.controllers.discrete.as_readings`): Z answers the wall end as the body swings
  past it. Only what is near counts: read at every distance, a corridor's remembered walls fill every sector and
  hold the robot at the first bend.
- **What is in the way.** Ch. 4.4's vehicle answers everything its forward-facing sensors read. In a corridor or
  niche a few centimetres wider than the robot the ±45° pair reads both walls at once: each brakes the robot
  through its large negative weight, the pair stops it short of a goal at a niche's end, and the one that reads
  nearer as the robot swings swings it back, from side to side. With ``lane`` (0, an extension) a forward-facing
  sensor and its mirror that both read a point farther than the robot's radius plus ``lane`` to the side of the
  line of travel — a passage's two walls, (radius + r)|sin φ| off it — are read as nothing
  (:func:`in_the_way`); a wall on one side alone still counts, as the robot may be closing on it, and the ±10° pair
  always does (its points lie within 1.3 cm of the line).

Command fusion drives the polar-chart map by default (:data:`DEFAULT_CHART`): a signed-chart map
reverses onto targets behind (:mod:`ekm.charts`), the polar one only onto those close behind, and a
Khepera's short-range sensors — six ahead, two behind — guard a reversing robot less well than one that
drives ahead, turned Z or not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ekm import indirect
from ekm.config import EKMConfig
from robots.controllers import escape as esc
from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, avoid_option, proximity, readings_to_the_goal
from robots.controllers.braitenberg import FRONT, avoid, z_matrix
from robots.controllers.discrete import as_readings, sense
from robots.params import KHEPERA, RobotParams, SensorSet


@dataclass(frozen=True)
class FusionParams:
    """Parameters of command fusion; the defaults are the thesis's ch. 6.2.1 set-up but ``avoid`` (``nearer``, an
    extension: at the goal nothing beyond it is avoided; ``all`` is ch. 4.5's), ``facing`` (``travel``, an
    extension: Z turned round while target reaching reverses; ``front`` is ch. 4.4's), ``remember`` (true, an
    extension: the sensors also read the remembered IR points in their sectors; false is ch. 4.4's) and ``lane``
    (0, an extension: a passage's two walls are not avoided; 1 or more is ch. 4.4's)."""

    sensors: str = field(default="short", metadata={"help": "IR ring: short (8 Khepera sensors, 5 cm) or long "
                                                            "(12 around, 17.5 cm)", "choices": ("short", "long")})
    beta: float = field(default=0.85, metadata={"help": "β of Eq. 4.11, the weight of target reaching"})
    period: float = field(default=1.024, metadata={"help": "target-reaching period in s (1.024 in ch. 6.2.1, "
                                                           "0.128 in ch. 6.2.2)"})
    cross: float = field(default=4.0, metadata={"help": "Z: m/s from a forward sensor to the opposite motor "
                                                        "at full activation (sent as -cross)"})
    same: float = field(default=0.4, metadata={"help": "Z: m/s of the other connections (small)"})
    refresh: str = field(default="sensed", metadata={
        "help": "when target reaching recomputes c_p: clock (every period) or sensed (also every tick while an "
                "obstacle is sensed)", "choices": ("clock", "sensed")})
    avoid: str = avoid_option("which readings the avoidance answers: all (ch. 4.5) or nearer (at the goal, none beyond "
                              "it; an extension)")
    facing: str = field(default="travel", metadata={
        "help": "which way Z's forward-facing sensors face: front (ch. 4.4, always the robot's front) or travel "
                "(the way target reaching drives: the back while the map reverses; an extension)",
        "choices": ("front", "travel")})
    back_cone: float = field(default=100.0, metadata={
        "help": "degrees: with facing=travel, how far from the way back a sensor counts as forward-facing while the "
                "map reverses (the Khepera's rear pair is at 20 degrees, its sides at 95)"})
    remember: bool = field(default=True, metadata={
        "help": "each sensor also reads the remembered IR points (and declared movers) in its sector (an extension; "
                "false: its own return alone, ch. 4.4)"})
    within: float = field(default=0.02, metadata={
        "help": "remember=true: m from the body within which a remembered point is read"})
    lane: float = field(default=0.0, metadata={
        "help": "m: a forward-facing sensor and its mirror that both read walls farther than the robot's radius plus "
                "this to the side of the line of travel (a passage) are not avoided (1 or more: everything read is, "
                "ch. 4.4; an extension)"})
    memory_points: int = mem.option("memory_points", 128, "remember=true")
    memory_s: float = mem.option("memory_s", 30.0, "remember=true")
    merge: float = mem.option("merge", 0.01, "remember=true")
    see_through: float = mem.option("see_through", 0.005, "remember=true", "the points' radius, as Samba's")
    escape_s: float = field(default=2.5, metadata={
        "help": "a declared mover that would hit the robot standing (its body grown by 1 cm) within this many s: it "
                "drives straight ahead or back out of the mover's way, as Samba and the fields do (0: never; an "
                "extension), s"})

    def __post_init__(self):
        if not 0.0 < self.beta <= 1.0:
            raise ValueError(f"beta must be in (0, 1], got {self.beta}")
        if self.cross < 0 or self.same < 0:
            raise ValueError(f"cross and same must be >= 0, got {self.cross}, {self.same}")
        if not 0.0 < self.back_cone <= 180.0:
            raise ValueError(f"back_cone must be in (0, 180] degrees, got {self.back_cone}")
        if not self.lane >= 0:
            raise ValueError(f"lane must be >= 0 (1 or more: off), got {self.lane}")
        if not self.escape_s >= 0:
            raise ValueError(f"escape_s must be >= 0, got {self.escape_s}")
        for name in ("memory_s", "merge", "see_through", "within"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not (isinstance(self.memory_points, int) and self.memory_points >= 1):
            raise ValueError(f"memory_points must be a whole number >= 1, got {self.memory_points}")


#: The chart of the map command fusion drives when no map is given (see the module docstring).
DEFAULT_CHART = "polar"


class FusionState(NamedTuple):
    """The shared motor state: the last target-reaching command, when the next is due, for which checkpoint; and
    the remembered IR points (``remember``)."""

    c_p: jax.Array  # (2,) m/s
    due: jax.Array  # s: time of the next target-reaching update
    target_id: jax.Array  # the checkpoint c_p was computed for
    memory: mem.Memory


@cache
def init(p: FusionParams = FusionParams()) -> FusionState:
    return FusionState(jnp.zeros(2, jnp.float32), jnp.zeros((), jnp.float32), jnp.asarray(-1, jnp.int32),
                       mem.empty(p.memory_points))


#: m the escape grows the body by (``escape_s``): the fields' clearance.
ESCAPE_CLEARANCE = 0.01


@partial(jax.jit, static_argnames=("cfg", "beta", "period", "sensors", "on_sensed", "nearer", "remember", "radius",
                                   "passage", "escape"))
def step(state: FusionState, obs: Observation, ekm, z, *, cfg: EKMConfig, beta: float, period: float,
         sensors: SensorSet, on_sensed: bool = False, nearer: bool = False, remember: tuple | None = None,
         radius: float = KHEPERA.radius, passage: tuple | None = None, escape: tuple | None = None):
    """One tick: refresh c_p if its period is up or the checkpoint changed, c_o from the IR (with ``nearer``, none
    beyond the goal; with ``remember`` = (merge, memory_s, see_through, within), the remembered points too,
    :func:`~robots.controllers.discrete.as_readings`) through ``z`` ``(2, 2, m)`` — ``z[0]`` while c_p drives
    forward, ``z[1]`` while it reverses — and fuse (Eq. 4.11); with ``escape`` = (escape_s, max_speed), out of a
    declared mover's way (:func:`robots.controllers.escape.out_of_the_way`)."""
    refresh = (obs.t >= state.due - 1e-6) | (obs.target_id != state.target_id)
    if on_sensed:
        refresh = refresh | jnp.any(jnp.isfinite(obs.ir))
    c_p = jnp.where(refresh, indirect.control(ekm, obs.target, cfg)[0], state.c_p)
    due = jnp.where(refresh, obs.t + period, state.due)
    reversing = (c_p[0] + c_p[1] < 0.0).astype(jnp.int32)  # z[1]: the vehicle facing backward (``facing``)
    readings, memory = readings_to_the_goal(obs) if nearer else obs.ir, state.memory
    if remember is not None:
        merge, memory_s, through, within = remember
        angles = jnp.asarray(sensors.angles, jnp.float32)
        memory, points, valid = sense(memory, obs, angles, radius=radius, range_m=sensors.range_m, merge=merge,
                                      memory_s=memory_s, through=through, nearer=nearer)
        readings = as_readings(points, valid, angles, jnp.asarray(readings, jnp.float32), radius=radius, within=within)
    if passage is not None:
        lane, front, mirror = passage
        readings = in_the_way(readings, jnp.asarray(sensors.angles, jnp.float32), reversing, radius, lane, front,
                              jnp.asarray(mirror))
    c_o = avoid(z[reversing], proximity(readings, sensors))
    c = beta * c_p + (1.0 - beta) * c_o
    if escape is not None:
        escape_s, max_speed = escape
        still = jnp.isfinite(memory.seen) & ~mem.near_movers(memory.points, obs.markers)
        c = esc.out_of_the_way(c, memory.points, still, obs.markers, obs.pose, radius + ESCAPE_CLEARANCE, max_speed,
                               escape_s)
    return FusionState(c_p, due, jnp.asarray(obs.target_id, jnp.int32), memory), c


def mirrors(angles) -> tuple[int, ...]:
    """The index of the sensor at −φ for each sensor at φ of ``angles`` (rad), its own where there is none."""
    a = np.asarray(angles, dtype=float)
    cost = np.abs(np.sin(0.5 * (a[:, None] + a[None, :]))) + np.abs(np.cos(a[:, None]) - np.cos(a[None, :]))
    return tuple(int(j) for j in np.argmin(cost, axis=1))


def in_the_way(readings, angles, reversing, radius: float, lane: float, front: tuple, mirror):
    """``readings`` ``(m,)`` with those of a passage's walls read as nothing: a forward-facing sensor of Z (within
    ``front[reversing]`` rad of the way it faces; ``front[1]`` None when Z faces the front while reversing too)
    whose point lies farther than ``radius + lane`` from the line of travel — the point a sensor at φ from that way
    reads at r lies (radius + r)|sin φ| to the side — while its mirror sensor (``mirror`` ``(m,)``, :func:`mirrors`)
    reads one so far on the other side. Walls on both sides of a corridor or niche a few centimetres wider than the
    robot are not in its way; read, they brake it through its ±45° sensors and swing it from side to side. A wall on
    one side alone still counts: the robot may be closing on it (``lane``, an extension)."""
    turned = front[1] is not None
    phi = angles - jnp.pi * reversing if turned else angles
    cone = jnp.where(reversing == 1, front[1], front[0]) if turned else front[0]
    ahead = jnp.cos(phi) >= jnp.cos(cone) - 1e-6
    aside = ahead & jnp.isfinite(readings) & ((radius + readings) * jnp.abs(jnp.sin(phi)) > radius + lane)
    return jnp.where(aside & aside[mirror], jnp.inf, readings)


def build(params: FusionParams, ekm, cfg: EKMConfig, robot: RobotParams = KHEPERA, spec: str = "fusion") -> Controller:
    """Command fusion driven by the indirect map ``ekm`` (one trial) on ``robot``."""
    sensors = robot.short_range if params.sensors == "short" else robot.long_range
    robot.substeps(params.period)  # a whole number of physics sub-steps, or ValueError
    ahead = z_matrix(sensors, params.cross, params.same)
    back = (z_matrix(sensors, params.cross, params.same, front=math.radians(params.back_cone), backward=True)
            if params.facing == "travel" else ahead)
    z = jnp.asarray(np.stack([ahead, back]))
    run = partial(step, ekm=ekm, z=z, cfg=cfg, beta=params.beta, period=params.period, sensors=sensors,
                  on_sensed=params.refresh == "sensed", nearer=params.avoid == "nearer",
                  remember=((params.merge, params.memory_s, params.see_through, params.within) if params.remember
                            else None),
                  radius=robot.radius,
                  passage=((params.lane, (FRONT, math.radians(params.back_cone) if params.facing == "travel" else None),
                            mirrors(sensors.angles)) if params.lane < 1.0 else None),
                  escape=(params.escape_s, robot.max_wheel_speed) if params.escape_s > 0 else None)
    return Controller(name="fusion", spec=spec, sensors=sensors, init=partial(init, params), step=run, params=params,
                      robot=robot)
