"""A game's physics (robots.soccer.game.Game): a robot pushes the ball off at (1 + e)·m_r/(m_r + m_b) times its
speed, a goal is counted once and (rule "centre") is followed by a kick-off with every robot at rest on its
kick-off pose, rule "sahota" plays on, the IR sees the other robot and not the ball, and bad set-ups are
refused. The robots have no slip (actuator_noise 0): every path is worked out by hand."""

import dataclasses
import math

import numpy as np
import pytest

from ekm.errors import InputError
from robots.params import KHEPERA
from robots.soccer.ball import BallParams
from robots.soccer.field import Field
from robots.soccer.game import Game, kickoff_poses

C = KHEPERA.max_wheel_speed  # 0.16 m/s, 20 speed units: sent exactly
QUIET = dataclasses.replace(KHEPERA, actuator_noise=0.0)
F = Field()  # 1.2 m × 0.8 m; mouth y in [0.28, 0.52]; centre spot (0.6, 0.4)
M_ROBOT, M_BALL = 0.07, 0.0027  # kg: robots.body's Khepera, BallParams' table-tennis ball
INF = math.inf


def test_the_kickoff_poses_are_a_quarter_of_the_length_from_each_goal_facing_the_other():
    zero, one = kickoff_poses(F)
    np.testing.assert_allclose(zero, [0.3, 0.4, 0.0])  # 1.2 / 4, 0.8 / 2
    np.testing.assert_allclose(one, [0.9, 0.4, math.pi])


@pytest.mark.parametrize("e", [0.7, 0.5])
def test_a_robot_at_full_speed_sends_a_still_ball_off_at_1_plus_e_times_its_speed_times_the_mass_ratio(e):
    # Robot 0 drives from its kick-off (0.3, 0.4, 0) straight at the ball on the centre spot; robot 1 stands
    # out of the way. No rolling friction, so the ball keeps the speed the bounce gives it.
    #
    # Which speed? The robot is velocity-controlled, but its velocity is set only *before* each sub-step: in
    # the sub-step of the bounce the solver treats it as the free 0.07 kg body it is, so momentum is shared:
    #   v_ball = (1 + e) · m_r / (m_r + m_b) · v = (1 + e) × 0.07 / 0.0727 × 0.16
    #          = 0.2618982 m/s (e = 0.7) or 0.2310867 m/s (e = 0.5),
    # 3.7 % below the (1 + e) v = 0.272 (0.240) m/s of an infinitely heavy robot. Measured: the first to 8
    # digits. The contact is one point between two circles without friction, so Chipmunk's sequential
    # impulses solve it exactly on their first iteration; rel 1e-6 leaves room for rounding only, and is
    # 37,000 times finer than the gap between the two answers.
    # When: the surfaces (0.3 + 0.025 and 0.6 − 0.02) meet once the robot has come 0.255 m; with the motor lag
    # (robots/test_body.py: free_x) that is in sub-step 102, the 13th period. 16 periods leave 3 to spare.
    game = Game(F, BallParams(restitution=e, rolling_friction=0.0), 2, (0, 1), QUIET,
                kickoff=[(0.3, 0.4, 0.0), (0.9, 0.15, math.pi)])
    xs = []
    for _ in range(16):
        game.step([(C, C), (0.0, 0.0)])
        xs.append(game.robots[0].pose[0])
    expected = (1 + e) * M_ROBOT / (M_ROBOT + M_BALL) * C
    vx, vy = game.pitch.ball_velocity
    assert vx == pytest.approx(expected, rel=1e-6)
    assert vy == pytest.approx(0.0, abs=1e-12)  # head on
    assert game.pitch.ball_position[0] > xs[-1] + 0.045 + 0.01  # it left the robot behind
    # the robot was not slowed: after the bounce it still makes 0.16 × 0.128 = 0.02048 m a period
    assert np.diff(xs[-3:]) == pytest.approx([0.02048, 0.02048], abs=1e-9)
    assert game.robots[0].collisions == 0  # the ball is not an obstacle
    assert game.goals == [] and game.score.goals == (0, 0)


def roll_into_goal(rule):
    """The ball placed at (1.1, 0.4) and kicked at 0.3 m/s straight at side 1's goal, while robot 0 spins on the
    spot at (0.3, 0.4) and robot 1 drives at 0.08 m/s from (0.9, 0.4) towards side 0 (away from the ball).
    Returns the game after 3 periods and the goals each period returned."""
    game = Game(F, BallParams(), 2, (0, 1), QUIET, rule=rule)
    game.pitch.place(1.1, 0.4)
    game.pitch.kick((0.3, 0.0))
    returned = [game.step([(-0.08, 0.08), (0.08, 0.08)]) for _ in range(3)]
    return game, returned


