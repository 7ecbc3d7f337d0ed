"""One robot's body (robots.body.RobotBody) in a bare pymunk space with two robots: each robot's IR sees the
other at the gap between their surfaces and never sees itself, an ``unseen`` category (a ball) is invisible to
the rays, a ``pushes`` shape is neither a collision nor slid against while the other robot is one collision,
each robot's noise comes from its own seed, and bad indices and seeds are refused."""

import dataclasses
import math

import numpy as np
import pymunk
import pytest

from robots.body import MAX_ROBOTS, SLOP, RobotBody
from robots.params import KHEPERA

C = KHEPERA.max_wheel_speed  # 0.16 m/s = 20 speed units of 8 mm/s: sent exactly
QUIET = dataclasses.replace(KHEPERA, actuator_noise=0.0)  # no slip: every path below is worked out by hand
BALL_TYPE, BALL_BIT = 2, 1 << 20  # a ball's collision type and category bit, as robots.soccer.game uses
INF = math.inf


def free_x(n: int, x0: float) -> float:
    """x of a robot at heading 0, started at rest at ``x0``, after ``n`` 16 ms sub-steps at wheel command (C, C)
    without slip: the motor lag gives sub-step j the speed C (1 − e^(−0.8 j)) (dt / τ = 0.016 / 0.02 = 0.8, and
    the law composes across periods), so x = x0 + C dt (n − (1 − e^(−0.8 n)) / (1 − e^(−0.8))); the lag costs
    1 / (1 − e^(−0.8)) = 1.816 sub-steps of travel, 4.6 mm."""
    return x0 + C * 0.016 * (n - (1.0 - math.exp(-0.8 * n)) / (1.0 - math.exp(-0.8)))


class Owner:
    """What a world or a game does round its robots: the space, its clock, and each sub-step drive → step →
    settle for every robot."""

    def __init__(self):
        self.space = pymunk.Space()
        self.space.collision_slop = SLOP
        self.k = 0

    def clock(self) -> float:
        return self.k * 0.016

    def robot(self, pose, index, seed=0, params=QUIET, **kwargs) -> RobotBody:
        r = RobotBody(self.space, self.clock, params, seed, index=index, **kwargs)
        r.place(pose)
        return r

    def ball(self, x, y, category=BALL_BIT) -> pymunk.Body:
        """A table-tennis ball (2.7 g, radius 0.02 m), free to move; no bounce (elasticities 0)."""
        body = pymunk.Body(0.0027, math.inf)
        shape = pymunk.Circle(body, 0.02)
        shape.collision_type, shape.filter = BALL_TYPE, pymunk.ShapeFilter(categories=category)
        body.position = (x, y)
        self.space.add(body, shape)
        return body

    def run(self, robots, commands, periods, noise=True):
        """``periods`` control periods of 0.128 s; slip drawn from each robot's stream, or none (``noise``
        False). Returns each robot's pose after every period ``(periods, len(robots), 3)``."""
        zeros = np.zeros(KHEPERA.noise_shape(KHEPERA.avoid_period))
        out = []
        for _ in range(periods):
            twists = [r.motors(c, None if noise else zeros) for r, c in zip(robots, commands)]
            for j in range(8):
                for r, (v, omega) in zip(robots, twists):
                    r.drive(v[j], omega[j])
                self.space.step(0.016)
                self.k += 1
                for r in robots:
                    r.settle(unsqueeze=False)
            out.append([r.pose for r in robots])
        return np.array(out)


# ------------------------------------------------------------------------------------------------ sensing

