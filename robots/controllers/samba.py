"""Samba (Riekki 1999, ch. 3, Fig. 16): object markers, Goto and Avoid action maps, an MAV composite and an
arbiter that sends the heaviest action — driven by the planner's checkpoints like the EKM architectures.

Every 0.128 s tick, :func:`maps` (pure; :func:`step` is it jitted, plus the wheels):

1. **Object markers** (§3.3.1) are bound from what the robot senses and what the world declares. IR returns
   are obstacle points, kept in the world frame and seen again from wherever the robot is
   (:mod:`~robots.controllers.memory`: Riekki's egocentric markers "update the location of the object also
   on the basis of the robot's ego-motion"); a return that lies on a declared moving obstacle is bound to
   that obstacle's marker instead (``obs.markers``: position, velocity and radius). IR sees nothing
   beyond 0.2 m from the centre (the long ring), so undeclared obstacles are known only that close. A ray
   forgets a remembered point only when it passes within ``see_through`` (5 mm, the points' radius) of it: with
   the 1 cm of ``merge`` a ray grazing a pillar forgot the edge it had seen and the robot drove into the pillar
   (issue 35; measured in docs/reproduce/every-kind.md).
2. **The task marker** (§3.3.2) is the planner's current checkpoint, ``obs.target`` (α, d). At the final
   checkpoint of a moving goal it carries the goal's velocity (``obs.target_velocity``): the goal is a
   point IR cannot see, so its position and velocity come from the observation.
3. **Goto map** of the task marker (:mod:`~robots.controllers.actionmaps`): OSA by default, a point for a
   fixed checkpoint (Riekki's GotoLoc, ch. 5.1); a moving goal is a point enlarged by the robot's radius —
   the body must come over it, which is the runner's capture (centre within 25 mm). A fixed checkpoint adds
   a time constraint (§3.3.2: "not before …"): speeds above d / ``brake_s`` are filtered out (§3.2.8, a
   filter on an action parameter), so the heaviest speed falls with the distance d and, within s_1 ·
   ``brake_s`` (0.02 m/s × 0.2 s = 4 mm) of the goal, no action is left: the arbiter sends zero, which the
   runner sees as the stop within its 5 mm. (An intermediate checkpoint counts as reached at 5 mm, before
   that; the braking only slows the last 3 cm.)
4. **Avoid map** of every obstacle marker by the separate procedure of §3.2.6: the exact time to collision
   of the robot's disc, grown by ``clearance``, with each object under each action — moving objects with
   their velocities; then **filtered** by time to collision (Fig. 30): actions that would collide only
   after ``avoid_ttc`` s are not inhibited, so an obstacle far along an action does not close it.
5. **Composite** = MAV(Goto, filtered Avoid) (§3.2.7, Fig. 15): an action is positive when the checkpoint
   would be reached before any obstacle. (After ``squeeze_s`` with no action, in a gap, the maps are made with a
   smaller clearance, ``squeeze``: :func:`maps`.)
6. **Arbiter** (§3.5): the heaviest action, with hysteresis — the actions within ``keep`` of the last
   action's direction *in the world* count their time shorter by the fraction ``tie`` (with the exponential
   weight curve, w^(1/(1 + tie))), so a jump to another direction needs a clearly better action. When the
   checkpoint lies straight behind an obstacle, left and right tie, and as the robot turns, the grid's
   directions move under the tie: without hysteresis the winner flips side tick after tick and the robot
   turns on the spot, losing time (``tests/robots/controllers/test_samba.py`` has such a world). The chosen direction is refined
   between its neighbours by a parabola through their weights (the grid is 5° coarse, which misses a
   checkpoint 20 cm ahead by up to 9 mm). No positive action: the robot stops (§3.1: "only positive weights
   cause actions to be performed").

**The wheels.** The action (direction, speed) reaches the differential drive through
:func:`~robots.controllers.base.velocity_to_wheels`: turn towards the direction at 4× the heading error while
driving forward at the velocity's component along the heading (none if it points backwards). What this
loses against Riekki's holonomic players, who turned and dashed within one 0.1 s cycle: an action is a
velocity the robot reaches only *after turning*; it cannot step sideways or back away while facing an
obstacle (a sideways action is a turn on the spot first, ~0.5 s for a half turn), and during the turn it
moves along its old heading, which the maps never weighed as the action. The arbiter therefore limits the
speed it hands over so that this straight-ahead motion is itself not inhibited on the composite map
(:func:`forward_speed`): the robot turns on the spot rather than drive into what it turns away from.

Measured choices (rejected settings with numbers) are in ``docs/reproduce/samba.md``.
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
from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, sensor_angles, velocity_to_wheels
from robots.params import KHEPERA, RobotParams

@dataclass(frozen=True)
class SambaParams:
    """Parameters of Samba; one set for every world (``docs/reproduce/samba.md``)."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm; ch. 6.2.2) or short",
                                                   "choices": ("short", "long")})
    goto: str = field(default="osa", metadata={"help": "Goto maps by OSA (projection, §3.2.4) or MSA (relaxation, "
                                                       "Eq. 3.1)", "choices": ("osa", "msa")})
    directions: int = field(default=72, metadata={"help": "directions of the velocity maps (5° apart)"})
    speeds: int = field(default=8, metadata={"help": "speeds of the velocity maps, evenly up to c*"})
    full_s: float = field(default=am.FULL_S, metadata={"help": "weight curve: full weight up to this time to "
                                                               "collision, s (Fig. 17)"})
    tau_s: float = field(default=am.TAU_S, metadata={"help": "weight curve: exponential fall's time constant, s"})
    avoid_ttc: float = field(default=0.5, metadata={"help": "filter: Avoid actions colliding later than this are "
                                                            "removed, s (Fig. 30: 0.5)"})
    clearance: float = field(default=0.01, metadata={"help": "m added to the robot's radius in the Avoid maps"})
    brake_s: float = field(default=0.2, metadata={"help": "fixed checkpoint: speeds above distance / brake_s "
                                                          "are filtered, s"})
    tie: float = field(default=0.1, metadata={"help": "arbiter hysteresis: actions near the last one's direction "
                                                      "count their time shorter by this fraction"})
    keep: float = field(default=0.2, metadata={"help": "arbiter hysteresis: rad either side of the last action's "
                                                         "direction that count as near it"})
    refine: bool = field(default=True, metadata={"help": "arbiter: refine the chosen direction between its "
                                                         "neighbours (parabola through their weights)"})
    guard: bool = field(default=True, metadata={"help": "arbiter: slow the straight-ahead motion of a turn to what "
                                                        "the composite map does not inhibit"})
    closer: bool = field(default=True, metadata={"help": "arbiter: with no positive action, take the collision-free "
                                                         "action that closes on the task marker fastest"})
    propagation: float = field(default=0.15, metadata={"help": "goto=msa: propagation factor p of Eq. 3.1"})
    passes: int = field(default=8, metadata={"help": "goto=msa: passes of Eq. 3.1"})
    memory_points: int = mem.option("memory_points", 128)
    memory_s: float = mem.option("memory_s", 30.0)
    merge: float = mem.option("merge", 0.01)
    see_through: float = mem.option("see_through", 0.005, why="the points' radius, merge / 2, as the fields'")
    squeeze: float = field(default=0.003, metadata={"help": "m added to the robot's radius instead of clearance once "
                                                           "clearance has left no action for squeeze_s (>= clearance: "
                                                           "never)"})
    squeeze_s: float = field(default=2.0, metadata={"help": "s without an action at clearance before the maps are "
                                                            "made at squeeze"})
    escape_s: float = field(default=1.5, metadata={"help": "a declared mover that would hit the robot standing where "
                                                           "it is within this many s: it drives straight ahead or back "
                                                           "out of the mover's way (0: never), s"})

    def __post_init__(self):
        for name in ("tau_s", "avoid_ttc", "brake_s", "memory_s", "merge", "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if min(self.full_s, self.clearance, self.squeeze, self.squeeze_s) < 0 or not 0 <= self.tie < 1 \
                or not 0 <= self.propagation <= 1:
            raise ValueError("full_s, clearance, squeeze and squeeze_s must be >= 0, tie in [0, 1) and propagation "
                             "in [0, 1]")
        if self.directions < 4 or self.speeds < 1 or self.passes < 0 or self.memory_points < 1:
            raise ValueError("directions >= 4, speeds >= 1, passes >= 0 and memory_points >= 1 are needed")

    def grid(self, robot: RobotParams = KHEPERA) -> am.VelocityGrid:
        """The velocity maps' actions: ``directions`` × ``speeds`` up to the robot's c*."""
        return am.VelocityGrid(self.directions, self.speeds, robot.max_wheel_speed)


class SambaState(NamedTuple):
    """What Samba carries between ticks: the remembered IR obstacle points (stationary object markers), the
    world direction of the last action sent (NaN before the first), for the arbiter's hysteresis, and since when
    (s) the maps at ``clearance`` have had no action (NaN: they had one last tick), for the squeeze."""

    memory: mem.Memory
    heading: jax.Array
    stuck_since: jax.Array


class Tick(NamedTuple):
    """One tick of Samba (:func:`maps`): the state after it, the maps ``(n_dir, n_speed)`` — Goto, the filtered
    Avoid, their MAV composite — the unfiltered times to collision, the chosen action (indices ``i, j``, its
    direction in the robot frame and speed) and ``go`` (False: no positive action, the robot stops). The
    obstacle markers ``objects`` ``(n, 5)`` are (x, y, vx, vy, radius) in the robot frame, ``valid`` ``(n,)``."""

    state: SambaState
    goto: jax.Array
    avoid: jax.Array
    composite: jax.Array
    times: jax.Array
    i: jax.Array
    j: jax.Array
    direction: jax.Array
    speed: jax.Array
    go: jax.Array
    objects: jax.Array
    valid: jax.Array


@cache
def init(p: SambaParams) -> SambaState:
    return SambaState(mem.empty(p.memory_points), jnp.asarray(jnp.nan, jnp.float32), jnp.asarray(jnp.nan, jnp.float32))


def bind(state: SambaState, obs: Observation, p: SambaParams, robot: RobotParams):
    """Object markers (step 1 of the module docstring): the memory after this tick's IR returns (those on a
    declared mover left out) and every obstacle marker in the robot frame, ``(n, 5)`` and ``valid`` ``(n,)``."""
    sensors = robot.long_range if p.sensors == "long" else robot.short_range
    angles = jnp.asarray(sensor_angles(sensors))
    pose = jnp.asarray(obs.pose, jnp.float32)
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    ir = jnp.asarray(obs.ir, jnp.float32)
    readings = mem.off_movers(pose, ir, angles, markers, radius=robot.radius)
    memory = mem.update(state.memory, pose, readings, angles, obs.t, radius=robot.radius, range_m=sensors.range_m,
                        merge=p.merge, forget_after=p.memory_s, through=p.see_through)
    objects, valid = esc.object_markers(memory.points, jnp.isfinite(memory.seen), markers, pose)
    return memory, objects, valid


def goto_map(obs: Observation, p: SambaParams, robot: RobotParams):
    """The Goto map of the task marker (step 3): OSA (or MSA) for the checkpoint, a moving goal enlarged by the
    robot's radius, and a fixed checkpoint's speeds above d / ``brake_s`` filtered out."""
    grid = p.grid(robot)
    alpha, d = obs.target[0], obs.target[1]
    pos = d * jnp.stack([jnp.cos(alpha), jnp.sin(alpha)])
    vel = esc.to_robot(jnp.asarray(obs.target_velocity, jnp.float32), obs.pose[2])
    moving = jnp.asarray(obs.final) & (jnp.sum(vel * vel) > 0)
    if p.goto == "osa":
        goto = am.osa(pos, vel, grid, radius=jnp.where(moving, robot.radius, 0.0), full=p.full_s, tau=p.tau_s)
    else:
        goto = am.msa(pos, vel, grid, p.propagation, p.passes, full=p.full_s, tau=p.tau_s)
    limit = jnp.where(moving, jnp.inf, d / p.brake_s)
    return am.apply_mask(goto, am.speed_mask(grid, limit))


def arbiter(composite, heading, theta, p: SambaParams, grid: am.VelocityGrid):
    """The action sent (step 6): indices (i, j) of the heaviest action, with hysteresis — the actions within
    ``keep`` of the last action's world direction ``heading`` (NaN: none yet) count their time shorter by the
    fraction ``tie`` (weight w^(1/(1 + tie)) on the exponential curve), so a jump to a far direction needs a
    clearly better action. Returns ``(i, j, go)``; ``go`` False when no action weighs above zero."""
    prev = wrap(heading - theta)
    near = (jnp.abs(wrap(jnp.asarray(grid.angles()) - prev)) <= p.keep + 1e-6) & ~jnp.isnan(heading)
    favoured = jnp.where(near[:, None] & (composite > 0),
                         jnp.power(jnp.maximum(composite, 1e-30), 1.0 / (1.0 + p.tie)), composite)
    i, j = am.best(favoured)
    return i, j, jnp.max(composite) > 0


def forward_speed(direction, speed, composite, grid: am.VelocityGrid):
    """The speed to hand :func:`velocity_to_wheels` so that what the wheels do at once — drive straight ahead at
    speed · cos(direction) while turning — is itself not inhibited: at most the fastest straight-ahead speed
    below the first that the composite map inhibits (negative: an obstacle met before the checkpoint; 0 if even
    the slowest is: the robot turns on the spot)."""
    free = jnp.cumprod(composite[0, :] >= 0)  # direction 0 is straight ahead; slowest first
    v_safe = jnp.max(jnp.where(free > 0, jnp.asarray(grid.speed_values()), 0.0))
    c = jnp.cos(direction)
    return jnp.where(c > 1e-6, jnp.minimum(speed, v_safe / jnp.maximum(c, 1e-6)), speed)


def refine(composite, i, j):
    """Where between its neighbouring directions the chosen action's weight peaks, in bins (−½ … ½): the vertex
    of the parabola through the weights of directions i − 1, i, i + 1 at speed j — the heaviest action's
    direction at finer than the grid's 5°, so that a checkpoint straight ahead is not missed by up to 2.5°
    (a blocked, negative neighbour pushes the vertex away from it)."""
    n = composite.shape[0]
    wl, w0, wr = composite[(i - 1) % n, j], composite[i, j], composite[(i + 1) % n, j]
    curve = wl - 2.0 * w0 + wr
    return jnp.where(curve < 0, jnp.clip(0.5 * (wl - wr) / jnp.where(curve < 0, curve, -1.0), -0.5, 0.5), 0.0)


def collision_times(objects, valid, n_still: int, grow: float, grid: am.VelocityGrid):
    """Time to collision ``(n_dir, n_speed)`` with the first obstacle marker hit under each action: the first
    ``n_still`` markers (the remembered IR points) are stationary — distance along the ray over the speed,
    :func:`actionmaps.ray_distances` — and the rest (declared movers) are timed with their velocities."""
    reach = am.ray_distances(objects[:n_still, :2], objects[:n_still, 4] + grow, grid, valid[:n_still])
    still = reach[:, None] / jnp.asarray(grid.speed_values())[None, :]
    movers = am.collision_times(objects[n_still:, :2], objects[n_still:, 2:4], objects[n_still:, 4] + grow, grid,
                                valid[n_still:])
    return jnp.minimum(still, movers)


def closer_when_stuck(i, j, go, times, obs: Observation, p: SambaParams, grid: am.VelocityGrid):
    """When no action weighs above zero (``go`` False), the action free of collision for ``avoid_ttc`` that closes
    on the task marker fastest, if one closes on it at all: Samba never stands still while an action that hits
    nothing brings it closer. (With a moving goal the Goto map gives only the actions that intercept it weight
    (Riekki Fig. 23); when an obstacle inhibits those, nothing positive is left, and a robot standing beside a
    post watched its target leave.) Closing speed: the action's velocity along the direction to the marker,
    less the marker's own speed away; a fixed checkpoint keeps the Goto map's speed limit (d / ``brake_s``), so
    at the goal, where no speed is left, the robot still stops. Returns ``(i, j, go)``."""
    alpha = obs.target[0]
    vel = esc.to_robot(jnp.asarray(obs.target_velocity, jnp.float32), obs.pose[2])
    away = vel[0] * jnp.cos(alpha) + vel[1] * jnp.sin(alpha)
    angles, speeds = jnp.asarray(grid.angles()), jnp.asarray(grid.speed_values())
    closing = speeds[None, :] * jnp.cos(angles[:, None] - alpha) - away  # (n_dir, n_speed)
    moving = jnp.asarray(obs.final) & (jnp.sum(vel * vel) > 0)
    slow_enough = speeds[None, :] <= jnp.where(moving, jnp.inf, obs.target[1] / p.brake_s)  # the Goto map's own limit
    score = jnp.where((times > p.avoid_ttc) & (closing > 1e-3) & slow_enough, closing, -jnp.inf)
    k = jnp.argmax(score)
    use = ~go & jnp.isfinite(score.reshape(-1)[k])
    return jnp.where(use, k // score.shape[1], i), jnp.where(use, k % score.shape[1], j), go | use


def choose(goto, times, heading, theta, obs: Observation, p: SambaParams, grid: am.VelocityGrid):
    """Steps 4–6 on the times to collision ``times``: the filtered Avoid map, the composite, and the arbiter's
    action ``(i, j)`` with ``go`` (what it sends) and ``positive`` (the action weighs above zero)."""
    avoid = am.filter_times(am.avoid(times, p.full_s, p.tau_s), times, p.avoid_ttc)
    composite = am.mav(goto, avoid)
    i, j, go = arbiter(composite, heading, theta, p, grid)
    positive = go
    if p.closer:
        i, j, go = closer_when_stuck(i, j, go, times, obs, p, grid)
    return avoid, composite, i, j, go, positive


def in_a_gap(points, valid, direction, length: float, half_width: float):
    """Whether remembered ``points`` ``(n, 2)`` (robot frame, where ``valid``) lie on both sides of the way along
    ``direction`` (rad), from ``length`` behind the robot to twice ``length`` ahead, nearer each other across the way
    than ``2 half_width`` (m): the nearest on the left at l, on the right at r from the line, l + r < 2 half_width —
    the narrow place of a gap, not a wall the robot would slide along. The width, not each side's distance: a robot
    off a slot's centre line (or a point read a few millimetres into a wall) has one side beyond ``half_width``."""
    e = jnp.stack([jnp.cos(direction), jnp.sin(direction)])
    along = points @ e
    lateral = e[0] * points[:, 1] - e[1] * points[:, 0]
    beside = valid & (along >= -length) & (along <= 2.0 * length)
    left = jnp.min(jnp.where(beside & (lateral > 0), lateral, jnp.inf))
    right = jnp.min(jnp.where(beside & (lateral < 0), -lateral, jnp.inf))
    return left + right < 2.0 * half_width


def maps(state: SambaState, obs: Observation, p: SambaParams, robot: RobotParams = KHEPERA) -> Tick:
    """Samba's maps and choice for one tick (the module docstring's steps 1–6); pure, so a recorded
    ``(state, obs)`` gives the very maps the run used (:mod:`evaluation.actionmap_plot`).

    When the Avoid map at ``clearance`` has left no action to send for ``squeeze_s``, and the maps made at
    ``squeeze`` send the robot a body's length (twice its radius) or more before any contact between remembered
    points on both sides, nearer each other than the body and two clearances (:func:`in_a_gap`) — through a gap,
    not closer to a wall or along it — those maps drive it (an extension, issue 35) until the wide ones have an
    action again. Why: a robot in a gap of a pillar forest barely wider than its body plus twice the clearance had
    every way ahead closed by the points of both pillars and stood until the time limit; squeezing at once, or
    towards a shut door, drove robots into walls (``docs/reproduce/every-kind.md``)."""
    grid = p.grid(robot)
    memory, objects, valid = bind(state, obs, p, robot)
    goto = goto_map(obs, p, robot)
    theta = jnp.asarray(obs.pose[2], jnp.float32)
    times = collision_times(objects, valid, p.memory_points, robot.radius + p.clearance, grid)
    avoid, composite, i, j, go, positive = choose(goto, times, state.heading, theta, obs, p, grid)
    t = jnp.asarray(obs.t, jnp.float32)
    stuck_since = jnp.where(go, jnp.nan, jnp.where(jnp.isnan(state.stuck_since), t, state.stuck_since))
    if p.squeeze < p.clearance:
        chosen = (times, avoid, composite, i, j, go, positive)

        def squeezed(_):
            """The maps at ``squeeze`` where they send the robot through a gap; else the wide ones."""
            tight = collision_times(objects, valid, p.memory_points, robot.radius + p.squeeze, grid)
            narrow = choose(goto, tight, state.heading, theta, obs, p, grid)
            _, _, i2, j2, go2, _ = narrow
            free = tight[i2, j2] * jnp.asarray(grid.speed_values())[j2] >= 2.0 * robot.radius
            gap = in_a_gap(objects[:p.memory_points, :2], valid[:p.memory_points], jnp.asarray(grid.angles())[i2],
                           robot.radius, robot.radius + p.clearance)
            return jax.tree.map(lambda a, b: jnp.where(go2 & free & gap, b, a), chosen, (tight, *narrow))

        # the second maps only when the wide ones have had no action for squeeze_s (not every tick)
        times, avoid, composite, i, j, go, positive = jax.lax.cond(
            ~go & (t - stuck_since >= p.squeeze_s), squeezed, lambda _: chosen, None)
    direction = jnp.asarray(grid.angles())[i]
    if p.refine:
        direction = direction + jnp.where(positive, refine(composite, i, j), 0.0) * grid.step_angle
    speed = jnp.asarray(grid.speed_values())[j]
    heading = jnp.where(go, wrap(theta + direction), state.heading)
    if p.guard:
        speed = forward_speed(direction, speed, composite, grid)
    return Tick(SambaState(memory, heading, stuck_since), goto, avoid, composite, times, i, j, direction, speed, go,
                objects, valid)


@partial(jax.jit, static_argnames=("p", "robot"))
def step(state: SambaState, obs: Observation, *, p: SambaParams, robot: RobotParams = KHEPERA):
    """One tick: :func:`maps`, then the chosen (direction, speed) as wheel speeds (:func:`velocity_to_wheels`),
    or zero when no action weighs above zero."""
    tick = maps(state, obs, p, robot)
    wheels = jnp.where(tick.go, velocity_to_wheels(tick.direction, tick.speed, robot), 0.0)
    if p.escape_s > 0:
        wheels = escape(wheels, tick, p, robot)
    return tick.state, wheels


def escape(wheels, tick: Tick, p: SambaParams, robot: RobotParams = KHEPERA):
    """The wheel command when a declared mover would hit the robot where it stands within ``escape_s``: the
    straight motion that puts the first contact off the longest (:mod:`~robots.controllers.escape`, an extension,
    issue 35; its times straight ahead and back are the Avoid map's own)."""
    grid = p.grid(robot)
    t_stand = esc.standing_time(tick.objects, tick.valid, p.memory_points, robot.radius + p.clearance)
    straight = jnp.stack([tick.times[0], tick.times[grid.directions // 2]])  # θ = 0 and θ = π
    return esc.escape(wheels, t_stand, straight, grid, p.escape_s)


def build(params: SambaParams, ekm=None, cfg=None, robot: RobotParams = KHEPERA, spec: str = "samba") -> Controller:
    """Samba on ``robot`` (it drives no EKM: ``ekm`` and ``cfg`` are ignored)."""
    sensors = robot.long_range if params.sensors == "long" else robot.short_range
    return Controller(name="samba", spec=spec, sensors=sensors, init=partial(init, params),
                      step=partial(step, p=params, robot=robot), params=params, robot=robot)
