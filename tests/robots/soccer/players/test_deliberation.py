"""Sahota's reactive-deliberation soccer player (his §4.2, Tables 3 and 4; the levels of §4.3): each behaviour's bid
and plan, which behaviour wins where, the stability bias, how the three levels deliberate, and what each action
schema sends to the wheels — on hand-built plays in the player's own frame, the numbers worked out by hand.

Field 1.2 × 0.8 m: G = (1.2, 0.4) the goal attacked, H = (0, 0.4) the home goal; body radius R = 0.025, ball
radius 0.02, so the touching distance c = 0.045; c* = 0.16 m/s; a full-wheel turn on the spot 2 c* / 0.053 =
6.0377 rad/s. slow(T) = ln(1 + T) / ln 9."""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.params import KHEPERA, LONG_RANGE
from robots.soccer.field import Field
from robots.soccer.play import Play
from robots.soccer.players import deliberation as sd

P = sd.SoccerDeliberationParams()
F = Field()
C_STAR = KHEPERA.max_wheel_speed

bid_jit = jax.jit(sd.bid, static_argnames=("p", "field", "robot"))
deliberate_jit = jax.jit(sd.deliberate, static_argnames=("p", "field", "robot"))
tick_jit = jax.jit(sd.tick, static_argnames=("p", "field", "robot"))
defend_jit = jax.jit(sd.defend_point, static_argnames=("p", "field", "robot"))


def play(pose, ball, opp=(1.0, 0.7, math.pi, 0.0, 0.0), t=0.0, velocity=(0.0, 0.0)):
    ball = tuple(ball) + (0.0, 0.0) * (len(ball) == 2)
    return Play(t=np.float32(t), ir=np.full(len(LONG_RANGE.angles), np.inf, np.float32),
                pose=np.asarray(pose, np.float32), velocity=np.asarray(velocity, np.float32),
                ball=np.asarray(ball, np.float32), opponent=np.asarray(opp, np.float32))


def bids(*args, p=P, **kw):
    return bid_jit(play(*args, **kw), p, F, KHEPERA)


def running(action, ruling, waypoint=2, due=100.0, p=P):
    """A state whose executor runs ``action`` for behaviour ``ruling``, the next deliberation far off."""
    return sd.init(p)._replace(action=action, ruling=jnp.int32(ruling), waypoint=jnp.int32(waypoint),
                               due=jnp.float32(due))


@functools.cache
def player(p):
    """The built player of ``p`` (built once, so its step compiles once)."""
    return sd.build(p)


def step(state, pl, p=P):
    """One tick through the built player: (state, wheels as numpy)."""
    state, w = player(p).step(state, pl)
    return state, np.asarray(w)


# ------------------------------------------------------------------------------------------ bids: who wins where

def test_the_ball_lined_up_before_the_goal_makes_shoot_win_with_a_push_through_it():
    # player (0.7, 0.4) facing the goal, ball (0.9, 0.4) still, opponent (1.0, 0.7): |o − b| = 0.316 > reach
    # shoot: u = (1, 0), A = (0.82, 0.4), straight on (the way passes 8 cm from the ball), touch at x = 0.855:
    # 0.155 m, no turn → 0.96875 s, slow = 0.30830; far = 0.3 / 1.2 = 0.25 → 8 − 0.9249 − 0.5 = 6.5751
    # clear: u = (b − H)/|b − H| = (1, 0), the same plan → 3 + 0 − 0.9249 = 2.0751
    # servo at ball: lined 1, close 1 − 0.2/0.3 = 1/3, pressed 0 → 2 + 1 = 3
    # go red line: theirs = 0.9/0.6 − 1 = 0.5, near(0.6) = 1 − 0.1/0.1 = 0 → 1 + 2.5 = 3.5; go home: 1 (own = 0)
    b = bids((0.7, 0.4, 0.0), (0.9, 0.4))
    np.testing.assert_allclose(np.asarray(b.bids), [6.5751, 2.0751, 3.0, 1.0, 3.5, 0.0, 1.0, 0.0], atol=1e-3)
    assert int(jnp.argmax(b.bids)) == sd.SHOOT
    assert float(b.times[sd.SHOOT]) == pytest.approx(0.96875, abs=1e-4)
    shoot = jax.tree.map(lambda a: a[sd.SHOOT], b.actions)
    assert int(shoot.schema) == sd.PATH and int(shoot.first) == 2  # no way round: straight to A
    # end T = b + 0.15 u (the field's exit along u is 0.275 m further): (1.05, 0.4)
    np.testing.assert_allclose(np.asarray(shoot.path[2:]), [[0.82, 0.4], [1.05, 0.4]], atol=1e-5)
    # a ball 0.1 m before the goal line: the end is shortened to stay R inside the field, at x = 1.175
    b = bids((0.9, 0.4, 0.0), (1.1, 0.4))
    np.testing.assert_allclose(np.asarray(b.actions.path[sd.SHOOT, 2:]), [[1.02, 0.4], [1.175, 0.4]], atol=1e-5)


