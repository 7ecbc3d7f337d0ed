"""IR sensors (robots.sensors, PymunkWorld.ranges/sense): readings against analytic ray distances, the
reading model (noise, resolution, clipping, inf) and the size of the noise."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from robots.params import KHEPERA, LONG_RANGE, SHORT_RANGE
from robots.sensors import ir_readings, sensor_rays
from robots.world import PymunkWorld
from robots.worldfile import parse_world
from robots.worldnames import load_world

R = KHEPERA.radius
TAU = LONG_RANGE.resolution_m


def arena(**extra):
    """1 x 1 m box; walls 1 cm thick, so the inner faces are at 0.005 and 0.995."""
    return parse_world({"name": "box", "size": [1.0, 1.0], "start": [0.2, 0.8, 0.0], "goal": [0.2, 0.2], **extra})


INNER_FACES = [("x", 0.005, 0.0, 1.0), ("x", 0.995, 0.0, 1.0), ("y", 0.005, 0.0, 1.0), ("y", 0.995, 0.0, 1.0)]


def rays(pose, sensors):
    """Rim points and unit directions of each sensor, computed here from first principles."""
    x, y, theta = pose
    phi = theta + np.asarray(sensors.angles)
    u = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    return np.array([x, y]) + R * u, u


def ray_to_faces(p, u, faces):
    """Distance along the ray p + s u to the nearest axis-parallel face (axis, value, lo, hi)."""
    best = np.inf
    for axis, value, lo, hi in faces:
        i, j = (0, 1) if axis == "x" else (1, 0)
        if abs(u[i]) < 1e-12:
            continue
        s = (value - p[i]) / u[i]
        if s >= 0 and lo <= p[j] + s * u[j] <= hi:
            best = min(best, s)
    return best


def ray_to_circle(p, u, centre, radius):
    """Distance along the ray p + s u to the circle's edge (p outside the circle)."""
    m = p - np.asarray(centre)
    b = m @ u
    disc = b * b - (m @ m - radius * radius)
    if disc < 0:
        return np.inf
    s = -b - math.sqrt(disc)
    return s if s >= 0 else np.inf


def expected(distances, sensors):
    d = np.asarray(distances, dtype=float)
    return np.where(d <= sensors.range_m, d, np.inf)


def check_noise_free(sim, sensors, exact):
    """ranges() equals the analytic distances; noise-free readings are within half a resolution of them."""
    exact = expected(exact, sensors)
    np.testing.assert_allclose(sim.ranges(sensors), exact, atol=1e-9)
    readings = sim.sense(sensors, noise=0)
    seen = np.isfinite(exact)
    assert np.array_equal(np.isfinite(readings), seen)
    assert np.all(np.abs(readings[seen] - exact[seen]) <= 0.5 * sensors.resolution_m + 1e-12)
    steps = readings[seen] / sensors.resolution_m
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-9)  # quantised to tau
    return readings


# ------------------------------------------------------------------------ (c) analytic distances

def test_long_range_readings_of_the_arena_walls_at_a_slant():
    pose = (0.85, 0.30, 0.4)
    sim = PymunkWorld(arena(), seed=0)
    sim.place(pose)
    p, u = rays(pose, LONG_RANGE)
    exact = [ray_to_faces(p[k], u[k], INNER_FACES) for k in range(12)]
    readings = check_noise_free(sim, LONG_RANGE, exact)
    assert np.flatnonzero(np.isfinite(readings)).tolist() == [0, 10, 11]  # the right wall, at 0, -60, -30 degrees
    assert readings[0] == pytest.approx(0.13)  # (0.995 - 0.873) / cos 0.4 = 0.1319 -> 0.13


def test_long_range_readings_of_a_circle_obstacle():
    pose = (0.38, 0.47, 0.4)
    sim = PymunkWorld(arena(unforeseen=[{"type": "circle", "center": [0.5, 0.5], "radius": 0.05}]), seed=0)
    sim.place(pose)
    p, u = rays(pose, LONG_RANGE)
    exact = [min(ray_to_circle(p[k], u[k], (0.5, 0.5), 0.05), ray_to_faces(p[k], u[k], INNER_FACES))
             for k in range(12)]
    readings = check_noise_free(sim, LONG_RANGE, exact)
    assert np.flatnonzero(np.isfinite(readings)).tolist() == [0, 11]  # the disc, ahead and at -30 degrees


