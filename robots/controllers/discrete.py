"""What the discrete-response architectures share (:mod:`~robots.controllers.subsumption`,
:mod:`~robots.controllers.damn`, :mod:`~robots.controllers.deliberation`): a response as a forward speed and a
turn rate, the IR returns as points in the robot's frame, the corridor the body sweeps ahead, and where a
point lies from the robot.

Arkin (ch. 3.3, §3.4.3) calls an encoding *discrete* when a behaviour chooses among "a prespecified set of
possible responses"; here every such response is a pair (v, ω) — forward speed (m/s) and turn rate (rad/s,
+ = left) — turned into wheel speeds by :func:`wheels`, the one map from (v, ω) to the differential drive.

**What they sense** (:func:`sense`): the IR hits of this tick and those remembered in the world frame
(:mod:`~robots.controllers.memory`, as Samba and the extended fields keep them), and the nearest surface
point of each declared moving obstacle — the long ring's rays are 30° apart, so a box corner between two of
them is seen only when it touches the body; the memory keeps what a ray saw a moment ago. Brooks's robots
kept no such map ("the world is its own best model"); here every architecture of a comparison sees through
the same memory, so the comparison weighs how they *respond*, not what they see. Command fusion's Braitenberg
vehicle reads the same memory through its sensors' sectors (:func:`as_readings`).
"""

from __future__ import annotations

import jax.numpy as jnp

from ekm.angles import wrap
from robots.controllers import memory as mem
from robots.controllers.base import beyond_the_goal
from robots.params import KHEPERA, RobotParams


def wheels(v, omega, robot: RobotParams = KHEPERA):
    """Wheel speeds ``(2,)`` (m/s, left then right) of forward speed ``v`` (m/s) and turn rate ``omega`` (rad/s):
    ``v ∓ ω b / 2`` with b the wheel base; when a wheel would exceed c*, both are scaled down together, so the
    response keeps its curvature."""
    half = 0.5 * robot.wheel_base * jnp.asarray(omega, jnp.float32)
    pair = jnp.stack([v - half, v + half]).astype(jnp.float32)
    peak = jnp.max(jnp.abs(pair))
    return pair * jnp.minimum(1.0, robot.max_wheel_speed / jnp.maximum(peak, 1e-12))


def in_the_way(points, seen, radius: float, margin: float, reach: float):
    """Which ``points`` ``(m, 2)`` (robot frame) lie in the corridor the body sweeps driving straight on: ahead
    of the centre, within ``radius + reach`` of it along x, and within ``radius + margin`` of the centre line.
    A jamb 4 cm to the side of an 8 cm doorway's centre line is not in a 2.5 cm robot's way with a 0.5 cm margin."""
    x, y = points[:, 0], points[:, 1]
    return seen & (x > 0.0) & (x <= radius + reach) & (jnp.abs(y) < radius + margin)


def free_ahead(points, valid, radius: float, clearance: float):
    """How far (m) the body drives straight on (along +x of the robot frame) before it comes within ``clearance``
    of one of the valid ``points`` ``(n, 2)``: inf when it never does, 0 when one is that close already."""
    x, y = points[:, 0], points[:, 1]
    half = radius + clearance
    across = valid & (jnp.abs(y) < half) & (x > 0.0)
    reach = x - jnp.sqrt(jnp.maximum(half ** 2 - y ** 2, 0.0))
    return jnp.min(jnp.where(across, jnp.maximum(reach, 0.0), jnp.inf))


def rotate(points, angle):
    """``points`` ``(n, 2)`` in a frame turned by ``angle`` (rad, + = left): what lies at ``angle`` is then ahead."""
    c, s = jnp.cos(angle), jnp.sin(angle)
    return jnp.stack([c * points[:, 0] + s * points[:, 1], -s * points[:, 0] + c * points[:, 1]], axis=-1)


def bearing(pose, point):
    """Where the world point ``point`` ``(2,)`` lies from a robot at ``pose`` (x, y, θ): (α, d), α in rad
    (+ = left of the heading), d in m — the u_p of ch. 4.1."""
    delta = jnp.asarray(point, jnp.float32) - pose[:2]
    return wrap(jnp.arctan2(delta[1], delta[0]) - pose[2]), jnp.sqrt(jnp.sum(jnp.square(delta)))


def world_point(pose, target):
    """The world position ``(2,)`` of a point at u_p = (α, d) from a robot at ``pose`` (the inverse of
    :func:`bearing`)."""
    phi = pose[2] + target[0]
    return pose[:2] + target[1] * jnp.stack([jnp.cos(phi), jnp.sin(phi)])


