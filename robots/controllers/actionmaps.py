"""Action maps (Riekki 1999, ch. 3.2): velocity maps over (direction, speed), how they are made, filtered
and combined. Pure ``jnp`` functions over whole maps (no loop over actions); :mod:`~robots.controllers.samba`
builds the architecture from them.

**The map.** A velocity map (§3.2.1) gives every action — a velocity (direction θ_i, speed s_j) of the
robot, in the robot frame (0 = ahead, + = left) — a weight: ``(n_dir, n_speed)`` arrays on a
:class:`VelocityGrid` (default 72 directions × 8 speeds up to c* = 0.16 m/s). Index i is the direction and j
the speed, as in Eq. 3.1. Goto maps weigh in [0, 1], Avoid maps in [−1, 0] (§3.2.6).

**The weight curve** (Fig. 17, Fig. 46) turns a time to collision into a weight: full weight up to
``full`` s, then falling. Riekki's is soccer-scale — full up to 0.1 s, "very low" beyond 3 s (Fig. 49) —
while this robot's times run 3–30 s (0.16 m/s across a 1.2 m arena and round obstacles), where his curve
would give weights that underflow into ties. :func:`weight` rescales it to the robot in two ways: the full
weight lasts one control period, 0.128 s (Riekki's 0.1 s is one period of his 10 Hz system), and the fall
is an exponential ``exp(−(t − full)/tau)`` with ``tau`` = 10 s instead of about 1 s, so an arena-crossing
30 s still weighs 0.05 and 300 s 1e−13 (float32 holds it). Because the curve is exponential, a ratio of
weights is a difference of times, w₂/w₁ = exp(−Δt/tau), and a power of a weight scales its time:
w^(1/(1 + f)) is the weight of t/(1 + f) (the arbiter's hysteresis in :mod:`~robots.controllers.samba`).

**Goto maps.** Two methods (§3.2.2–3.2.4):

- :func:`msa` — *Many Satisfying Actions*: every action that collides with the object gets the weight of
  its collision time (for a moving object, found by shifting a point along its trajectory, Fig. 18), and
  the others are filled by the relaxation of Eq. 3.1 (:func:`relax`, propagation factor p, a number of
  passes; Fig. 19);
- :func:`osa` — *One Satisfying Action*: the optimal action (full speed to the earliest collision point)
  and every other action weighted by projecting it onto the optimal path, t = d_opt / (s cos δ) (Fig. 21);
  a circular object is enlarged by the robot's radius and the actions in its *object sector* are timed to
  the enlarged object's edge, the projecting sectors reach 90° past the sector's edges (Fig. 24, 25); for
  a moving object the actions turning past the optimal direction towards the object get zero (Fig. 23).

**Avoid maps** are negated Goto maps (:func:`negate`) or, by a separate procedure (§3.2.6), the exact time
to collision of the robot's disc with the object's under each action, −weight(t), and zero for actions that
never collide (:func:`collision_times`, :func:`avoid`): only actions that collide are inhibited, like
Riekki's AvoidOpp maps (ch. 5.1, "calculating weights only for the actions in the object sector"). For
stationary objects the time is a distance along each direction over the speed (:func:`ray_distances`),
n_speed times cheaper — what keeps a map of 128 remembered IR points cheap enough for every tick.

**Combining and filtering** (§3.2.7–3.2.8): :func:`mav` keeps for every action the weight of greatest
magnitude with its sign (an obstacle reached at the same time as the target wins the tie); filtering sets
to zero the actions meeting a condition — a time-to-collision threshold (:func:`filter_times`, Fig. 28, 30),
a sector (:func:`sector_mask`, Fig. 31), a speed limit (:func:`speed_mask`) or any mask (:func:`apply_mask`,
Fig. 47).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from ekm.angles import wrap

#: The weight curve's defaults (see the module docstring): full weight for one 0.128 s control period, then an
#: exponential fall with a 10 s time constant.
FULL_S = 0.128
TAU_S = 10.0


@dataclass(frozen=True)
class VelocityGrid:
    """The actions of a velocity map: ``directions`` evenly round the circle, θ_i = 2πi/n wrapped to (−π, π]
    (θ_0 = 0, straight ahead), and ``speeds`` evenly up to ``max_speed``, s_j = c*(j + 1)/n (no zero speed:
    standing still is no action; the arbiter stops when no action weighs above zero)."""

    directions: int = 72
    speeds: int = 8
    max_speed: float = 0.16

    def __post_init__(self):
        if self.directions < 4 or self.speeds < 1 or not self.max_speed > 0:
            raise ValueError(f"a velocity grid needs >= 4 directions, >= 1 speed and max_speed > 0, got {self}")

    @property
    def shape(self) -> tuple[int, int]:
        return (self.directions, self.speeds)

    @property
    def step_angle(self) -> float:
        """Δθ between neighbouring directions (rad)."""
        return 2.0 * math.pi / self.directions

    @property
    def step_speed(self) -> float:
        return self.max_speed / self.speeds

    def angles(self) -> np.ndarray:
        """θ_i ``(n_dir,)`` in (−π, π]."""
        a = self.step_angle * np.arange(self.directions)
        return wrap(a).astype(np.float32)

    def speed_values(self) -> np.ndarray:
        """s_j ``(n_speed,)``."""
        return (self.step_speed * np.arange(1, self.speeds + 1)).astype(np.float32)

    def velocities(self) -> np.ndarray:
        """Every action as a velocity vector ``(n_dir, n_speed, 2)`` in the robot frame (m/s)."""
        a, s = self.angles()[:, None], self.speed_values()[None, :]
        return np.stack([s * np.cos(a), s * np.sin(a)], axis=-1).astype(np.float32)

    def direction_index(self, alpha):
        """The index of the direction nearest ``alpha`` (rad)."""
        return jnp.mod(jnp.round(alpha / self.step_angle).astype(jnp.int32), self.directions)


# ---------------------------------------------------------------------------------------------- weights

def weight(t, full: float = FULL_S, tau: float = TAU_S):
    """The weight curve (Fig. 17, rescaled to this robot; module docstring): 1 for a time to collision
    ``t`` ≤ ``full`` s, ``exp(−(t − full)/tau)`` after, 0 for ``t = inf`` (no collision)."""
    t = jnp.asarray(t)
    return jnp.where(jnp.isfinite(t), jnp.exp(-jnp.maximum(t - full, 0.0) / tau), 0.0)


# ---------------------------------------------------------------------------------------- Eq. 3.1 (MSA)

def relax(w, p: float = 0.15, passes: int = 8, fixed=None):
    """Propagate ``w`` ``(n_dir, n_speed)`` by the relaxation formula Eq. 3.1, ``passes`` times:

    w_ij ← (1 − p) w_ij + p max(w_ij, w_i+1,j, w_i−1,j, w_i,j+1, w_i,j−1)

    Directions wrap round the circle; at the slowest and fastest speed the missing neighbour is left out.
    Because w_ij itself is in the max, a weight only rises (Riekki: "weights are adjusted only upwards"),
    and an action at least as heavy as its neighbours keeps its weight. A satisfying action next to a
    heavier one (the slower actions towards a stationary object, next to faster ones) would still rise;
    ``fixed`` ``(n_dir, n_speed)`` bool pins such actions at their weight — the intent of §3.2.3, "to
    preserve the weights of the satisfying actions" (:func:`msa` passes its satisfying actions).
    """
    w = jnp.asarray(w)
    keep = jnp.zeros(w.shape, bool) if fixed is None else jnp.asarray(fixed, bool)

    def one(_, w):
        up, down = jnp.roll(w, -1, axis=0), jnp.roll(w, 1, axis=0)
        faster = jnp.concatenate([w[:, 1:], w[:, -1:]], axis=1)
        slower = jnp.concatenate([w[:, :1], w[:, :-1]], axis=1)
        top = jnp.maximum(jnp.maximum(jnp.maximum(w, up), jnp.maximum(down, faster)), slower)
        return jnp.where(keep, w, (1.0 - p) * w + p * top)

    return jax.lax.fori_loop(0, passes, one, w)


def satisfying_times(position, velocity, grid: VelocityGrid, samples: int = 256, horizon: float = 120.0):
    """Collision times ``(n_dir, n_speed)`` of the satisfying actions of the MSA method (Fig. 18), ``inf``
    elsewhere: a point is shifted along the object's trajectory l(t) = position + velocity·t (robot frame,
    m and m/s) at ``samples`` times from the earliest a full-speed robot could meet it to ``horizon`` s
    (geometrically spaced); each needs the velocity l(t)/t, which falls in one (direction, speed) cell —
    that cell gets the shortest such time. For a stationary object every speed towards it is satisfying.
    """
    p, u = jnp.asarray(position, jnp.float32), jnp.asarray(velocity, jnp.float32)
    dist = jnp.linalg.norm(p)
    t_lo = jnp.maximum(dist / (grid.max_speed + jnp.linalg.norm(u)), 1e-3) * 0.5
    t = t_lo * jnp.exp(jnp.linspace(0.0, 1.0, samples) * jnp.log(jnp.maximum(horizon / t_lo, 1.0 + 1e-6)))
    here = p[None, :] + u[None, :] * t[:, None]  # (K, 2)
    need = here / t[:, None]  # robot velocity that meets the point at t
    speed = jnp.linalg.norm(need, axis=-1)
    i = grid.direction_index(jnp.arctan2(need[:, 1], need[:, 0]))
    j = jnp.round(speed / grid.step_speed).astype(jnp.int32) - 1
    ok = (j >= 0) & (j < grid.speeds)
    # exact times for the stationary case: the cell's own speed, not the sample's
    tt = jnp.where(jnp.linalg.norm(u) > 0, t, dist / (grid.step_speed * (jnp.clip(j, 0, grid.speeds - 1) + 1)))
    out = jnp.full(grid.shape, jnp.inf, jnp.float32)
    return out.at[jnp.where(ok, i, 0), jnp.where(ok, j, 0)].min(jnp.where(ok, tt, jnp.inf))


def msa(position, velocity, grid: VelocityGrid, p: float = 0.15, passes: int = 8, full: float = FULL_S,
        tau: float = TAU_S):
    """A Goto map by the MSA method (§3.2.3): :func:`satisfying_times` through the weight curve, then
    :func:`relax` with the satisfying actions pinned. Objects are points (Riekki: the object's size is taken
    into account by tuning p and the passes)."""
    t = satisfying_times(position, velocity, grid)
    sat = jnp.isfinite(t)
    return relax(weight(t, full, tau), p, passes, fixed=sat)


# ------------------------------------------------------------------------------------------------ OSA

def earliest_collision(position, velocity, radius, speed: float):
    """The earliest time t* ≥ 0 at which a robot at ``speed`` can reach the disc of ``radius`` round an object
    at ``position`` moving with ``velocity`` — |p + u t| − ρ = c* t — or ``inf`` if it never can; 0 inside."""
    p, u = jnp.asarray(position), jnp.asarray(velocity)
    a = jnp.dot(u, u) - speed**2
    b = jnp.dot(p, u) - radius * speed
    c = jnp.dot(p, p) - radius**2
    disc = b * b - a * c
    sq = jnp.sqrt(jnp.maximum(disc, 0.0))
    # roots of a t² + 2 b t + c = 0; the smallest non-negative one with |p + u t| ≥ ρ (c* t ≥ 0)
    lin = jnp.where(b < 0, -c / (2.0 * b), jnp.inf)  # a == 0: the object as fast as the robot
    r1 = jnp.where(a != 0, (-b - sq) / jnp.where(a != 0, a, 1.0), lin)
    r2 = jnp.where(a != 0, (-b + sq) / jnp.where(a != 0, a, 1.0), jnp.inf)
    lo, hi = jnp.minimum(r1, r2), jnp.maximum(r1, r2)
    t = jnp.where(lo >= 0, lo, jnp.where(hi >= 0, hi, jnp.inf))
    t = jnp.where((disc < 0) & (a != 0), jnp.inf, t)
    return jnp.where(c <= 0, 0.0, t)


def optimum(position, velocity, radius, speed: float):
    """The optimal action's collision time t*, the collision point C = p + u t* (the enlarged object's centre
    then) and its direction α_opt (§3.2.4)."""
    p, u = jnp.asarray(position, jnp.float32), jnp.asarray(velocity, jnp.float32)
    t = earliest_collision(p, u, radius, speed)
    c = p + u * jnp.where(jnp.isfinite(t), t, 0.0)
    return t, c, jnp.arctan2(c[1], c[0])


def osa_times(position, velocity, grid: VelocityGrid, radius: float = 0.0):
    """Times ``(n_dir, n_speed)`` of the OSA method (§3.2.4, Fig. 21, 24, 25), ``inf`` for actions outside the
    projecting sectors (weight 0).

    The object at ``position`` (robot frame, m) moving with ``velocity`` (m/s), enlarged to ``radius`` (the
    object's radius plus the robot's; 0 for a point), is met at the earliest collision point C (:func:`optimum`),
    at distance |C|. With δ = θ − α_opt and the object sector's half-width β = asin(ρ/|C|):

    - |δ| ≤ β (object sector): t = the ray's distance to the enlarged object's edge / s;
    - β < |δ| ≤ β + 90° (projecting sectors): the action projected onto the nearer sector edge, t =
      √(|C|² − ρ²) / (s cos(|δ| − β));
    - for a moving object, the actions turning past the optimal direction towards the object (beyond the
      sector's edge on the object's side) get ``inf``: they would need more than c* (Fig. 23).
    """
    p, u = jnp.asarray(position, jnp.float32), jnp.asarray(velocity, jnp.float32)
    t_opt, c, a_opt = optimum(p, u, radius, grid.max_speed)
    dc = jnp.maximum(jnp.linalg.norm(c), 1e-9)
    rho = jnp.minimum(radius, dc)
    beta = jnp.arcsin(jnp.clip(rho / dc, 0.0, 1.0))
    theta, s = jnp.asarray(grid.angles())[:, None], jnp.asarray(grid.speed_values())[None, :]
    delta = wrap(theta - a_opt)
    ad = jnp.abs(delta)
    # inside the object sector: distance along the ray to the circle of radius rho round C
    along = dc * jnp.cos(ad) - jnp.sqrt(jnp.maximum(rho**2 - (dc * jnp.sin(ad)) ** 2, 0.0))
    t_in = jnp.maximum(along, 0.0) / s
    tangent = jnp.sqrt(jnp.maximum(dc**2 - rho**2, 0.0))
    proj = jnp.cos(ad - beta)
    t_side = jnp.where(proj > 1e-6, tangent / (s * jnp.maximum(proj, 1e-6)), jnp.inf)
    t = jnp.where(ad <= beta, t_in, jnp.where(ad - beta < 0.5 * jnp.pi, t_side, jnp.inf))
    moving = jnp.dot(u, u) > 0
    a_obj = jnp.arctan2(p[1], p[0])
    side = jnp.sign(wrap(a_obj - a_opt))
    past = moving & (side != 0) & (jnp.sign(delta) == side) & (ad > beta)
    t = jnp.where(past, jnp.inf, t)
    return jnp.where(jnp.isfinite(t_opt), t, jnp.inf)


def osa(position, velocity, grid: VelocityGrid, radius: float = 0.0, full: float = FULL_S, tau: float = TAU_S):
    """A Goto map by the OSA method: :func:`osa_times` through the weight curve."""
    return weight(osa_times(position, velocity, grid, radius), full, tau)


# ------------------------------------------------------------------------------------------ Avoid maps

def collision_times(positions, velocities, radii, grid: VelocityGrid, valid=None):
    """Time to collision ``(n_dir, n_speed)`` under each action with the first of ``k`` objects hit: discs at
    ``positions`` ``(k, 2)`` (robot frame, m) moving with ``velocities`` ``(k, 2)`` (m/s), of ``radii`` ``(k,)``
    — each the object's radius plus the robot's (plus any clearance). ``inf`` where no object is ever hit;
    0 for an action that closes in on an object the robot already touches. ``valid`` ``(k,)`` masks objects.

    Exact for constant velocities: the first root t ≥ 0 of |q + (u − v) t| = ρ (the separate procedure of
    §3.2.6, not a negated Goto map).
    """
    q = jnp.asarray(positions, jnp.float32)[:, None, None, :]  # (k, 1, 1, 2)
    u = jnp.asarray(velocities, jnp.float32)[:, None, None, :]
    rho = jnp.asarray(radii, jnp.float32)[:, None, None]
    w = u - jnp.asarray(grid.velocities())[None]  # (k, n_dir, n_s, 2) relative velocity
    a = jnp.sum(w * w, axis=-1)
    b = jnp.sum(q * w, axis=-1)
    c = jnp.sum(q * q, axis=-1) - rho**2
    disc = b * b - a * c
    t = jnp.where((b < 0) & (disc >= 0) & (a > 0), (-b - jnp.sqrt(jnp.maximum(disc, 0.0))) / jnp.maximum(a, 1e-12),
                  jnp.inf)
    t = jnp.where(c <= 0, jnp.where(b < 0, 0.0, jnp.inf), t)
    if valid is not None:
        t = jnp.where(jnp.asarray(valid)[:, None, None], t, jnp.inf)
    return jnp.min(t, axis=0) if t.shape[0] else jnp.full(grid.shape, jnp.inf, jnp.float32)


def travel_to_touch(along, c):
    """How far the robot's centre travels straight along a direction before a disc of radius ρ round it touches a
    point: ``along`` the point's coordinate along the direction and ``c`` = |q|² − ρ² (q the point from the centre),
    any shape: the nearer root of |q − s e| = ρ, along − √(along² − c); ``inf`` when the line passes it or it is
    behind; 0 when the disc already holds it and the direction closes in on it."""
    disc = along**2 - c
    d = jnp.where((along > 0) & (disc >= 0), along - jnp.sqrt(jnp.maximum(disc, 0.0)), jnp.inf)
    return jnp.where(c <= 0, jnp.where(along > 0, 0.0, jnp.inf), d)


def ray_distances(positions, radii, grid: VelocityGrid, valid=None):
    """For stationary discs at ``positions`` ``(k, 2)`` of ``radii`` ``(k,)``: the distance ``(n_dir,)`` the
    robot travels along each direction before it touches the first one (``inf``: none; 0 when it already
    touches one and the direction closes in on it). A stationary object's time to collision is this distance
    over the speed, so ``ray_distances(...)[:, None] / speeds`` equals :func:`collision_times` with zero
    velocities at 1/n_speed of the cost."""
    q = jnp.asarray(positions, jnp.float32)[:, None, :]  # (k, 1, 2)
    rho = jnp.asarray(radii, jnp.float32)[:, None]
    a = jnp.asarray(grid.angles())
    e = jnp.stack([jnp.cos(a), jnp.sin(a)], axis=-1)[None]  # (1, n_dir, 2)
    d = travel_to_touch(jnp.sum(q * e, axis=-1), jnp.sum(q * q, axis=-1) - rho**2)  # (k, n_dir)
    if valid is not None:
        d = jnp.where(jnp.asarray(valid)[:, None], d, jnp.inf)
    return jnp.min(d, axis=0) if d.shape[0] else jnp.full((grid.directions,), jnp.inf, jnp.float32)


def avoid(times, full: float = FULL_S, tau: float = TAU_S):
    """An Avoid map from collision times (:func:`collision_times`): −weight(t), 0 where nothing is hit."""
    return -weight(times, full, tau)


def negate(goto):
    """An Avoid map made by negating a Goto map (§3.2.6)."""
    return -jnp.asarray(goto)


# -------------------------------------------------------------------------------------- MAV, filtering

def mav(*maps):
    """Combine maps by the Maximum of Absolute Values (§3.2.7): per action, the weight of greatest magnitude
    with its sign. On a tie the negative weight wins (an obstacle hit as soon as the target is reached is
    still hit). ``mav(a, b, c)`` or ``mav(stack)`` for a stack ``(m, n_dir, n_speed)``."""
    w = jnp.stack([jnp.asarray(m) for m in maps]) if len(maps) > 1 else jnp.asarray(maps[0])
    if w.ndim == 2:
        return w
    pos = jnp.max(jnp.maximum(w, 0.0), axis=0)
    neg = jnp.min(jnp.minimum(w, 0.0), axis=0)
    return jnp.where(-neg >= pos, neg, pos)


def filter_map(w, condition):
    """Filtering (§3.2.8): the weights of the actions meeting ``condition`` (bool, the map's shape) set to 0."""
    return jnp.where(condition, 0.0, w)


def filter_times(w, times, longer_than: float):
    """Filter the actions whose time to collision ``times`` exceeds ``longer_than`` s (Fig. 28; Fig. 30's
    0.5 s filter on an Avoid map)."""
    return filter_map(w, jnp.asarray(times) > longer_than)


def sector_mask(grid: VelocityGrid, center, half_width):
    """A filter mask ``(n_dir, n_speed)``: 1 for the directions within ``half_width`` of ``center`` (rad), 0
    elsewhere (Fig. 31: the allowed deviation from the path to a goal)."""
    inside = jnp.abs(wrap(jnp.asarray(grid.angles()) - center)) <= half_width + 1e-6
    return jnp.broadcast_to(inside[:, None], grid.shape).astype(jnp.float32)


def speed_mask(grid: VelocityGrid, max_speed):
    """A filter mask: 1 for the speeds up to ``max_speed`` (m/s), 0 above."""
    ok = jnp.asarray(grid.speed_values()) <= max_speed + 1e-6
    return jnp.broadcast_to(ok[None, :], grid.shape).astype(jnp.float32)


def apply_mask(w, mask):
    """Filter by a mask (§3.2.8, Fig. 47): a zero in ``mask`` removes the action."""
    return jnp.where(jnp.asarray(mask) > 0, w, 0.0)


def best(w):
    """The heaviest action's indices (i, j) — the simplest arbiter (§3.5)."""
    k = jnp.argmax(jnp.ravel(w))
    return k // w.shape[1], k % w.shape[1]