def test_a_rolling_ball_is_met_where_it_will_be_and_its_speed_lowers_the_bids():
    # the ball of the test above rolling on at 0.15 m/s: 0.2 m away, 1.25 s at c*; it stops after 1 s, 0.15 − 0.075
    # = 0.075 m on, at (0.975, 0.4): A = (0.895, 0.4), the touch at 0.93, 0.23 m → 1.4375 s, slow = 0.40550;
    # fast = 0.15 / 0.3 = 0.5; far from where the ball is now, 0.25 → shoot 8 − 1.2165 − 0.5 − 0.5 = 5.7835,
    # clear 3 − 1.2165 − 0.5 = 1.2835; the end 0.15 m past the ball, (1.125, 0.4)
    b = bids((0.7, 0.4, 0.0), (0.9, 0.4, 0.15, 0.0))
    np.testing.assert_allclose(np.asarray(b.bids)[:2], [5.7835, 1.2835], atol=1e-3)
    np.testing.assert_allclose(np.asarray(b.actions.path[sd.SHOOT, 2:]), [[0.895, 0.4], [1.125, 0.4]], atol=1e-5)


def test_goal_side_of_a_ball_in_its_end_the_player_clears_rather_than_keeps_goal():
    # player on the home line (0.05, 0.4) facing out, ball (0.15, 0.4): own = 1 − 0.15/0.6 = 0.75
    # clear: u = (1, 0), A = (0.07, 0.4), touch at 0.105: 0.055 m → 0.34375 s, slow = 0.13447 → 3 + 4.5 − 0.4034
    # = 7.0966; shoot: same plan, far = 1.05/1.2 = 0.875 → 8 − 0.4034 − 1.75 = 5.8466
    # servo: close 1 − 0.1/0.3 = 2/3 → 2 + 2 = 4; defend home line: near = 1 → 1 + 7 · 0.75 = 6.25
    b = bids((0.05, 0.4, 0.0), (0.15, 0.4), opp=(0.6, 0.4, math.pi, 0.0, 0.0))
    np.testing.assert_allclose(np.asarray(b.bids), [5.8466, 7.0966, 4.0, 1.0, 1.0, 0.0, 0.0, 6.25], atol=1e-3)
    assert int(jnp.argmax(b.bids)) == sd.CLEAR


def test_on_the_wrong_side_of_a_ball_before_its_goal_the_player_goes_home_round_the_ball():
    # player (0.4, 0.4) facing home, ball (0.15, 0.4): the way to A = (0.07, 0.4) runs through the ball, so round
    # it: through the centre line, to the field centre's side — (0.6, 0.4) − b is along the way, so perp (0, −1):
    # beside = (0.15, 0.32). Legs 0.26249 + 0.11314 + 0.035 = 0.41063 m, turns 0.3097 + 1.0951 + 2.3562 = 3.7610
    # rad → 2.5664 + 0.6229 = 3.1893 s, slow = 0.65198 → clear 7.5 − 1.9559 = 5.5441, shoot 8 − 1.9559 − 1.75
    # = 4.2941; servo: lined = −1 → 0; go home line: near(0.05) = 0 → 1 + 5.25 = 6.25
    b = bids((0.4, 0.4, math.pi), (0.15, 0.4))
    np.testing.assert_allclose(np.asarray(b.bids), [4.2941, 5.5441, 0.0, 1.0, 1.0, 0.0, 6.25, 0.0], atol=1e-3)
    assert float(b.times[sd.CLEAR]) == pytest.approx(3.1893, abs=1e-3)
    home = jax.tree.map(lambda a: a[sd.GO_HOME], b.actions)
    assert int(jnp.argmax(b.bids)) == sd.GO_HOME and int(home.schema) == sd.PATH and int(home.first) == 1
    np.testing.assert_allclose(np.asarray(home.path[1:]), [[0.15, 0.32], [0.05, 0.4], [0.05, 0.4]], atol=1e-5)