def test_readings_inside_the_concave_trap():
    world = load_world("concave-obstacle")  # U: inner faces y = 0.275, y = 0.525, x = 0.75; open towards -x
    faces = [("y", 0.275, 0.45, 0.75), ("y", 0.525, 0.45, 0.75), ("x", 0.75, 0.275, 0.525), ("x", 0.005, 0, 0.8)]
    pose = (0.65, 0.40, 0.0)
    sim = PymunkWorld(world, seed=0)
    sim.place(pose)
    p, u = rays(pose, LONG_RANGE)
    readings = check_noise_free(sim, LONG_RANGE, [ray_to_faces(p[k], u[k], faces) for k in range(12)])
    assert readings[0] == pytest.approx(0.075)  # the bottom of the U, straight ahead
    assert readings[6] == np.inf  # looking back out of the mouth


def test_a_thin_segment_obstacle_is_seen_at_its_distance():
    sim = PymunkWorld(arena(unforeseen=[{"type": "segment", "from": [0.6, 0.2], "to": [0.6, 0.8]}]), seed=0)
    sim.place((0.5, 0.5, 0.0))
    assert sim.ranges()[0] == pytest.approx(0.6 - 0.5 - R, abs=1e-12)


def test_sensors_see_a_moving_obstacle_where_it_is_now():
    world = load_world("three-rooms-moving")  # robot-sized disc on a 12 s anticlockwise circle
    mover = world.moving[0]
    sim = PymunkWorld(world, seed=0)
    pose = (0.55, 0.24, 0.0)
    sim.place(pose)
    p, u = rays(pose, LONG_RANGE)
    front = [0, 1, 2, 3, 9, 10, 11]  # the sensors behind see the wall at x = 0.4
    seen = []
    for _ in range(3):
        centre = mover.at(sim.t).center
        exact = expected([ray_to_circle(p[k], u[k], centre, mover.shape.radius) for k in front], LONG_RANGE)
        np.testing.assert_allclose(sim.ranges()[front], exact, atol=1e-9)
        seen.append([front[i] for i in np.flatnonzero(np.isfinite(exact))])
        sim.step([0.0, 0.0], period=KHEPERA.target_period)
    assert seen == [[0], [1], [1]]  # straight ahead at first, then up to the left (the +30 degree sensor)


def test_short_range_sensors_of_a_robot_3cm_from_a_wall():
    pose = (0.94, 0.5, 0.0)  # rim 3 cm from the right wall's face
    sim = PymunkWorld(arena(), seed=0)
    sim.place(pose)
    p, u = rays(pose, SHORT_RANGE)
    readings = check_noise_free(sim, SHORT_RANGE, [ray_to_faces(p[k], u[k], INNER_FACES) for k in range(8)])
    front = [SHORT_RANGE.angles.index(a) for a in SHORT_RANGE.angles if abs(a) < 0.2]
    assert np.all(readings[front] == pytest.approx(0.03))  # the two front sensors (±10 degrees): 3.05 cm
    assert np.isinf(np.delete(readings, front)).all()  # ±45 degrees already reads 5.3 cm: beyond 5 cm


def test_the_robot_never_sees_its_own_body():
    sim = PymunkWorld(parse_world({"name": "big", "size": [2.0, 2.0], "start": [1.0, 1.0, 0.7], "goal": [1.5, 1.5]}),
                      seed=0)
    for sensors in (SHORT_RANGE, LONG_RANGE):
        assert np.isinf(sim.ranges(sensors)).all()
        assert np.isinf(sim.sense(sensors)).all()


def test_a_rim_pressed_into_a_wall_reads_zero():
    sim = PymunkWorld(arena(), seed=0)
    sim.place((0.995 - R + 0.001, 0.5, 0.0))  # 1 mm of overlap
    assert sim.ranges()[0] == 0.0
    assert sim.sense(noise=0)[0] == 0.0


