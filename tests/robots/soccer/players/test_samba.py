"""Samba for Soccer (Riekki 1999, ch. 5) on hand-built plays: the ball map, the kick through the ball, going
round a ball the robot stands in front of, the AvoidOpp map, the defensive location, the arbiter's
conditions, and bounded, finite wheels. Every expected number is worked out by hand in the comments.

The default grid is 36 directions × 4 speeds: direction i is 10°·i (wrapped to (−180°, 180°]), speed j is
0.04·(j + 1) m/s. The weight curve is w(t) = exp(−(t − 0.128)/10) for t > 0.128 s. Touching distance robot–
ball R = 0.025 + 0.02 = 0.045 m; the kick point is R + gap = 0.065 m behind the ball.
"""

import dataclasses
import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots import kinematics as kin
from robots.controllers.base import Controller
from robots.params import KHEPERA
from robots.soccer.field import Field
from robots.soccer.play import Play
from robots.soccer.players import samba as ss

P = ss.SoccerSambaParams()
FIELD = Field()
FAR = (1.0, 0.7, 0.0, 0.0, 0.0)  # an opponent out of the way
DEG = math.pi / 180.0
C = 0.16


def w(t):
    """The weight curve, by hand."""
    return math.exp(-(t - 0.128) / 10.0)


def play(pose, ball, opponent=FAR):
    return Play(jnp.float32(0.0), jnp.full(12, jnp.inf, jnp.float32), jnp.asarray(pose, jnp.float32),
                jnp.zeros(2, jnp.float32), jnp.asarray(ball, jnp.float32), jnp.asarray(opponent, jnp.float32))


@partial(jax.jit, static_argnames=("p",))
def tick(state, pl, p=P):
    return ss.maps(state, pl, p, FIELD, KHEPERA)


def fresh(p=P, task=-1):
    return ss.init(p)._replace(task=jnp.asarray(task, jnp.int32))


def index(deg, n=36):
    return round(deg / (360 / n)) % n


def heaviest(m):
    k = int(np.argmax(np.asarray(m)))
    return k // m.shape[1], k % m.shape[1]


# ------------------------------------------------------------------------------------------------ GotoBall

def test_the_ball_map_points_at_a_still_ball_at_full_speed_whichever_way_the_robot_faces():
    # ball 0.3 m along +x; the enlarged ball's edge is 0.3 − 0.045 = 0.255 m away: t = 0.255/0.16 = 1.59375 s
    for theta, bearing in ((0.0, 0.0), (math.pi / 2, -90.0), (math.pi, 180.0)):
        t = tick(fresh(), play((0.3, 0.4, theta), (0.6, 0.4, 0.0, 0.0)))
        i, j = heaviest(t.goto_ball)
        assert (i, j) == (index(bearing), 3)
        assert float(t.goto_ball[i, j]) == pytest.approx(w(1.59375), abs=1e-4)  # 0.86366


def test_the_ball_map_leads_a_rolling_ball():
    # robot (0.3, 0.3) facing +x, ball (0.5, 0.3) rolling +y at 0.08 m/s. The earliest touch solves
    # |p + u t| = 0.16 t + 0.045 with p = (0.2, 0), u = (0, 0.08): 0.0192 t² + 0.0144 t − 0.037975 = 0,
    # t = 1.0805 s, the ball then at C = (0.2, 0.0864): 23.4° left. In the object sector (half-width
    # asin(0.045/0.2179) = 11.9°) the ray to the enlarged ball at C is 0.17438 m long at 20° (3.37° off) and
    # 0.17913 m at 30° (6.63° off): 20° at full speed is heaviest, t = 0.17438/0.16 = 1.0899 s — 20° ahead of
    # the ball's bearing (0°), towards where it rolls.
    t = tick(fresh(), play((0.3, 0.3, 0.0), (0.5, 0.3, 0.0, 0.08)))
    assert heaviest(t.goto_ball) == (2, 3)
    assert float(t.goto_ball[2, 3]) == pytest.approx(w(1.0899), abs=1e-3)  # 0.9083
    # rolling the other way the lead mirrors
    t = tick(fresh(), play((0.3, 0.3, 0.0), (0.5, 0.3, 0.0, -0.08)))
    assert heaviest(t.goto_ball) == (index(-20.0), 3)


# ------------------------------------------------------------------------------------------------ kicking

