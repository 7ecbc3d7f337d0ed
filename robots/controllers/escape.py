"""Out of a declared mover's way: the straight motion that puts off a collision the longest (an extension of
Samba and of the extended neural fields, issues 35 and 32).

A controller that chooses a *direction* — Samba's arbiter, the fields' winning neuron — reaches it on a
differential drive only after turning, and a robot turning on the spot in a mover's path is hit however well
it chose. A straight motion, ahead or back, needs no turn, so its time to collision is exact for the wheels.
When a declared mover would hit the robot standing where it is within ``escape_s`` seconds, the robot takes the
straight motion — ahead or back, at any of a velocity grid's speeds — whose first contact with anything
(movers by their velocities, still points along the ray) comes latest, if it comes later than standing's.

Objects are Samba's object markers: rows (x, y, vx, vy, radius) in the robot frame (x ahead, y left; m, m/s),
the first ``n_still`` of them still (their velocities are ignored), the rest declared movers. Pure ``jnp``.
"""

from __future__ import annotations

import jax.numpy as jnp

from robots.controllers import actionmaps as am


def to_robot(v, theta):
    """World-frame vectors ``(..., 2)`` in the frame of a robot heading ``theta`` (rad)."""
    c, s = jnp.cos(theta), jnp.sin(theta)
    return jnp.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1]], axis=-1)


def markers_to_robot(markers, pose):
    """Declared movers ``(k, 5)`` (x, y, vx, vy, radius; world frame) as object markers in the robot frame of
    ``pose`` ``(3,)``."""
    markers = jnp.asarray(markers, jnp.float32).reshape(-1, 5)
    return jnp.concatenate([to_robot(markers[:, :2] - pose[:2], pose[2]), to_robot(markers[:, 2:4], pose[2]),
                            markers[:, 4:5]], axis=1)


def object_markers(points, still, markers, pose):
    """Object markers ``(K + k, 5)`` in the robot frame of ``pose`` ``(3,)`` — the world ``points`` ``(K, 2)`` as still
    ones, then the declared movers ``markers`` ``(k, 5)`` (world frame) — and which count ``(K + k,)``: the points
    where ``still``, every mover."""
    pts = to_robot(points - pose[:2], pose[2])
    moving = markers_to_robot(markers, pose)
    objects = jnp.concatenate([jnp.concatenate([pts, jnp.zeros_like(pts), jnp.zeros_like(pts[:, :1])], axis=1),
                               moving], axis=0)
    return objects, jnp.concatenate([still, jnp.ones(moving.shape[0], bool)])


def standing_time(objects, valid, n_still: int, grow: float):
    """When the first declared mover (rows ``n_still:`` of ``objects`` ``(n, 5)``, where ``valid``) touches the
    robot standing still, its disc grown by ``grow`` (m: the robot's radius plus any clearance); ``inf``: never."""
    zero = am.VelocityGrid(4, 1, 1e-6)  # standing: any action of a vanishing speed
    stand = am.collision_times(objects[n_still:, :2], objects[n_still:, 2:4], objects[n_still:, 4] + grow, zero,
                               valid[n_still:])
    return jnp.min(stand)


def straight_times(objects, valid, n_still: int, grow: float, grid: am.VelocityGrid):
    """Time to the first contact ``(2, n_speed)`` driving straight ahead (row 0) and straight back (row 1) at
    each of ``grid``'s speeds: still objects by their distance along the ray, movers by their velocities."""
    line = am.VelocityGrid(4, grid.speeds, grid.max_speed)  # directions 0, π/2, π, −π/2
    reach = am.ray_distances(objects[:n_still, :2], objects[:n_still, 4] + grow, line, valid[:n_still])
    still = reach[:, None] / jnp.asarray(line.speed_values())[None, :]
    movers = am.collision_times(objects[n_still:, :2], objects[n_still:, 2:4], objects[n_still:, 4] + grow, line,
                                valid[n_still:])
    times = jnp.minimum(still, movers)
    return jnp.stack([times[0], times[2]])


def escape(wheels, t_stand, straight, grid: am.VelocityGrid, escape_s: float):
    """The wheel command ``(2,)`` (m/s): ``wheels`` unless standing would be hit within ``escape_s`` (``t_stand``,
    :func:`standing_time`) and a straight motion of ``straight`` ``(2, n_speed)`` (:func:`straight_times`) is
    hit later — then the one hit latest, both wheels at its speed (negative: back)."""
    best = jnp.argmax(straight)
    t_best = straight.reshape(-1)[best]
    v = jnp.asarray(grid.speed_values())[best % grid.speeds] * jnp.where(best // grid.speeds == 0, 1.0, -1.0)
    threatened = (t_stand < escape_s) & (t_best > t_stand)
    return jnp.where(threatened, jnp.stack([v, v]), wheels)


def out_of_the_way(wheels, points, still, markers, pose, grow: float, max_speed: float, escape_s: float,
                   speeds: int = 8):
    """:func:`escape` for a controller that remembers world ``points`` ``(K, 2)`` (those ``still`` ``(K,)`` count
    along the ray) and sees the declared movers ``markers`` ``(k, 5)`` (world frame) from ``pose`` ``(3,)``: the
    robot's disc grown by ``grow`` (m), straight motions at ``speeds`` speeds evenly up to ``max_speed`` (m/s)."""
    objects, valid = object_markers(points, still, markers, jnp.asarray(pose, jnp.float32))
    grid = am.VelocityGrid(4, speeds, max_speed)
    n = points.shape[0]
    return escape(wheels, standing_time(objects, valid, n, grow), straight_times(objects, valid, n, grow, grid), grid,
                  escape_s)