# The goal: friction 0.15 m/s² taken half before and half after each step, the ball moves by
# 0.016 × (0.3 − 0.0024 (j + 1/2)) in step j, so after n steps it has come 0.0048 n − 0.0000192 n² m;
# that reaches the 0.1 m to the line (x = 1.2) first at n = 22.94 → 23: t = 23 × 0.016 = 0.368 s, in the
# third period (sub-steps 17 … 24), one sub-step before its end.
GOAL_T = 0.368


def test_a_ball_rolled_into_side_1s_goal_is_one_goal_for_side_0_then_a_kickoff_at_rest():
    game, returned = roll_into_goal("centre")
    assert returned[:2] == [[], []] and len(returned[2]) == 1
    (t, side), = returned[2]
    assert side == 0 and t == pytest.approx(GOAL_T, abs=1e-9)
    assert game.goals == returned[2] and game.score.goals == (1, 0)
    assert game.score.in_goal is None and game.score.locked is None
    # the kick-off: the ball still on the centre spot, and the robots — which were moving — at rest on their
    # kick-off poses at the end of the period, their wheels stopped (driven on through the period's last
    # sub-step, they would be 0.08 × 0.016 = 1.3 mm and 0.048 rad off)
    np.testing.assert_array_equal(game.pitch.ball_position, [0.6, 0.4])
    np.testing.assert_array_equal(game.pitch.ball_velocity, [0.0, 0.0])
    for r, pose in zip(game.robots, kickoff_poses(F)):
        np.testing.assert_allclose(r.pose, pose, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(r.wheels, [0.0, 0.0])
        np.testing.assert_allclose(r.trace[-1], pose, rtol=0, atol=1e-12)
    # play on from the kick-off: nothing more is scored, and the ball stays put (nobody is near it)
    for _ in range(5):
        assert game.step([(-0.08, 0.08), (0.08, 0.08)]) == []
    assert game.score.goals == (1, 0) and len(game.goals) == 1
    np.testing.assert_array_equal(game.pitch.ball_position, [0.6, 0.4])


def test_under_rule_sahota_the_goal_counts_once_and_play_goes_on():
    game, returned = roll_into_goal("sahota")
    assert [g for period in returned for g in period] == [pytest.approx((GOAL_T, 0))]
    assert game.score == ((1, 0), 1, 1)  # side 1 scored upon: locked; the ball in its goal
    assert game.pitch.ball_position[0] > 1.2  # not re-centred: past the line (1.204 m)
    # robot 1 drove on: 0.08 m/s for 24 sub-steps less the lag's 1.816, 0.08 × 0.016 × 22.184 = 0.0284 m
    assert game.robots[1].pose[0] == pytest.approx(0.9 - 0.0284, abs=1e-4)
    # the ball bounces off the back of the goal and rolls back out over the line: no second goal (while it
    # rocks across the line it is still "in" the goal, and side 1 stays locked until the ball reaches side 0's
    # half), and no kick-off
    for _ in range(37):  # 40 periods in all, 5.12 s (short of the 15 s of a dead ball)
        assert game.step([(-0.08, 0.08), (0.08, 0.08)]) == []
    assert game.score.goals == (1, 0) and len(game.goals) == 1 and game.restarts == []
    assert game.pitch.ball_position[0] < 1.2  # it came back out: measured 1.09 m
    assert game.robots[1].pose[0] < 0.9 - 0.3  # 0.08 × 5.1 s = 0.41 m, never put back


def test_the_ir_of_each_robot_sees_the_other_robot_and_not_the_ball():
    # robot 0 at (0.4, 0.4) facing +x, robot 1 at (0.5, 0.4) facing it, the ball (radius 0.02) between them at
    # (0.45, 0.4): 0.005 m from robot 0's rim. Seen through the ball, the other robot is 0.1 − 0.05 = 0.05 m
    # away. Every other ray misses: a ray at ±30° passes the other robot's centre 0.05 m off and the ball's
    # 0.025 m off, and the walls are 0.375 m away, beyond the 0.175 m range.
    game = Game(F, BallParams(), 2, (0, 1), QUIET, kickoff=[(0.4, 0.4, 0.0), (0.5, 0.4, math.pi)])
    game.pitch.place(0.45, 0.4)
    for r in game.robots:
        np.testing.assert_allclose(r.ranges(), [0.05] + [INF] * 11, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(r.sense(noise=0), [0.05] + [INF] * 11)


@pytest.mark.parametrize("pose", [(0.01, 0.15, 0.0), (0.3, 0.02, 0.0), (0.3, 0.9, 0.0), (1.5, 0.4, 0.0)],
                         ids=["in-the-end-wall", "in-a-side-wall", "off-the-pitch", "beyond-the-goal"])
def test_a_kickoff_pose_in_a_wall_or_off_the_pitch_is_refused(pose):
    # a robot (radius 0.025) at x = 0.01 beside the mouth or at y = 0.02 overlaps a wall; y = 0.9 is beyond the
    # side wall; x = 1.5 is behind side 1's goal (its back is at 1.26)
    with pytest.raises(InputError, match="kick-off pose 1"):
        Game(F, BallParams(), 2, (0, 1), QUIET, kickoff=[(0.3, 0.4, 0.0), pose])


def test_a_kickoff_pose_in_a_goal_mouth_is_allowed():
    # (−0.03, 0.4): inside side 0's goal box, 0.03 m from its back wall (x = −0.06) and 0.12 m from its sides
    game = Game(F, BallParams(), 2, (0, 1), QUIET, kickoff=[(-0.03, 0.4, 0.0), (0.9, 0.4, math.pi)])
    np.testing.assert_array_equal(game.robots[0].pose, [-0.03, 0.4, 0.0])


@pytest.mark.parametrize("make, match", [
    (lambda: Game(F, BallParams(), 2, (0,), QUIET), "seeds"),
    (lambda: Game(F, BallParams(), 3, (0, 1), QUIET), "seeds"),
    (lambda: Game(F, BallParams(), 2, (0, 1), QUIET, kickoff=[(0.3, 0.4, 0.0)]), "kick-off poses"),
    (lambda: Game(F, BallParams(), 2, (0, 1), QUIET, rule="offside"), "rule"),
    (lambda: Game(F, BallParams(), 2, (0, 1), QUIET).step([(0.1, 0.1)]), "commands"),
    (lambda: Game(F, BallParams(), 2, (0, 1), QUIET).step([(0.1, 0.1)] * 3), "commands"),
])
def test_mismatched_seeds_poses_commands_or_a_bad_rule_are_refused(make, match):
    with pytest.raises(InputError, match=match):
        make()


@pytest.mark.parametrize("seed", [1.5, -1, True])
def test_a_bad_seed_is_refused_not_rounded(seed):
    with pytest.raises(ValueError, match="seed"):
        Game(F, BallParams(), 2, (0, seed), QUIET)


def test_each_robot_of_a_game_moves_as_its_own_robot():
    """A Khepera and a worn-wheel Khepera (left wheel 0.9), noise off, both sent 0.096 m/s on each wheel for
    1.024 s (eight periods of eight 16 ms sub-steps) from rest. The wheels lag (τ = 20 ms, each sub-step's speed
    c (1 − e^{−j dt/τ}), j = 0..63) and cover c (1.024 − dt / (1 − e^{−dt/τ})) = c · 0.994943 m; so the Khepera goes
    0.095515 m straight, and the worn-wheel one turns left by (0.096 − 0.0864) / 0.053 · 0.994943 = 0.18022 rad."""
    worn = dataclasses.replace(QUIET, name="worn", wheel_gain=(0.9, 1.0))
    game = Game(F, BallParams(), 2, (0, 1), [QUIET, worn])
    start = [r.pose.copy() for r in game.robots]
    for _ in range(8):
        game.step([(0.096, 0.096)] * 2)
    travelled = 1.024 - 0.016 / (1.0 - math.exp(-0.8))
    np.testing.assert_allclose(game.robots[0].pose - start[0], [0.096 * travelled, 0.0, 0.0], atol=1e-9)
    turned = math.remainder(game.robots[1].pose[2] - start[1][2], 2 * math.pi)
    assert turned == pytest.approx(0.0096 / 0.053 * travelled, rel=1e-6)


def test_robots_that_step_differently_cannot_share_a_game():
    slow = dataclasses.replace(QUIET, name="slow", avoid_period=0.256, target_period=1.024)
    with pytest.raises(InputError, match="robots khepera and slow must share avoid_period"):
        Game(F, BallParams(), 2, (0, 1), [QUIET, slow])