def test_with_the_ball_between_robot_and_goal_it_drives_through_the_ball_at_the_goal():
    # robot (0.6, 0.4) facing +x, ball (0.7, 0.4). Straight ahead the touch is head-on after 0.055/s: n = +x,
    # the ball leaves at 1.7·s along +x and crosses x = 1.2 at y = 0.4, inside the posts (0.28, 0.52) less
    # 0.02, after 0.5/(1.7 s). At 10° the robot's centre touches at 0.05696 m along the ray, (0.0561, 0.0099);
    # n = ((0.1, 0) − that)/0.045 = (0.9756, −0.2198), −12.7°: the ball would cross x = 1.2 at
    # 0.4 − 0.5 tan 12.7° = 0.287 < 0.30. So only straight ahead is in make_goal, weighing w(0.055/s + 0.5/(1.7 s)):
    # at 0.16 m/s w(0.34375 + 1.83824) = 0.8143.
    t = tick(fresh(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0)))
    mg = np.asarray(t.make_goal)
    assert np.all(mg[1:] == 0.0)
    assert mg[0] == pytest.approx([w(0.055 / s + 0.5 / (1.7 * s)) for s in (0.04, 0.08, 0.12, 0.16)], abs=1e-4)
    # ±10° send it within 45° of the goal: dribble, GotoBall's weights there
    assert np.asarray(t.dribble)[[1, 35], 3] == pytest.approx(np.asarray(t.goto_ball)[[1, 35], 3])
    assert np.all(np.asarray(t.dribble)[[1, 35], 3] > 0)
    assert int(t.task) == 0 and float(t.direction) == pytest.approx(0.0, abs=1e-6)
    assert float(t.speed) == pytest.approx(C)
    _, wheels = ss.step(fresh(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0)), p=P)
    assert np.asarray(wheels) == pytest.approx([C, C], abs=1e-6)


def test_a_keeper_on_the_line_blocks_the_shot_but_not_the_push():
    # The opponent at (0.78, 0.4), just behind the ball (0.7, 0.4); robot (0.6, 0.4) facing +x.
    # AvoidOpp: the robot would hit it after (0.18 − 0.055)/0.16 = 0.78125 s — after touching the ball at
    # 0.34375 s, so the kick maps' AvoidOpp (collisions before the touch) leaves it out (Fig. 52: the ball is
    # reached first). DontKicktoOpp: the ball, kicked at 0.272 m/s, meets the keeper's disc (0.045 m) after
    # (0.08 − 0.045)/0.272 = 0.1287 s: −w(0.4724) = −0.9662, heavier than the shot's w(2.182) = 0.8143 (Fig. 57:
    # an opponent on the line blocks the kick). The push (dribble) is GotoBall's w(0.34375) = 0.9787.
    t = tick(fresh(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0), (0.78, 0.4, math.pi, 0.0, 0.0)))
    assert float(t.avoid_opp[0, 3]) == pytest.approx(-w(0.78125), abs=1e-4)
    assert float(t.dont_kick_opp[0, 3]) == pytest.approx(-w(0.34375 + 0.035 / 0.272), abs=1e-4)
    assert float(t.composite[0, 0, 3]) == pytest.approx(-w(0.34375 + 0.035 / 0.272), abs=1e-4)
    assert float(t.composite[1, 0, 3]) == pytest.approx(w(0.34375), abs=1e-4)
    assert not bool(t.valid[0]) and int(t.task) == 1 and abs(float(t.direction)) < 1e-6
    # a keeper 7 cm off the ball's line (> 0.045) does not meet the ball: the shot is on
    t = tick(fresh(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0), (1.1, 0.47, math.pi, 0.0, 0.0)))
    assert float(t.dont_kick_opp[0, 3]) == 0.0 and int(t.task) == 0
    # 5 cm off the line at (0.78, 0.45): the ball passes it (0.05 > 0.045) but the robot, driving on after the
    # kick, would hit it (0.05 < 0.055) after (0.18 − √(0.055² − 0.05²))/0.16 = 0.9818 s: AvoidOpp has it, but
    # after the touch, so the kick stands at w(2.182).
    t = tick(fresh(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0), (0.78, 0.45, math.pi, 0.0, 0.0)))
    assert float(t.avoid_opp[0, 3]) == pytest.approx(-w(0.9818), abs=1e-3)
    assert float(t.dont_kick_opp[0, 3]) == 0.0
    assert float(t.composite[0, 0, 3]) == pytest.approx(w(0.34375 + 0.5 / 0.272), abs=1e-4)
    # (at −10° the touch sends the ball at +12.7°, 0.031 m from the opponent's centre: DontKicktoOpp inhibits
    # it, and the refined direction moves away from it, within half a bin)
    assert float(t.dont_kick_opp[35, 3]) < 0
    assert int(t.task) == 0 and 0.0 < float(t.direction) / DEG <= 5.0