def test_an_opponent_pressing_the_ball_turns_the_shot_into_a_poke_with_the_servo():
    # player (0.5, 0.4), ball (0.6, 0.4), opponent (0.68, 0.42): |o − b| = 0.08246, pressed = 0.72513
    # shoot: 0.055 m to the touch, slow = 0.13447, far = 0.5 → 8 − 0.4034 − 1.4503 − 1 = 5.1463
    # servo: lined 1, close 2/3 → 2 + 2 + 2.1754 = 6.1754; clear 3 − 0.4034 = 2.5966 (own = 0 at the half-way line)
    b = bids((0.5, 0.4, 0.0), (0.6, 0.4), opp=(0.68, 0.42, math.pi, 0.0, 0.0))
    np.testing.assert_allclose(np.asarray(b.bids)[:3], [5.1463, 2.5966, 6.1754], atol=1e-3)
    assert int(jnp.argmax(b.bids)) == sd.AT_BALL
    assert int(b.actions.schema[sd.AT_BALL]) == sd.SERVO
    # the opponent far away: shoot 8 − 0.4034 − 1 = 6.5966 beats the servo's 2 + 2 = 4
    b = bids((0.5, 0.4, 0.0), (0.6, 0.4))
    np.testing.assert_allclose(np.asarray(b.bids)[[sd.SHOOT, sd.AT_BALL]], [6.5966, 4.0], atol=1e-3)


def test_the_opponent_on_the_ball_in_its_half_sends_the_player_to_the_red_line_then_to_defend_it():
    # ball (1.0, 0.6), opponent on it (1.05, 0.6): theirs = 2/3, pressed = 1 − 0.05/0.3 = 5/6; far = 0.28284/1.2
    # shoot from (0.2, 0.4): u = (0.7071, −0.7071), A = (0.94343, 0.65657): 0.78646 + 0.035 m, turns 0.3326 + 1.1180
    # rad → 5.3743 s, slow = 0.84300 → 8 − 2.5290 − 1.6667 − 0.4714 = 3.3329
    # servo: lined = (0.7071, −0.7071)·(0.9701, 0.2425) = 0.51450, close 0 → 0.5145 · (2 + 2.5) = 2.3152
    # go red line: near(0.6) = 0 → (1 + 5 · 2/3) = 4.3333
    # clear: along b − H, u = (0.9806, 0.1961), A = (0.92155, 0.58431): 0.74472 + 0.035 m, turns 0.2501 + 0.0527
    # rad → 4.9234 s, slow = 0.80962 → 3 − 2.4289 = 0.5711
    b = bids((0.2, 0.4, 0.0), (1.0, 0.6), opp=(1.05, 0.6, math.pi, 0.0, 0.0))
    np.testing.assert_allclose(np.asarray(b.bids)[[sd.SHOOT, sd.CLEAR, sd.AT_BALL, sd.GO_RED, sd.DEFEND_RED]],
                               [3.3329, 0.5711, 2.3152, 4.3333, 0.0], atol=1e-3)
    assert int(jnp.argmax(b.bids)) == sd.GO_RED
    np.testing.assert_allclose(np.asarray(b.actions.path[sd.GO_RED, 2]), [0.6, 0.4], atol=1e-6)
    # on the red line (0.6, 0.4): defend red line 4.3333 beats shoot (3.8894) and the servo (1.4230)
    b = bids((0.6, 0.4, 0.0), (1.0, 0.6), opp=(1.05, 0.6, math.pi, 0.0, 0.0))
    np.testing.assert_allclose(np.asarray(b.bids)[[sd.SHOOT, sd.AT_BALL, sd.GO_RED, sd.DEFEND_RED]],
                               [3.8894, 1.4230, 0.0, 4.3333], atol=1e-3)
    assert int(jnp.argmax(b.bids)) == sd.DEFEND_RED
    assert int(b.actions.schema[sd.DEFEND_RED]) == sd.DEFEND
    assert float(b.actions.line[sd.DEFEND_RED]) == pytest.approx(0.6)