# --------------------------------------------------------------------------------- reading model

def test_reading_model_rounds_to_tau_clips_and_marks_nothing_seen_as_inf():
    d = np.array([0.0123, 0.0126, 0.17, 0.10, np.inf, 0.18, 0.0])
    xi = np.array([0.0, 0.0, 1.0, -11.0, 0.0, 0.0, 3.0])
    np.testing.assert_allclose(ir_readings(d, xi, LONG_RANGE), [0.010, 0.015, 0.175, 0.0, np.inf, np.inf, 0.0])
    jax_readings = np.asarray(ir_readings(jnp.asarray(d), jnp.asarray(xi), LONG_RANGE, xp=jnp))
    np.testing.assert_allclose(jax_readings, ir_readings(d, xi, LONG_RANGE), atol=1e-7)


def test_rays_start_on_the_rim_and_reach_the_range():
    start, end = sensor_rays(np.array([0.2, 0.3, 1.0]), LONG_RANGE)
    np.testing.assert_allclose(np.linalg.norm(start - [0.2, 0.3], axis=1), R)
    np.testing.assert_allclose(np.linalg.norm(end - start, axis=1), LONG_RANGE.range_m)
    np.testing.assert_allclose(start[0] - [0.2, 0.3], R * np.array([math.cos(1.0), math.sin(1.0)]))  # ahead


def test_sensor_noise_is_ten_percent():
    """10 % multiplicative noise (thesis ch. 6.1), measured through the world's own noise stream.

    Readings are quantised to tau = 5 mm, which adds about tau^2 / 12 to their variance (Sheppard's
    correction, accurate when the noise std is at least about tau). So the check uses a distance where the
    noise std (12 mm) is well above tau and far below the 17.5 cm clip, and removes tau^2 / 12 before
    comparing the relative std with 0.10.
    """
    d = 0.12
    sim = PymunkWorld(arena(), seed=11)
    sim.place((0.995 - R - d, 0.5, 0.0))
    assert sim.ranges()[0] == pytest.approx(d)
    front = np.array([sim.sense()[0] for _ in range(4000)])
    assert np.all(np.isfinite(front)) and front.max() < LONG_RANGE.range_m  # no clipping involved
    np.testing.assert_allclose(front / TAU, np.round(front / TAU), atol=1e-9)
    sigma = math.sqrt(front.var(ddof=1) - TAU**2 / 12)
    assert sigma / d == pytest.approx(LONG_RANGE.noise, abs=0.01)
    assert front.mean() == pytest.approx(d, abs=0.001)  # unbiased


def test_hit_points_of_many_poses_equal_one_pose_at_a_time():
    """The runner turns a run's readings into world points in one batched call (RunRecord.hits): the same
    bits as one call a tick, each point radius + reading from the centre along its sensor."""
    from robots.controllers.base import hit_points

    rng = np.random.default_rng(3)
    poses = np.column_stack([rng.uniform(0, 1, 20), rng.uniform(0, 1, 20), rng.uniform(-np.pi, np.pi, 20)])
    readings = rng.uniform(0, LONG_RANGE.range_m, (20, 12))
    readings[rng.random((20, 12)) < 0.4] = np.inf
    pts, seen = hit_points(poses, readings, LONG_RANGE.angles, R)
    assert pts.shape == (20, 12, 2) and seen.shape == (20, 12) and 0 < seen.sum() < seen.size
    for k in range(20):
        one, one_seen = hit_points(poses[k], readings[k], LONG_RANGE.angles, R)
        assert np.array_equal(pts[k], one) and np.array_equal(seen[k], one_seen)
    distance = np.linalg.norm(pts - poses[:, None, :2], axis=-1)
    np.testing.assert_allclose(distance[seen], (R + readings)[seen], rtol=0, atol=1e-12)
    bearing = np.arctan2(*(pts - poses[:, None, :2])[..., ::-1].transpose(2, 0, 1))
    off = (bearing - poses[:, 2:3] - np.asarray(LONG_RANGE.angles) + np.pi) % (2 * np.pi) - np.pi
    np.testing.assert_allclose(off[seen], 0.0, atol=1e-9)