def test_the_kick_is_read_in_the_robots_frame_and_waits_until_the_ball_is_near():
    # Facing +y at (0.6, 0.4) with the ball at (0.7, 0.4): the ball is at −90°, and only that direction sends
    # it at the goal. The make_goal composite is 0 at −80° and −100°, so the refined direction is −90° itself;
    # going sideways is a turn on the spot to the right: ω = 4·(−π/2), wheels ∓0.0265·ω = ±0.166, scaled to c*.
    t = tick(fresh(), play((0.6, 0.4, math.pi / 2), (0.7, 0.4, 0.0, 0.0)))
    mg = np.asarray(t.make_goal)
    assert np.flatnonzero(mg.any(axis=1)).tolist() == [index(-90.0)]
    assert mg[index(-90.0), 3] == pytest.approx(w(0.34375 + 0.5 / 0.272), abs=1e-4)
    assert int(t.task) == 0 and float(t.direction) == pytest.approx(-math.pi / 2, abs=1e-5)
    _, wheels = ss.step(fresh(), play((0.6, 0.4, math.pi / 2), (0.7, 0.4, 0.0, 0.0)), p=P)
    assert np.asarray(wheels) == pytest.approx([C, -C], abs=1e-5)
    # 0.4 m behind the ball on the line: the shot is on the map, w((0.4 − 0.045)/0.16 + 1.838) = w(4.057), but
    # the touch is 2.22 s away (> kick_s = 1 s): not a kick yet, the player goes for its kick point.
    t = tick(fresh(), play((0.3, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0)))
    assert float(t.make_goal[0, 3]) == pytest.approx(w(0.355 / 0.16 + 0.5 / 0.272), abs=1e-4)
    assert not bool(t.valid[0]) and not bool(t.valid[1]) and int(t.task) == 2


def test_the_kick_point_is_where_a_ball_too_fast_to_catch_will_stop():
    # ball (0.6, 0.4) rolling away along +x at 0.3 m/s, robot at (0.3, 0.4): faster than c*, it cannot be
    # touched before friction (0.15 m/s²) stops it after 2 s, 0.3²/0.3 = 0.3 m on, at (0.9, 0.4): the kick
    # point is 0.065 m behind that, (0.835, 0.4).
    t = tick(fresh(), play((0.3, 0.4, 0.0), (0.6, 0.4, 0.3, 0.0)))
    assert np.asarray(t.kick_point) == pytest.approx([0.835, 0.4], abs=1e-5)
    # ball (0.45, 0.4) rolling towards the robot at 0.1 m/s: touched after (0.15 − 0.045)/0.26 = 0.40 s, before
    # it stops (0.67 s): the kick point is behind the ball as it is now, (0.385, 0.4).
    t = tick(fresh(), play((0.3, 0.4, 0.0), (0.45, 0.4, -0.1, 0.0)))
    assert np.asarray(t.kick_point) == pytest.approx([0.385, 0.4], abs=1e-5)




def test_in_front_of_the_ball_it_turns_away_rather_than_push_the_ball_towards_its_own_goal():
    # robot (0.8, 0.4) facing −x, ball 0.1 m straight ahead at (0.7, 0.4): every touch pushes the ball
    # towards −x (n within 90° of the robot→ball direction), so no kick task is valid. The kick point
    # (0.635, 0.4) is straight ahead beyond the ball: goto_kick's heaviest action is straight ahead at full
    # speed (t = 0.165/0.16 = 1.03125 s), but the ball (touched at 0.1 − 0.05 = 0.05 m, 0.3125 s) comes first:
    # the catch_ball composite there is −w(0.3125).
    t = tick(fresh(), play((0.8, 0.4, math.pi), (0.7, 0.4, 0.0, 0.0)))
    assert not bool(t.valid[0]) and not bool(t.valid[1]) and int(t.task) == 2
    assert np.all(np.asarray(t.make_goal) == 0) and np.all(np.asarray(t.dribble) == 0)
    assert heaviest(t.goto_kick) == (0, 3) and float(t.goto_kick[0, 3]) == pytest.approx(w(1.03125), abs=1e-4)
    assert float(t.composite[2, 0, 3]) == pytest.approx(-w(0.3125), abs=1e-4)
    # The chosen direction passes beside the ball: the ball (grown by 5 mm) covers asin(0.05/0.1) = 30° either
    # side; 40° is the nearest free direction, refined away from the blocked 30° by at most half a bin.
    assert 30.0 < abs(float(t.direction)) / DEG <= 45.0
    # Even the slowest straight-ahead action touches within 1.5 s (0.05/0.04 = 1.25 s): it turns on the spot.
    assert float(t.speed) == 0.0
    _, wheels = ss.step(fresh(), play((0.8, 0.4, math.pi), (0.7, 0.4, 0.0, 0.0)), p=P)
    assert float(wheels[0]) == pytest.approx(-float(wheels[1]), abs=1e-6) and abs(float(wheels[0])) > 0.01