def test_a_push_that_cannot_start_on_the_field_or_a_ball_in_a_goal_bids_nothing():
    # ball (1.15, 0.1) by the far corner: u = (0.1644, 0.9864), A = (1.1368, 0.0211) — closer than R to the wall
    assert float(bids((0.9, 0.2, 0.0), (1.15, 0.1)).bids[sd.SHOOT]) == 0.0
    b = bids((0.3, 0.4, math.pi), (-0.03, 0.4))  # in the home goal
    assert float(b.bids[sd.SHOOT]) == 0.0 and float(b.bids[sd.CLEAR]) == 0.0
    # own = 1: the goalie's pair bids 1 + 7 = 8, split by near(0.05) = 1 − 0.25/0.1 → 0: go home 8
    assert float(b.bids[sd.GO_HOME]) == pytest.approx(8.0)
    # goals 0.2 m deep, the ball (1.28, 0.4) in the one attacked: the "shot" would start at A = (1.36, 0.4), inside
    # the goal, and push the ball back out of it
    deep = Field(goal_depth=0.2)
    assert float(bid_jit(play((1.0, 0.4, 0.0), (1.28, 0.4)), P, deep, KHEPERA).bids[sd.SHOOT]) == 0.0


def test_a_ball_on_the_goal_line_in_the_mouth_is_cleared_from_inside_the_mouth():
    # ball (0.01, 0.32): u = (b − H)/|b − H| = (0.12403, −0.99228), A = b − 0.08 u = (0.00008, 0.39938) —
    # nearer the end line than R, but inside the mouth's channel. From (0.06, 0.45) facing home: 0.07844 +
    # 0.035 m, turns 1.6952 rad → 0.98976 s, slow = 0.31313; own = 1 − 0.01/0.6 = 0.98333 → 3 + 5.9 − 0.9394
    # = 7.9606
    b = bids((0.06, 0.45, math.pi), (0.01, 0.32))
    assert float(b.bids[sd.CLEAR]) == pytest.approx(7.9606, abs=1e-3)
    np.testing.assert_allclose(np.asarray(b.actions.path[sd.CLEAR, 2]), [0.00008, 0.39938], atol=1e-5)


def test_a_player_between_the_approach_point_and_the_ball_pushes_on_without_going_back():
    # player (0.55, 0.4) between A = (0.52, 0.4) and the ball (0.6, 0.4), on the line: first waypoint the end
    b = bids((0.55, 0.4, 0.0), (0.6, 0.4))
    assert int(b.actions.first[sd.SHOOT]) == 3
    assert float(b.times[sd.SHOOT]) == pytest.approx(0.005 / 0.16, abs=1e-4)  # 5 mm to the touch at 0.555


# ------------------------------------------------------------------------------------------ the deliberator

def test_the_ruling_behaviour_keeps_control_by_its_stability_bias_while_its_schema_runs():
    # player (0.5, 0.4), ball (0.6, 0.4), opponent (0.72, 0.4): pressed = 0.6 → shoot 8 − 0.4034 − 1.2 − 1
    # = 5.3966, servo 2 + 2 + 1.8 = 5.8: the servo wins a fresh deliberation, not one against shoot's running
    # path (5.3966 + 1 = 6.3966)
    pl = play((0.5, 0.4, 0.0), (0.6, 0.4), opp=(0.72, 0.4, math.pi, 0.0, 0.0))
    np.testing.assert_allclose(np.asarray(bid_jit(pl, P, F, KHEPERA).bids)[[sd.SHOOT, sd.AT_BALL]], [5.3966, 5.8],
                               atol=1e-3)
    path = sd._action(sd.PATH, np.zeros((4, 2)))
    assert int(deliberate_jit(sd.init(P), pl, P, F, KHEPERA)[0]) == sd.AT_BALL
    assert int(deliberate_jit(running(path, sd.SHOOT), pl, P, F, KHEPERA)[0]) == sd.SHOOT
    # its path ended (idle): no bias
    assert int(deliberate_jit(running(sd._action(sd.IDLE), sd.SHOOT), pl, P, F, KHEPERA)[0]) == sd.AT_BALL
    q = sd.SoccerDeliberationParams(stability=0.0)
    assert int(deliberate_jit(running(path, sd.SHOOT, p=q), pl, q, F, KHEPERA)[0]) == sd.AT_BALL


# world 1: the ball lined up before the goal (shoot 6.58 wins); world 2: the ball behind the player before its own
# goal — go home line 6.25 outbids shoot's 8 − 3 · slow(5.4402 s) − 1.75 = 3.7069 (+ 1 while it rules)
WORLD1 = dict(pose=(0.7, 0.4, 0.0), ball=(0.9, 0.4))
WORLD2 = dict(pose=(0.7, 0.4, 0.0), ball=(0.15, 0.4))