@pytest.mark.parametrize("ahead, reading", [
    (0.10, 0.05),  # centres 0.10 apart: 0.10 − 2 × 0.025 = 0.05 m between the surfaces, 10 steps of 5 mm
    (0.1733, 0.125),  # 0.1733 − 0.05 = 0.1233 m = 24.66 τ, read as 25 τ = 0.125 m
])
def test_each_robot_sees_the_other_at_the_gap_between_the_surfaces(ahead, reading):
    world = Owner()
    a = world.robot((0.5, 0.5, 0.0), index=0)
    b = world.robot((0.5 + ahead, 0.5, math.pi / 2), index=1)  # B faces up: A lies to its left (+90°)
    gap = ahead - 0.05
    # Only the ray straight at the other robot meets it: a ray at 30° passes the other's centre at
    # ahead × sin 30° >= 0.05 m, outside its 0.025 m radius. Nothing else is in the space.
    expected_a = [gap] + [INF] * 11  # A's sensor 0 looks ahead (0°)
    expected_b = [INF] * 3 + [gap] + [INF] * 8  # B's sensor 3 looks at +90° (2π · 3 / 12)
    np.testing.assert_allclose(a.ranges(), expected_a, rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.ranges(), expected_b, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(a.sense(noise=0), [reading] + [INF] * 11)  # noise-free, quantised
    np.testing.assert_array_equal(b.sense(noise=0), [INF] * 3 + [reading] + [INF] * 8)


@pytest.mark.parametrize("index", [0, 5, MAX_ROBOTS - 1])
def test_a_robot_never_sees_its_own_body(index):
    world = Owner()
    a = world.robot((0.5, 0.5, 0.3), index=index)
    assert np.all(a.ranges() == INF)  # alone in the space: every ray leaves its own disc and meets nothing
    assert np.all(a.sense(noise=0) == INF)
    # with another robot beside it, only the ray towards it hits (at ~0.061 m), none at 0 on its own rim
    world.robot((0.5, 0.6, 0.0), index=(index + 1) % MAX_ROBOTS)  # 0.1 m to the left (heading 0.3 rad)
    r = a.ranges()
    assert np.isfinite(r).sum() == 1 and np.all(r[np.isfinite(r)] > 0.04)


def test_an_unseen_category_is_invisible_to_the_rays_and_any_other_is_seen():
    # A ball (radius 0.02) at x = 0.56 between A (rim at 0.525) and B (surface at 0.575): its surface is
    # 0.56 − 0.02 − 0.525 = 0.015 m ahead of A. With its category unseen, A reads B at 0.05 m through it.
    for unseen, reading in ((BALL_BIT, 0.05), (0, 0.015)):
        world = Owner()
        a = world.robot((0.5, 0.5, 0.0), index=0, unseen=unseen)
        world.robot((0.6, 0.5, math.pi), index=1)
        world.ball(0.56, 0.5)
        assert a.ranges()[0] == pytest.approx(reading, abs=1e-12), unseen
        assert a.sense(noise=0)[0] == reading  # 10 τ or 3 τ: exact


# -------------------------------------------------------------------------------------------- contacts

@pytest.mark.parametrize("pushes, wall", [(True, False), (True, True), (False, False)],
                         ids=["pushed", "pushed-along-a-wall", "obstacle"])
def test_a_pushed_shape_is_no_collision_and_is_not_slid_against(pushes, wall):
    # A starts 0.1 m behind a free ball (centres; 0.055 m between the surfaces) and drives at it at full
    # speed for 10 periods (80 sub-steps), then stands for 3. The ball has no bounce and is 26 times lighter:
    # the robot shoves it along, and once the robot stops it rolls away (the contact ends).
    # "along a wall": a static segment at y = 0.4753 overlaps A's rim (y = 0.475) by 0.3 mm: A touches it all
    # along the way, so A slides on every sub-step — against the wall (whose normal is across its motion: no
    # effect), and it must not slide against the ball too.
    world = Owner()
    if wall:
        world.space.add(pymunk.Segment(world.space.static_body, (0.0, 0.4753), (2.0, 0.4753), 0.0))
    a = world.robot((0.3, 0.5, 0.0), index=0, pushes=(BALL_TYPE,) if pushes else ())
    b = world.robot((0.3, 0.9, 0.0), index=1, pushes=(BALL_TYPE,) if pushes else ())  # far away, standing
    ball = world.ball(0.4, 0.5)
    poses = world.run([a, b], [(C, C), (0.0, 0.0)], 10, noise=False)
    x = poses[-1, 0, 0]
    free = free_x(80, 0.3)  # 0.3 + 0.00256 × (80 − 1.816) = 0.50015 m, the path with no ball at all
    if pushes:
        # The robot drives through it as if it were not there; only the solver's position correction of each
        # shove (fractions of the 0.1 mm slop, a few dozen shoves) holds it back: measured 0.07 mm.
        assert x == pytest.approx(free, abs=1e-4)
        assert ball.position.x - x > 0.045 - C * 0.016  # the ball went ahead of it, never through it
        world.run([a, b], [(0.0, 0.0), (0.0, 0.0)], 3, noise=False)
        assert ball.position.x - a.pose[0] > 0.045 + 0.01  # rolled off: the contact has ended
        # touching the ball, beginning or ending it, is no contact: only the wall counts, and always has
        assert (a.collisions, a.touching) == ((1, 1) if wall else (0, 0))
        assert a.contact_s == pytest.approx(13 * 8 * 0.016 if wall else 0.0)
    else:  # the same ball as an obstacle: a collision, slid against, and the robot held back by millimetres
        assert a.collisions == 1 and a.touching == 1 and a.contact_s > 0.5
        assert x < free - 0.003  # measured 5.4 mm short
    assert b.collisions == 0 and np.allclose(poses[:, 1], [0.3, 0.9, 0.0])


def test_meeting_two_shapes_in_one_sub_step_is_one_collision():
    # A jamb: two static segments on x = 0.5 with a 2 cm gap round y = 0.5. A (diameter 5 cm) drives along
    # y = 0.5 into the gap and meets both ends in the same sub-step (the 70th): one contact episode, not two.
    # Held there, it rattles in the jamb, making and breaking contacts every sub-step or two: still one.
    world = Owner()
    for y0, y1 in ((0.3, 0.49), (0.51, 0.7)):
        world.space.add(pymunk.Segment(world.space.static_body, (0.5, y0), (0.5, y1), 0.0))
    a = world.robot((0.3, 0.5, 0.0), index=0)
    poses = world.run([a], [(C, C)], 25, noise=False)
    assert a.collisions == 1 and a.touching >= 1
    # held at the jamb: the ends at distance 0.025 from the centre, sqrt(0.025² − 0.01²) = 0.0229 m back
    assert poses[-1, 0, 0] == pytest.approx(0.5 - math.sqrt(0.025**2 - 0.01**2), abs=C * 0.016)


def test_driving_into_the_other_robot_is_one_collision_for_each_and_shoves_it():
    # A at x = 0.3 drives at B (centre 0.15 m ahead, standing) for 25 periods = 200 sub-steps. They touch when
    # A's centre reaches 0.45 − 0.05 = 0.40: free_x(n) >= 0.40 first at n = 41 (0.3 + 0.00256 × 39.2 = 0.4003),
    # so they are in contact for the last 200 − 40 = 160 sub-steps, 2.56 s, one unbroken episode.
    world = Owner()
    a = world.robot((0.3, 0.5, 0.0), index=0)
    b = world.robot((0.45, 0.5, 0.0), index=1)
    poses = world.run([a, b], [(C, C), (0.0, 0.0)], 25, noise=False)
    assert a.collisions == 1 and b.collisions == 1
    assert a.contact_s == pytest.approx(160 * 0.016, abs=0.016) and b.contact_s == pytest.approx(a.contact_s)
    gaps = np.hypot(*(poses[:, 0, :2] - poses[:, 1, :2]).T)
    assert gaps.min() > 2 * KHEPERA.radius - C * 0.016  # they overlap by no more than a sub-step of travel
    assert poses[-1, 1, 0] > 0.45 + 0.1  # B was shoved along (measured 0.20 m in 2.56 s)
    assert np.allclose(poses[:, :, 1], 0.5) and np.allclose(poses[:, :, 2], 0.0)  # head on: no turning


# ------------------------------------------------------------------------------------------------ noise

def two_robots(seeds):
    """Two noisy robots (10 % slip, 10 % sensor noise) side by side, driven for 10 periods; each robot's poses
    and its IR readings of the other, read after every period."""
    world = Owner()
    robots = [world.robot((0.5, 0.5, math.pi / 2), 0, seeds[0], KHEPERA),
              world.robot((0.6, 0.5, math.pi / 2), 1, seeds[1], KHEPERA)]
    poses, readings = [], []
    for _ in range(10):
        poses.append(world.run(robots, [(0.08, 0.08), (0.08, 0.08)], 1)[0])
        readings.append([r.sense() for r in robots])
    return np.array(poses), np.array(readings)


def test_each_robot_has_its_own_noise_and_a_seed_repeats_bit_for_bit():
    poses, readings = two_robots((3, 4))
    again_poses, again_readings = two_robots((3, 4))
    np.testing.assert_array_equal(poses, again_poses)  # the same seeds, the same calls: the same bits
    np.testing.assert_array_equal(readings, again_readings)
    # the two robots got the same commands from mirror-image starts but not the same slip: their paths part
    assert np.abs(poses[-1, 0, 1] - poses[-1, 1, 1]) > 1e-5 or np.abs(poses[-1, 0, 2] - poses[-1, 1, 2]) > 1e-5
    # each sees the other ~5 cm away (A on B's sensor 3 side), but the two rings' noise differs
    assert not np.array_equal(readings[:, 0, 9], readings[:, 1, 3])
    # the seed alone makes a robot's noise, not its index: robot 1 with seed 3 moves as robot 0 with seed 3
    swapped_poses, _ = two_robots((4, 3))
    np.testing.assert_allclose(swapped_poses[:, 1] - [0.1, 0.0, 0.0], poses[:, 0], rtol=0, atol=1e-12)


def test_reading_the_sensors_does_not_change_the_motor_noise():
    world, other = Owner(), Owner()
    a = world.robot((0.5, 0.5, 0.0), 0, 7, KHEPERA)
    b = other.robot((0.5, 0.5, 0.0), 0, 7, KHEPERA)
    for _ in range(5):
        a.sense()  # draws from a's sensor stream only
        world.run([a], [(0.1, 0.12)], 1)
        other.run([b], [(0.1, 0.12)], 1)
    np.testing.assert_array_equal(a.pose, b.pose)


# ----------------------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("kwargs", [dict(index=MAX_ROBOTS), dict(index=-1), dict(seed=-1), dict(seed=True),
                                    dict(seed=1.5), dict(seed="3")])
def test_an_index_out_of_range_or_a_bad_seed_is_refused(kwargs):
    with pytest.raises(ValueError, match="index" if "index" in kwargs else "seed"):
        RobotBody(pymunk.Space(), lambda: 0.0, KHEPERA, **{"seed": 0, **kwargs})