def test_in_front_of_a_still_ball_it_goes_round_and_touches_it_first_from_behind():
    """Integrate the robot (robots.kinematics, seeded slip) from in front of a still ball: its first touch — the
    centre within the touching distance 0.045 m of the ball's — comes from behind, the line of centres (the
    direction the ball is pushed) within 60° of +x: (0.7 − x)/gap > cos 60° = 0.5. Never towards its own goal."""
    step = jax.jit(partial(ss.step, p=P))
    rng = np.random.default_rng(0)
    state, robot = ss.init(P), kin.initial_state(np.array([0.8, 0.4, math.pi]))
    n = KHEPERA.substeps(0.128)
    for k in range(80):  # 10.2 s
        state, wheels = step(state, play(robot.pose, (0.7, 0.4, 0.0, 0.0)))
        robot, trace = kin.step(robot, np.asarray(wheels, float), rng.uniform(-1, 1, KHEPERA.noise_shape(0.128)), n)
        gaps = np.hypot(trace[:, 0] - 0.7, trace[:, 1] - 0.4)
        if np.any(gaps < 0.045):
            first = np.argmax(gaps < 0.045)
            assert (0.7 - trace[first, 0]) / gaps[first] > 0.5
            assert int(state.task) in (0, 1)  # a kick task made the touch
            break
    else:
        pytest.fail("the ball was never touched")
    assert k >= 8  # it took the way round: straight ahead it would touch in 0.055/0.16 = 0.34 s, tick 2


# ------------------------------------------------------------------------------------------------ AvoidOpp

def test_avoid_opp_inhibits_only_the_actions_that_collide():
    # robot (0.4, 0.4) facing +x, opponent still at (0.5, 0.4); discs touch at 0.025 + 0.025 + 0.005 = 0.055 m.
    # Straight ahead at 0.16 m/s: (0.1 − 0.055)/0.16 = 0.28125 s; at 0.08: 0.5625 s; at 0.04: 1.125 s, later
    # than the 1 s filter: 0. A direction collides when 0.1·sin δ < 0.055, |δ| < 33.4°: −30°…30°.
    t = tick(fresh(), play((0.4, 0.4, 0.0), (1.0, 0.2, 0.0, 0.0), (0.5, 0.4, math.pi, 0.0, 0.0)))
    a = np.asarray(t.avoid_opp)
    assert a[0, 3] == pytest.approx(-w(0.28125), abs=1e-4)  # −0.9848
    assert a[0, 1] == pytest.approx(-w(0.5625), abs=1e-4)  # −0.9575
    assert a[0, 0] == 0.0
    # at 20°: along 0.09397, off 0.03420; t = (0.09397 − √(0.055² − 0.0342²))/0.16 = 0.3183 s
    assert a[index(20.0), 3] == pytest.approx(-w(0.3183), abs=1e-3)
    colliding = [index(d) for d in range(-30, 31, 10)]
    assert np.all(a[colliding, 3] < -0.9)
    others = np.ones(36, bool)
    others[colliding] = False
    assert np.all(a[others] == 0.0)  # pointing away (180°) or passing by (40°, 90°): nothing
    assert a[index(180.0), 3] == 0.0 and a[index(40.0), 3] == 0.0
    # an opponent running away at c*: never caught, nothing inhibited
    t = tick(fresh(), play((0.4, 0.4, 0.0), (1.0, 0.2, 0.0, 0.0), (0.5, 0.4, 0.0, C, 0.0)))
    assert np.all(np.asarray(t.avoid_opp)[0] == 0.0)


# ------------------------------------------------------------------------------------------------ defending