def test_full_reactive_deliberation_interrupts_the_running_path_at_its_next_deliberation():
    p = sd.SoccerDeliberationParams(level="full")
    s = tick_jit(sd.init(p), play(**WORLD1), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.SHOOT and int(s.action.schema) == sd.PATH and float(s.due) == pytest.approx(0.512)
    s = tick_jit(s, play(**WORLD2, t=0.128), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.SHOOT  # not yet time
    s = tick_jit(s, play(**WORLD2, t=0.512), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.GO_HOME and int(s.action.schema) == sd.PATH


def test_the_half_wit_deliberates_only_when_idle_after_a_schema_ends_or_runs_its_maximum_time():
    p = sd.SoccerDeliberationParams(level="half")
    s = tick_jit(sd.init(p), play(**WORLD1), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.SHOOT
    s = tick_jit(s, play(**WORLD2, t=0.512), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.SHOOT and int(s.action.schema) == sd.PATH  # keeps running its path
    s, (v, w) = tick_jit(s, play(**WORLD2, t=4.096), p, F, KHEPERA)  # max_s: handed to stop
    assert int(s.action.schema) == sd.STOP and float(v) == 0.0 and float(w) == 0.0 and int(s.ruling) == sd.SHOOT
    s = tick_jit(s, play(**WORLD2, t=4.224), p, F, KHEPERA)[0]  # still: idle, so the deliberator runs
    assert int(s.ruling) == sd.GO_HOME and int(s.action.schema) == sd.PATH
    # the same with the full player: it re-plans every 0.512 s, so at 4.096 it is on its way home, not stopped
    q = sd.SoccerDeliberationParams(level="full")
    s = tick_jit(tick_jit(sd.init(q), play(**WORLD1), q, F, KHEPERA)[0], play(**WORLD2, t=4.096), q, F, KHEPERA)[0]
    assert int(s.ruling) == sd.GO_HOME and int(s.action.schema) == sd.PATH


def test_the_no_wit_alternates_offence_and_defence_without_looking_at_the_bids():
    p = sd.SoccerDeliberationParams(level="none")
    s = tick_jit(sd.init(p), play(**WORLD2), p, F, KHEPERA)[0]
    assert int(s.ruling) == sd.SHOOT  # although go home line bids 6.25 and shoot 3.71
    # the world held still: each schema runs max_s (4.096 s) and stops, or ends (the servo, behind the ball as
    # seen from G, at once); at each stop the next of the cycle
    seen, times = [int(s.ruling)], [0.0]
    for k in range(1, 120):
        before = int(s.cycle)
        s = tick_jit(s, play(**WORLD2, t=0.128 * k), p, F, KHEPERA)[0]
        if int(s.cycle) != before:
            seen.append(int(s.ruling))
            times.append(round(0.128 * k, 3))
    assert seen[:5] == [sd.SHOOT, sd.DEFEND_RED, sd.AT_BALL, sd.DEFEND_HOME, sd.SHOOT]
    # shoot 0 → stop at 4.096 → idle 4.224; defend red → stop 8.32 → 8.448; servo ends at once → idle 8.576
    assert times[:4] == [0.0, 4.224, 8.448, 8.576]


def test_every_level_deliberates_at_once_when_the_executor_is_idle_and_stop_waits_for_stillness():
    for level in sd.LEVELS:
        p = sd.SoccerDeliberationParams(level=level)
        s = running(sd._action(sd.STOP), sd.AT_BALL, p=p)
        s = tick_jit(s, play(**WORLD1, t=1.0, velocity=(0.05, 0.0)), p, F, KHEPERA)[0]  # still moving: stop stays
        assert int(s.action.schema) == sd.STOP and int(s.ruling) == sd.AT_BALL
        s = tick_jit(s, play(**WORLD1, t=1.128), p, F, KHEPERA)[0]  # still: idle, deliberated at once
        assert int(s.action.schema) != sd.IDLE and int(s.ruling) != sd.AT_BALL


# ------------------------------------------------------------------------------------------ the executor

def test_stop_and_idle_send_zero():
    execute = jax.jit(sd.execute, static_argnames=("p", "field", "robot"))
    for schema in (sd.STOP, sd.IDLE):
        after, _, (v, w) = execute(running(sd._action(schema), sd.WAIT), play(**WORLD1, t=1.0, velocity=(0.1, 0.0)),
                                   P, F, KHEPERA)
        assert int(after) == schema and float(v) == 0.0 and float(w) == 0.0
    # through the whole tick: a stop while the player still moves sends zero and stays a stop
    s, w = step(running(sd._action(sd.STOP), sd.WAIT), play(**WORLD1, t=1.0, velocity=(0.1, 0.0)))
    assert int(s.action.schema) == sd.STOP and np.array_equal(w, [0.0, 0.0])


def test_the_servo_turns_towards_the_ball_at_full_speed():
    # ball 45° to the left at (0.6, 0.5): v = c* cos 45° = 0.11314, ω = 4 · π/4 = 3.1416; wheels v ∓ ω · 0.0265
    # = (0.02989, 0.19639), scaled by 0.16 / 0.19639 → (0.02435, 0.16): the right wheel faster, a left turn
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL), play((0.5, 0.4, 0.0), (0.6, 0.5), t=1.0))
    np.testing.assert_allclose(w, [0.02435, 0.16], atol=1e-4)
    assert int(s.action.schema) == sd.SERVO
    # mirror image: the left wheel faster
    _, w = step(running(sd._action(sd.SERVO), sd.AT_BALL), play((0.5, 0.4, 0.0), (0.6, 0.3), t=1.0))
    np.testing.assert_allclose(w, [0.16, 0.02435], atol=1e-4)


def test_the_servo_leads_a_rolling_ball_by_its_rolling_model():
    # ball (0.6, 0.4) rolling up at 0.2 m/s, 0.1 m away: 0.625 s to get there, the ball then 0.125 − 0.15 ·
    # 0.625² / 2 = 0.09570 further, at (0.6, 0.49570): α = atan2(0.0957, 0.1) = 0.76345 → v = 0.11559,
    # ω = 3.0538; v ∓ ω · 0.0265 = (0.03467, 0.19652), scaled 0.16 / 0.19652 → (0.02823, 0.16)
    _, w = step(running(sd._action(sd.SERVO), sd.AT_BALL), play((0.5, 0.4, 0.0), (0.6, 0.4, 0.0, 0.2), t=1.0))
    np.testing.assert_allclose(w, [0.02823, 0.16], atol=1e-4)


def test_the_servo_ends_when_the_ball_is_struck_or_no_longer_advances():
    # touching (0.045 apart) and the ball leaving faster than the player: struck → stop, zero
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.555, 0.4, 0.0), (0.6, 0.4, 0.2, 0.0), t=1.0, velocity=(0.16, 0.0)))
    assert int(s.action.schema) == sd.STOP and np.array_equal(w, [0.0, 0.0])
    # touching a still ball, the player driving into it: not yet struck
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.555, 0.4, 0.0), (0.6, 0.4), t=1.0, velocity=(0.16, 0.0)))
    assert int(s.action.schema) == sd.SERVO and w[0] == pytest.approx(0.16)
    # the player past the ball (between it and G): striking it would not advance it
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL), play((0.7, 0.4, math.pi), (0.6, 0.4), t=1.0))
    assert int(s.action.schema) == sd.STOP and np.array_equal(w, [0.0, 0.0])


