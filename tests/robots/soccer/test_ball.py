"""The ball on its pitch (robots.soccer.ball): restitution at the walls, rolling friction that stops the ball
after v0²/(2f) m and v0/f s without turning it round, goal boxes the ball cannot leave except by the mouth,
and the input checks. pymunk is deterministic: no seeds needed."""

import math

import numpy as np
import pytest

from ekm.errors import InputError
from robots.soccer.ball import BallParams, Pitch
from robots.soccer.field import Field

DT = 0.016  # the robot's physics sub-step (robots.params.KHEPERA.dt)


def roll(pitch, steps):
    """Positions and velocities ``(steps, 2)`` after each of ``steps`` steps."""
    xs, vs = [], []
    for _ in range(steps):
        pitch.step(DT)
        xs.append(pitch.ball_position)
        vs.append(pitch.ball_velocity)
    return np.array(xs), np.array(vs)


@pytest.mark.parametrize("e", [0.7, 0.5])
def test_a_ball_rolled_at_an_end_wall_comes_back_at_restitution_times_its_speed(e):
    pitch = Pitch(Field(), BallParams(restitution=e, rolling_friction=0.0))
    pitch.place(0.6, 0.15)  # y = 0.15 m: beside the mouth (0.28 .. 0.52), so it meets the end wall
    pitch.kick((-0.3, 0.0))
    # it touches the wall at x = 0.02 (one radius) after (0.6 - 0.02) / 0.3 = 1.93 s = 121 steps; 160 steps
    # (2.56 s) give it 0.63 s to come back
    xs, vs = roll(pitch, 160)
    assert xs[:, 0].min() > 0.02 - 0.3 * DT  # it never goes deeper into the wall than one step's travel
    assert vs[-1, 0] == pytest.approx(0.3 * e, rel=0.01)  # 0.21 m/s for 0.7, 0.15 m/s for 0.5
    assert vs[-1, 1] == pytest.approx(0.0, abs=1e-9)  # head on: no sideways motion
    assert xs[-1, 0] > xs[-2, 0]  # moving away from the wall


def test_an_oblique_bounce_keeps_the_tangential_speed_and_scales_the_normal_one():
    pitch = Pitch(Field(), BallParams(restitution=0.7, rolling_friction=0.0))
    pitch.place(0.5, 0.2)
    pitch.kick((0.2, -0.2))
    # meets the bottom wall (y = 0.02) after 0.18 / 0.2 = 0.9 s; after 1.3 s it is on its way back up,
    # 0.2 + 0.2 * 1.3 = 0.76 m along, short of the far end
    _, vs = roll(pitch, 81)
    assert vs[-1] == pytest.approx([0.2, 0.2 * 0.7], rel=0.01)  # (0.2, 0.14): no contact friction


@pytest.mark.parametrize("v0, f", [(0.3, 0.15), (0.24, 0.3)])
def test_rolling_friction_stops_the_ball_after_v0_squared_over_2f_metres_and_v0_over_f_seconds(v0, f):
    # (0.3, 0.15): 0.09 / 0.3 = 0.3 m in 2.0 s; (0.24, 0.3): 0.0576 / 0.6 = 0.096 m in 0.8 s.
    # The kick points along (0.6, 0.8), from (0.2, 0.2): it stops by (0.38, 0.44), far from every wall.
    direction = np.array([0.6, 0.8])
    pitch = Pitch(Field(), BallParams(rolling_friction=f))
    pitch.place(0.2, 0.2)
    pitch.kick(v0 * direction)
    xs, vs = roll(pitch, round(1.5 * v0 / f / DT))
    speeds = np.hypot(vs[:, 0], vs[:, 1])
    stopped = int(np.argmax(speeds == 0.0)) + 1  # steps taken when the speed first reaches exactly 0
    assert speeds[-1] == 0.0 and abs(stopped * DT - v0 / f) <= DT + 1e-9  # 2.0 s (0.8 s), within a step
    rolled = np.linalg.norm(xs[-1] - [0.2, 0.2])
    assert rolled == pytest.approx(v0 * v0 / (2 * f), rel=0.02)
    assert np.all(vs @ direction >= 0.0)  # never turned round ...
    assert np.allclose(vs[:, 0] * direction[1], vs[:, 1] * direction[0])  # ... nor off its line
    assert np.all(np.diff((xs - [0.2, 0.2]) @ direction) >= 0.0)
    assert np.allclose(xs[stopped:], xs[-1])  # and it stays put


def test_stopping_distance_is_v_squared_over_2f():
    assert BallParams().stopping_distance(0.3) == pytest.approx(0.3)  # 0.09 / (2 × 0.15)
    assert BallParams(rolling_friction=0.0).stopping_distance(0.3) == math.inf


@pytest.mark.parametrize("side, start", [(0, (-0.03, 0.4)), (1, (1.23, 0.4))])
def test_a_ball_inside_a_goal_box_leaves_it_only_through_the_mouth(side, start):
    # 16 directions at 0.3 m/s for 1 s each, no rolling friction. The centre never leaves the pitch (field or
    # goal boxes); contacts are found after a step, so the ball may overlap a wall by up to one step's travel,
    # 0.3 × 0.016 = 4.8 mm, and no more: its clearance stays >= 0.02 - 0.005 = 0.015 m.
    for k in range(16):
        pitch = Pitch(Field(), BallParams(rolling_friction=0.0))
        pitch.place(*start)
        a = 2 * math.pi * k / 16
        pitch.kick((0.3 * math.cos(a), 0.3 * math.sin(a)))
        xs, _ = roll(pitch, 63)
        assert all(pitch.field.contains(x, margin=0.015) for x in xs), (side, k)


def test_the_ball_starts_still_on_the_centre_spot_and_place_stops_it():
    pitch = Pitch()
    assert pitch.ball_position == pytest.approx([0.6, 0.4]) and pitch.ball_velocity == pytest.approx([0, 0])
    pitch.kick((0.1, 0.0))
    pitch.place(0.3, 0.2)
    assert pitch.ball_position == pytest.approx([0.3, 0.2]) and pitch.ball_velocity == pytest.approx([0, 0])


@pytest.mark.parametrize("kwargs, name", [
    (dict(radius=-0.02), "radius"), (dict(radius=0.0), "radius"), (dict(mass=0.0), "mass"),
    (dict(restitution=1.5), "restitution"), (dict(restitution=-0.1), "restitution"),
    (dict(rolling_friction=-0.15), "rolling_friction"), (dict(mass=float("nan")), "mass"),
])
def test_bad_ball_parameters_are_refused_in_one_line(kwargs, name):
    with pytest.raises(InputError) as err:
        BallParams(**kwargs)
    assert name in str(err.value) and "\n" not in str(err.value)


def test_a_ball_too_big_for_the_goal_is_refused():
    with pytest.raises(InputError, match="does not fit"):
        Pitch(Field(), BallParams(radius=0.07))  # 0.07 m > goal depth 0.06 m: it could never cross the line


@pytest.mark.parametrize("call", [
    lambda p: p.place(0.01, 0.1),  # overlaps the end wall (0.01 < radius 0.02)
    lambda p: p.place(2.0, 0.4),  # off the field
    lambda p: p.kick((float("nan"), 0.0)),
    lambda p: p.kick((0.1, 0.2, 0.3)),
    lambda p: p.step(0.0),
])
def test_bad_pitch_calls_are_refused(call):
    with pytest.raises(InputError):
        call(Pitch())