def sense(memory: mem.Memory, obs, angles, *, radius: float, range_m: float, merge: float, memory_s: float,
          through: float | None = None, nearer: bool = False):
    """The memory after this tick's IR (returns on a declared mover left to its marker) and every obstacle point
    in the robot's frame: ``(K + k, 2)`` points (the K remembered, then the nearest surface point of each of the
    k declared movers) and their mask — with ``nearer``, remembered points beyond the goal left out
    (:func:`~robots.controllers.base.beyond_the_goal`; they stay remembered). A ray forgets a remembered point it
    passes within ``through`` of (m; ``merge`` when None: :func:`robots.controllers.memory.forget`)."""
    pose = jnp.asarray(obs.pose, jnp.float32)
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    readings = mem.off_movers(pose, jnp.asarray(obs.ir, jnp.float32), angles, markers, radius=radius)
    memory = mem.update(memory, pose, readings, angles, obs.t, radius=radius, range_m=range_m, merge=merge,
                        forget_after=memory_s, through=through)
    rel = jnp.concatenate([memory.points - pose[:2], markers[:, :2] - pose[:2]], axis=0)
    dist = jnp.sqrt(jnp.sum(jnp.square(rel), axis=1))
    surface = jnp.concatenate([jnp.zeros(memory.points.shape[0], jnp.float32), markers[:, 4]])
    rel = rel * (jnp.maximum(dist - surface, 0.0) / jnp.maximum(dist, 1e-9))[:, None]
    points = rotate(rel, pose[2])
    remembered = jnp.isfinite(memory.seen)
    if nearer:
        remembered = remembered & ~beyond_the_goal(dist[:memory.points.shape[0]] - radius, obs.target, obs.final)
    valid = jnp.concatenate([remembered, jnp.ones(markers.shape[0], bool)])
    return memory, points, valid


def as_readings(points, valid, angles, readings, *, radius: float, within: float = float("inf")):
    """Each sensor's reading ``(m,)`` (m from the body surface, inf: nothing) with the obstacle points ``(K, 2)``
    (robot frame, e.g. :func:`sense`'s; ``valid`` ``(K,)``) read too: a point counts for the sensor whose
    direction ``angles`` ``(m,)`` (rad) is nearest its own, at its distance from the body surface, and each sensor
    reads the nearer of its own ``readings`` ``(m,)`` and its points. Why: a reactive vehicle wired to its
    sensors (ch. 4.4's Braitenberg type 3C) answers a wall end in the blind angle between two of them only
    when it is sensed again, usually at contact; its sectors of the memory answer it as the body swings past."""
    alpha = jnp.arctan2(points[:, 1], points[:, 0])
    d = jnp.maximum(jnp.sqrt(jnp.sum(jnp.square(points), axis=1)) - radius, 0.0)
    nearest = jnp.argmin(jnp.abs(wrap(alpha[:, None] - jnp.asarray(angles, jnp.float32)[None, :])), axis=1)
    mine = (nearest[:, None] == jnp.arange(len(angles))[None, :]) & (valid & (d <= within))[:, None]  # (K, m)
    remembered = jnp.min(jnp.where(mine, d[:, None], jnp.inf), axis=0)
    return jnp.minimum(jnp.where(jnp.isfinite(readings), readings, jnp.inf), remembered)


def way_out(obs, radius: float, within: float, lane: float = float("inf")):
    """The declared mover closing on the robot within ``within`` (body to body) whose line passes within ``lane``
    of the body (its track, straight on, meets the robot where it stands), if any, and the way out of its line:
    (whether one does, unit world direction ``(2,)`` across the nearest such mover's line on the robot's side —
    its left when the robot is on the line). Why ``lane``: a mover closing on a line that passes the body clear
    (one circling the robot's goal) is no threat, and running from it carried the robot into its next pass."""
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    if markers.shape[0] == 0:
        return jnp.bool_(False), jnp.zeros(2, jnp.float32)
    pose = jnp.asarray(obs.pose, jnp.float32)
    rel = pose[None, :2] - markers[:, :2]  # from each mover to the robot
    dist = jnp.sqrt(jnp.sum(jnp.square(rel), axis=1))
    u = markers[:, 2:4] / jnp.maximum(jnp.linalg.norm(markers[:, 2:4], axis=1, keepdims=True), 1e-9)
    across = rel - jnp.sum(rel * u, axis=1, keepdims=True) * u  # from each mover's line to the robot
    beside = jnp.linalg.norm(across, axis=1) - markers[:, 4] - radius
    closing = jnp.sum(rel * markers[:, 2:4], axis=1) > 0.0
    threat = (dist - markers[:, 4] - radius < within) & closing & (beside < lane)
    nearest = jnp.argmin(jnp.where(threat, dist, jnp.inf))
    on_line = jnp.linalg.norm(across[nearest]) < 1e-6
    out = jnp.where(on_line, jnp.stack([-u[nearest, 1], u[nearest, 0]]), across[nearest])
    return jnp.any(threat), out / jnp.maximum(jnp.linalg.norm(out), 1e-9)