def test_defend_stands_between_the_ball_and_the_net_and_intercepts_a_ball_that_would_pass_it():
    # line x = 0.05, ball (0.6, 0.6): on the line from H = (0, 0.4) to the ball, y = 0.4 + 0.2 · 0.05 / 0.6 = 0.41667
    np.testing.assert_allclose(np.asarray(defend_jit(play((0.05, 0.3, 0.0), (0.6, 0.6)), 0.05, P, F, KHEPERA)),
                               [0.05, 0.41667], atol=1e-5)
    # ball (0.3, 0.4) rolling home at (−0.3, −0.1): 0.26352 m to the line, it rolls 0.31623² / 0.3 = 0.33333 m
    # before stopping, so it crosses at y = 0.4 − 0.1 · 0.25/0.3 = 0.31667, 8.3 cm from the player: intercept
    np.testing.assert_allclose(np.asarray(defend_jit(play((0.05, 0.4, 0.0), (0.3, 0.4, -0.3, -0.1)), 0.05, P, F,
                                                     KHEPERA)), [0.05, 0.31667], atol=1e-5)
    # the same ball at half the speed stops 0.08333 m on, short of the line: stay between (y = 0.4)
    np.testing.assert_allclose(np.asarray(defend_jit(play((0.05, 0.4, 0.0), (0.3, 0.4, -0.15, -0.05)), 0.05, P, F,
                                                     KHEPERA)), [0.05, 0.4], atol=1e-5)
    # a ball behind the line (0.02, 0.3), below the centre: beside it on the net's side, c + 5 mm = 0.05 above
    np.testing.assert_allclose(np.asarray(defend_jit(play((0.05, 0.5, 0.0), (0.02, 0.3)), 0.05, P, F, KHEPERA)),
                               [0.05, 0.35], atol=1e-5)