def test_when_the_opponent_has_the_ball_near_the_home_goal_the_player_goes_to_the_defensive_location():
    # ball (0.15, 0.4), 0.15 m from the home goal's centre (0, 0.4). The opponent's kick point is the ball's far
    # side from our goal, (0.215, 0.4); the opponent at (0.30, 0.4) is there in 0.085/0.16 = 0.53 s (< 1 s).
    # Ours, (0.085, 0.4), is |(0.6, 0.15) − (0.085, 0.4)| = 0.5725 m away: 3.58 s. The opponent has the ball.
    # Defensive location: ½ · 0.15 = 0.075 m from the goal (≥ 0.06, ≤ 0.15 − 0.065): (0.075, 0.4).
    # From (0.6, 0.15) facing −x it is at world 154.54°, −25.46° in the robot frame, 0.5815 m away: OSA for a
    # point weighs −30° (4.54° off) over −20° (5.46° off): t = 0.5815/(0.16 cos 4.54°) = 3.6457 s.
    opp = (0.30, 0.4, math.pi, 0.0, 0.0)
    t = tick(fresh(), play((0.6, 0.15, math.pi), (0.15, 0.4, 0.0, 0.0), opp))
    assert np.asarray(t.defloc) == pytest.approx([0.075, 0.4], abs=1e-6)
    assert np.asarray(t.kick_point) == pytest.approx([0.085, 0.4], abs=1e-6)
    assert float(t.t_opp) == pytest.approx(0.53125, abs=1e-4) and float(t.t_me) == pytest.approx(3.578, abs=1e-3)
    assert heaviest(t.goto_defloc) == (index(-30.0), 3)
    assert float(t.goto_defloc[index(-30.0), 3]) == pytest.approx(w(3.6457), abs=1e-3)  # 0.7034
    assert not bool(t.valid[2]) and int(t.task) == 3 and float(t.speed) == pytest.approx(C)
    # The direction refined between −40°, −30° and −20° (weights 0.69583, 0.70344, 0.70308 by the times
    # 0.5815/(0.16 cos δ), δ = 14.54°, 4.54°, 5.46°): the parabola's vertex 0.5·(wl − wr)/(wl − 2w0 + wr) =
    # 0.4545 bins from −30°, −25.46° — where the location is.
    assert float(t.direction) / DEG == pytest.approx(-25.455, abs=0.05)
    # the same ball with the opponent far away: the player goes for its kick point instead
    t = tick(fresh(), play((0.6, 0.15, math.pi), (0.15, 0.4, 0.0, 0.0)))
    assert int(t.task) == 2
    # and with the opponent at the ball far from our goal, (0.9, 0.4), 0.9 m > 0.6 m: it contests the ball.
    # Opponent at (0.97, 0.4), its kick point (0.965, 0.4) 0.03 s away; ours (0.835, 0.4) from (0.5, 0.6):
    # 0.3902/0.16 = 2.44 s.
    t = tick(fresh(), play((0.5, 0.6, 0.0), (0.9, 0.4, 0.0, 0.0), (0.97, 0.4, math.pi, 0.0, 0.0)))
    assert float(t.t_opp) < float(t.t_me) and int(t.task) == 2


def test_at_the_defensive_location_it_stops_and_turns_to_face_the_ball():
    # ball (0.5, 0.4): defensive location ½ · 0.5 = 0.25 m out, (0.25, 0.4); the robot stands on it facing +y.
    # Every speed is above 0 / brake_s: the defloc map is empty. The opponent at (0.57, 0.4) is 0.005 m from its
    # kick point (0.565, 0.4), the robot 0.185 m from ours (0.435, 0.4): it has the ball, no catching. The
    # touch is (0.25 − 0.045)/0.16 = 1.28 s off: no kick. Left: turn to the ball, −90°, on the spot,
    # ω = −2π rad/s, wheels ±0.166 scaled to ±c*.
    t = tick(fresh(), play((0.25, 0.4, math.pi / 2), (0.5, 0.4, 0.0, 0.0), (0.57, 0.4, math.pi, 0.0, 0.0)))
    assert np.all(np.asarray(t.goto_defloc) == 0.0)
    assert np.asarray(t.valid).tolist() == [False, False, False, False, True] and int(t.task) == 4
    assert float(t.direction) == pytest.approx(-math.pi / 2, abs=1e-5) and float(t.speed) == 0.0
    _, wheels = ss.step(fresh(), play((0.25, 0.4, math.pi / 2), (0.5, 0.4, 0.0, 0.0), (0.57, 0.4, math.pi, 0.0, 0.0)),
                        p=P)
    assert np.asarray(wheels) == pytest.approx([C, -C], abs=1e-5)