def test_defend_drives_along_its_line_forwards_or_backwards_and_turns_along_it_when_there():
    home = sd._action(sd.DEFEND, line=0.05)
    # facing +y at (0.05, 0.3), the point (0.05, 0.41667) straight ahead 0.11667 m: min(c*, 0.1167/0.5) = c*
    _, w = step(running(home, sd.DEFEND_HOME), play((0.05, 0.3, math.pi / 2), (0.6, 0.6), t=1.0))
    np.testing.assert_allclose(w, [0.16, 0.16], atol=1e-4)
    # the point (0.05, 0.38333) behind, 0.06667 m: backwards at 0.06667 / 0.5 = 0.13333
    _, w = step(running(home, sd.DEFEND_HOME), play((0.05, 0.45, math.pi / 2), (0.6, 0.2), t=1.0))
    np.testing.assert_allclose(w, [-0.13333, -0.13333], atol=1e-4)
    # at the point, heading 0.3: turns to π/2 on the spot, ω = 4 · (π/2 − 0.3) = 5.0832, wheels ∓ 0.13470
    _, w = step(running(home, sd.DEFEND_HOME), play((0.05, 0.41667, 0.3), (0.6, 0.6), t=1.0))
    np.testing.assert_allclose(w, [-0.13470, 0.13470], atol=1e-4)


def test_follow_path_slows_to_the_approach_point_then_drives_through_the_ball_and_stops_after_its_end():
    path = sd._action(sd.PATH, [[0.7, 0.4], [0.0, 0.0], [0.82, 0.4], [1.05, 0.4]])
    # 4 cm before A: 0.04 / 0.5 = 0.08 m/s
    s, w = step(running(path, sd.SHOOT), play((0.78, 0.4, 0.0), (0.9, 0.4), t=1.0))
    np.testing.assert_allclose(w, [0.08, 0.08], atol=1e-5)
    assert int(s.waypoint) == 2
    # 1 cm before A: passed (within 1.5 cm); on to T at full speed
    s, w = step(running(path, sd.SHOOT), play((0.81, 0.4, 0.0), (0.9, 0.4), t=1.0))
    np.testing.assert_allclose(w, [0.16, 0.16], atol=1e-5)
    assert int(s.waypoint) == 3 and int(s.action.schema) == sd.PATH
    # past A on the line and 5 mm to its left: A passed; T lies to the right, the left wheel faster
    s, w = step(running(path, sd.SHOOT), play((0.85, 0.405, 0.0), (0.9, 0.4), t=1.0))
    assert int(s.waypoint) == 3 and w[0] > w[1]
    # past the end: the path is done → stop, zero
    s, w = step(running(path, sd.SHOOT, waypoint=3), play((1.06, 0.4, 0.0), (1.15, 0.4), t=1.0))
    assert int(s.waypoint) == 4 and int(s.action.schema) == sd.STOP and np.array_equal(w, [0.0, 0.0])


def test_collision_detection_stops_driving_into_the_opponent_but_not_turning_on_the_spot():
    # servo at the ball (0.7, 0.4) with the opponent's body 5 mm ahead (centres 0.055 apart): stop
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.5, 0.4, 0.0), (0.7, 0.4), opp=(0.555, 0.4, math.pi, 0.0, 0.0), t=1.0))
    assert int(s.action.schema) == sd.STOP and np.array_equal(w, [0.0, 0.0])
    # 2.5 cm between the bodies, within halt (1 cm) + a tick's travel at c* (2.05 cm) of the corridor: stop
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.5, 0.4, 0.0), (0.7, 0.4), opp=(0.575, 0.4, math.pi, 0.0, 0.0), t=1.0))
    assert int(s.action.schema) == sd.STOP
    # 4 cm between them: beyond 3.05 cm, drives on at c*
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.5, 0.4, 0.0), (0.7, 0.4), opp=(0.59, 0.4, math.pi, 0.0, 0.0), t=1.0))
    assert int(s.action.schema) == sd.SERVO
    np.testing.assert_allclose(w, [0.16, 0.16], atol=1e-5)
    # the same opponent 4 cm beside the corridor's edge (centre 0.075 to the left): drives on
    s, w = step(running(sd._action(sd.SERVO), sd.AT_BALL),
                play((0.5, 0.4, 0.0), (0.7, 0.4), opp=(0.555, 0.475, math.pi, 0.0, 0.0), t=1.0))
    assert int(s.action.schema) == sd.SERVO
    # the goalie turning on the spot with the opponent touching it: it turns
    s, w = step(running(sd._action(sd.DEFEND, line=0.05), sd.DEFEND_HOME),
                play((0.05, 0.41667, 0.3), (0.6, 0.6), opp=(0.1, 0.41667, math.pi, 0.0, 0.0), t=1.0))
    assert int(s.action.schema) == sd.DEFEND
    np.testing.assert_allclose(w, [-0.13470, 0.13470], atol=1e-4)


def test_the_ball_rolls_on_slowing_until_it_stops_and_stays_on_the_field():
    ahead = jax.jit(sd.ahead, static_argnames=("p", "field"))
    ball = jnp.asarray([0.5, 0.4, 0.3, 0.0])  # stops after 0.3/0.15 = 2 s, 0.3² / 0.3 = 0.3 m on
    np.testing.assert_allclose(np.asarray(ahead(ball, 1.0, P, F)), [0.5 + 0.3 - 0.075, 0.4], atol=1e-6)
    np.testing.assert_allclose(np.asarray(ahead(ball, 5.0, P, F)), [0.8, 0.4], atol=1e-6)
    # from (1.1, 0.4) it would stop at 1.4: kept at 1.2 − 0.02
    np.testing.assert_allclose(np.asarray(ahead(jnp.asarray([1.1, 0.4, 0.3, 0.0]), 5.0, P, F)), [1.18, 0.4],
                               atol=1e-6)


# ------------------------------------------------------------------------------------------ contract

@pytest.mark.parametrize("level", sd.LEVELS)
def test_wheels_are_finite_and_within_c_star_on_random_and_degenerate_plays(level):
    rng = np.random.default_rng(0)
    p = sd.SoccerDeliberationParams(level=level)
    c = sd.build(p)
    s = c.init()
    t = 0.0
    for k in range(300):
        pose = (rng.uniform(0.0, 1.2), rng.uniform(0.0, 0.8), rng.uniform(-math.pi, math.pi))
        ball = (rng.uniform(-0.05, 1.25), rng.uniform(0.0, 0.8), *rng.normal(0.0, 0.15, 2))
        opp = (rng.uniform(0.0, 1.2), rng.uniform(0.0, 0.8), rng.uniform(-math.pi, math.pi), *rng.normal(0, 0.1, 2))
        if k % 10 == 0:  # degenerate: ball on the player, opponent on the player, all still
            ball, opp = (pose[0], pose[1], 0.0, 0.0), (pose[0], pose[1], 0.0, 0.0, 0.0)
        s, w = c.step(s, play(pose, ball, opp, t=t, velocity=tuple(rng.normal(0.0, 0.08, 2))))
        w = np.asarray(w)
        assert np.all(np.isfinite(w)) and np.all(np.abs(w) <= C_STAR + 1e-6), (k, w)
        assert all(np.all(np.isfinite(np.asarray(a))) for a in jax.tree.leaves(s.action))
        t += float(rng.choice([0.128, 0.512, 4.096]))


def test_parameters_say_their_units_and_levels_and_refuse_bad_values():
    from dataclasses import fields

    for f in fields(sd.SoccerDeliberationParams):
        assert f.metadata["help"].endswith(")") or "choices" in f.metadata, f.name
    level = next(f for f in fields(sd.SoccerDeliberationParams) if f.name == "level")
    assert level.default == "full" and level.metadata["choices"] == ("full", "half", "none")
    for bad in ({"level": "quarter"}, {"period": 0.0}, {"stability": -1.0}, {"sensors": "middle"}):
        with pytest.raises(ValueError):
            sd.SoccerDeliberationParams(**bad)


def test_build_gives_a_controller_on_the_chosen_ring_starting_idle_with_nobody_ruling():
    c = sd.build(sd.SoccerDeliberationParams(sensors="short"), spec="deliberation:sensors=short")
    assert c.name == "deliberation" and c.spec == "deliberation:sensors=short"
    assert c.sensors == KHEPERA.short_range and c.robot == KHEPERA
    s = c.init()
    assert int(s.ruling) == -1 and int(s.action.schema) == sd.IDLE