def test_the_choice_between_catching_and_defending_holds_until_the_other_player_is_half_a_second_ahead():
    # ball (0.3, 0.4): our kick point (0.235, 0.4), the opponent's (0.365, 0.4). Robot 0.25 m above ours: t_me =
    # 1.5625 s; opponent 0.28 m above its own: t_opp = 1.75 s (threat_s raised to 3 s so that it counts). Fresh,
    # we are first: catch_ball. Defending last tick, the opponent keeps "having the ball" while t_opp <
    # t_me + 0.5 = 2.06 s: defloc. Touching the ball takes √(0.065² + 0.25²) − 0.045 = 0.213 m, 1.33 s > 1 s:
    # no kick.
    p = dataclasses.replace(P, threat_s=3.0)
    pl = play((0.235, 0.65, 0.0), (0.3, 0.4, 0.0, 0.0), (0.365, 0.68, -math.pi / 2, 0.0, 0.0))
    t = tick(fresh(p), pl, p)
    assert float(t.t_me) == pytest.approx(1.5625, abs=1e-4) and float(t.t_opp) == pytest.approx(1.75, abs=1e-4)
    assert int(t.task) == 2
    assert int(tick(fresh(p, task=3), pl, p).task) == 3
    assert int(tick(fresh(p, task=2), pl, p).task) == 2


# ------------------------------------------------------------------------------------------------ contract

def test_wheels_are_finite_and_within_the_wheel_limit_on_random_plays():
    rng = np.random.default_rng(0)
    step = jax.jit(partial(ss.step, p=P))
    state = ss.init(P)
    for _ in range(300):
        pose = (rng.uniform(0.0, 1.2), rng.uniform(0.0, 0.8), rng.uniform(-math.pi, math.pi))
        ball = (rng.uniform(-0.05, 1.25), rng.uniform(0.0, 0.8), *rng.normal(0.0, 0.15, 2))
        opp = (rng.uniform(0.0, 1.2), rng.uniform(0.0, 0.8), rng.uniform(-math.pi, math.pi), *rng.normal(0.0, 0.1, 2))
        if rng.uniform() < 0.2:  # degenerate: the ball on the robot, or the robot on its kick point
            ball = (pose[0], pose[1], 0.0, 0.0) if rng.uniform() < 0.5 else ball
            opp = (pose[0], pose[1], *opp[2:]) if rng.uniform() < 0.5 else opp
        state, wheels = step(state, play(pose, ball, opp))
        wheels = np.asarray(wheels)
        assert wheels.shape == (2,) and np.all(np.isfinite(wheels)) and np.all(np.abs(wheels) <= C + 1e-6)
        assert -1 <= int(state.task) < len(ss.TASKS)
    # degenerate plays: the ball on either goal's centre (no direction from the goal to the ball), the robot on
    # its kick point, the ball still on top of the robot
    for pose, ball in (((0.6, 0.4, 0.0), (1.2, 0.4, 0.0, 0.0)), ((0.6, 0.4, 0.0), (0.0, 0.4, 0.0, 0.0)),
                       ((0.635, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0)), ((0.5, 0.5, 1.0), (0.5, 0.5, 0.0, 0.0))):
        for task in range(-1, len(ss.TASKS)):
            _, wheels = step(fresh(task=task), play(pose, ball, (0.5, 0.5, 0.0, 0.0, 0.0)))
            assert np.all(np.isfinite(np.asarray(wheels))) and np.all(np.abs(np.asarray(wheels)) <= C + 1e-6)


def test_build_gives_a_jitted_controller_and_every_parameter_says_its_unit():
    ctl = ss.build(P)
    assert isinstance(ctl, Controller) and ctl.name == "samba" and ctl.spec == "samba" and ctl.params is P
    assert ctl.sensors == KHEPERA.long_range
    assert ss.build(dataclasses.replace(P, sensors="short"), spec="samba:x").sensors == KHEPERA.short_range
    state, wheels = ctl.step(ctl.init(), play((0.6, 0.4, 0.0), (0.7, 0.4, 0.0, 0.0)))
    assert int(state.task) == 0 and np.asarray(wheels) == pytest.approx([C, C], abs=1e-6)
    for f in dataclasses.fields(ss.SoccerSambaParams):
        assert f.default is not dataclasses.MISSING and "(" in f.metadata["help"], f.name
    assert dataclasses.fields(ss.SoccerSambaParams)[0].metadata["choices"] == ("short", "long")
    with pytest.raises(ValueError):
        ss.SoccerSambaParams(sensors="medium")
