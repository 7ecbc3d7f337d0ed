"""Reactive deliberation (Sahota ch. 3, §4.3): each behaviour's bid and action, which bid wins, how the three
levels deliberate, and what the executor's schemas do — on hand-built observations, worked out by hand."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.controllers import deliberation as rd
from robots.controllers import memory as mem
from robots.controllers.discrete import sense
from robots.params import KHEPERA, LONG_RANGE
from tests.robots.controllers.observations import long_ring, observation

P = rd.DeliberationParams()
ANGLES = jnp.asarray(LONG_RANGE.angles, jnp.float32)
R = KHEPERA.radius


@jax.jit
def points_of(obs):
    _, pts, valid = sense(mem.empty(P.memory_points), obs, ANGLES, radius=R, range_m=LONG_RANGE.range_m, merge=P.merge,
                          memory_s=P.memory_s)
    return pts, valid


bid_jit = jax.jit(rd.bid, static_argnames=("p", "radius"))
tick_jit = jax.jit(rd.tick, static_argnames=("p", "robot"))
execute_jit = jax.jit(rd.execute, static_argnames=("p", "robot"))


def bids(ir, target=(0.0, 0.3), waited=0.0, **kw):
    obs = observation(ir, target=target, **kw)
    return bid_jit(*points_of(obs), obs, jnp.float32(waited), P, R)


def test_in_the_open_go_to_checkpoint_wins_with_the_servo():
    b = bids(long_ring())
    np.testing.assert_allclose(np.asarray(b.bids), [5.0, 2.0, 0.0, 0.0])
    assert int(b.actions.schema[rd.GOTO]) == rd.SERVO


def test_a_blocked_way_makes_go_round_bid_highest_with_a_detour_on_the_freer_side():
    # the point (0.1, 0): free 0.1 − 0.035 = 0.065 of the 0.3 m, b = 0.7833: goto 5 − 5b = 1.083, round 2 + 6b = 6.7
    b = bids(long_ring(s0=0.075))
    np.testing.assert_allclose(np.asarray(b.bids), [1.0833, 6.7, 0.0, 0.0], atol=1e-3)
    assert int(b.actions.schema[rd.ROUND]) == rd.PATH
    # detour 8 cm beside the blockage (0.065 along the line): both sides free, the left first; then the checkpoint
    np.testing.assert_allclose(np.asarray(b.actions.path[rd.ROUND]), [[0.565, 0.58], [0.8, 0.5]], atol=1e-4)
    # a point 6 cm out at 60° left, (0.03, 0.052), lies across the left detour's way (free 2.6 of its 10.3 cm)
    b = bids(long_ring(s0=0.075, s2=0.035))
    np.testing.assert_allclose(np.asarray(b.actions.path[rd.ROUND]), [[0.565, 0.42], [0.8, 0.5]], atol=1e-4)


def test_something_touching_close_ahead_makes_back_away_bid_nine():
    b = bids(long_ring(s0=0.005))  # 5 mm from the body, within close (1 cm)
    assert float(b.bids[rd.BACK]) == 9.0 and float(b.bids[rd.BACK]) == float(np.max(b.bids))
    assert int(b.actions.schema[rd.BACK]) == rd.PATH and bool(b.actions.backwards[rd.BACK])
    np.testing.assert_allclose(np.asarray(b.actions.path[rd.BACK]), [[0.45, 0.5], [0.45, 0.5]], atol=1e-6)


def test_wait_bids_while_a_mover_is_in_the_way_and_gets_bored():
    mover = [[0.6, 0.5, 0.0, 0.1, 0.02]]  # 5.5 cm from the body, on the line to the checkpoint
    assert float(bids(long_ring(), markers=mover).bids[rd.WAIT]) == 7.0
    assert float(bids(long_ring(), markers=mover, waited=2.0).bids[rd.WAIT]) == pytest.approx(3.5)
    assert float(bids(long_ring(), markers=[[0.5, 0.7, 0.0, 0.1, 0.02]]).bids[rd.WAIT]) == 0.0  # 90° off the line


@pytest.mark.parametrize("level, ruling, schema", [("full", rd.ROUND, rd.PATH), ("half", rd.GOTO, rd.SERVO),
                                                   ("none", rd.GOTO, rd.SERVO)])
def test_only_full_deliberation_interrupts_a_running_schema(level, ruling, schema):
    p = rd.DeliberationParams(level=level)
    state, _ = tick_jit(rd.init(p), observation(long_ring(), target=(0.0, 0.3)), ANGLES, p, KHEPERA)
    assert int(state.ruling) == rd.GOTO and int(state.action.schema) == rd.SERVO
    # 0.512 s on (the next deliberation), the way is blocked: go round outbids (6.7 vs 1.08 + 1 of stability)
    state, _ = tick_jit(state, observation(long_ring(s0=0.075), target=(0.0, 0.3), t=0.512), ANGLES, p, KHEPERA)
    assert int(state.ruling) == ruling and int(state.action.schema) == schema


def test_no_wit_takes_the_next_behaviour_of_its_cycle_without_looking():
    p = rd.DeliberationParams(level="none")
    state, _ = tick_jit(rd.init(p), observation(long_ring()), ANGLES, p, KHEPERA)
    state, _ = tick_jit(state, observation(long_ring(), t=4.2), ANGLES, p, KHEPERA)  # the servo ran max_s
    assert int(state.ruling) == rd.ROUND  # although go to checkpoint bids 5 and go round 2
    q = rd.DeliberationParams(level="half")
    state, _ = tick_jit(rd.init(q), observation(long_ring()), ANGLES, q, KHEPERA)
    state, _ = tick_jit(state, observation(long_ring(), t=4.2), ANGLES, q, KHEPERA)
    assert int(state.ruling) == rd.GOTO


def executor(action, ir=None, waypoint=0, **kw):
    obs = observation(long_ring() if ir is None else ir, target=(0.0, 0.3), **kw)
    state = rd.init(P)._replace(action=action, waypoint=jnp.int32(waypoint))
    return execute_jit(state, *points_of(obs), obs, P, KHEPERA)


def test_follow_path_passes_a_waypoint_within_a_centimetre_and_a_half_and_drives_on_to_the_next():
    path = rd._action(rd.PATH, [[0.51, 0.5], [0.8, 0.5]])
    action, i, (v, w) = executor(path)  # 1 cm from the first: passed
    assert int(i) == 1 and int(action.schema) == rd.PATH
    assert float(v) == pytest.approx(0.16) and float(w) == pytest.approx(0.0, abs=1e-6)  # 0.3 m / 0.5 s > c*
    action, i, (v, w) = executor(path, waypoint=1, pose=(0.79, 0.5, 0.0))
    assert int(i) == 2 and int(action.schema) == rd.STOP and float(v) == 0.0  # the last passed: stop


def test_stop_hands_over_to_idle_and_collision_detection_stops_the_servo():
    action, _, (v, w) = executor(rd._action(rd.STOP))
    assert int(action.schema) == rd.IDLE and float(v) == 0.0 and float(w) == 0.0
    action, _, (v, _) = executor(rd._action(rd.SERVO))
    assert int(action.schema) == rd.SERVO and float(v) == pytest.approx(0.16)
    action, _, (v, _) = executor(rd._action(rd.SERVO), ir=long_ring(s0=0.005))  # 5 mm ahead, within halt (8 mm)
    assert int(action.schema) == rd.STOP and float(v) == 0.0


def test_the_ruling_behaviour_keeps_control_by_its_stability_bias():
    # checkpoint 0.2 m ahead, a point at 0.171 m: free 0.136, b = 0.32: go round 2 + 6b = 3.92 outbids go to
    # checkpoint's 5 − 5b = 3.4 — but not 3.4 + 1 while go to checkpoint rules
    state, _ = tick_jit(rd.init(P), observation(long_ring(), target=(0.0, 0.2)), ANGLES, P, KHEPERA)
    blocked = observation(long_ring(s0=0.146), target=(0.0, 0.2), t=0.512)
    np.testing.assert_allclose(np.asarray(bids(long_ring(s0=0.146), target=(0.0, 0.2)).bids[:2]), [3.4, 3.92], atol=1e-3)
    kept, _ = tick_jit(state, blocked, ANGLES, P, KHEPERA)
    assert int(kept.ruling) == rd.GOTO
    fresh, _ = tick_jit(rd.init(P), blocked, ANGLES, P, KHEPERA)  # nobody rules yet: the higher bid wins
    assert int(fresh.ruling) == rd.ROUND


def test_a_ruling_go_round_plans_afresh_when_its_leg_becomes_blocked():
    deliberate = jax.jit(rd.deliberate, static_argnames=("p", "radius"))
    running = rd.init(P)._replace(ruling=jnp.int32(rd.ROUND), action=rd._action(rd.PATH, [[0.7, 0.5], [0.8, 0.6]]))
    open_way = observation(long_ring(), target=(0.0, 0.3))
    ruling, action, new = deliberate(running, *points_of(open_way), open_way, P, R)
    assert int(ruling) == rd.GOTO and bool(new)  # nothing in the way: go to checkpoint outbids (5 vs 2 + 1)
    # the point (0.1, 0) lies on the leg to (0.7, 0.5): go round wins again (6.7) and replans its detour
    blocked = observation(long_ring(s0=0.075), target=(0.0, 0.3))
    ruling, action, new = deliberate(running, *points_of(blocked), blocked, P, R)
    assert int(ruling) == rd.ROUND and bool(new)
    np.testing.assert_allclose(np.asarray(action.path), [[0.565, 0.58], [0.8, 0.5]], atol=1e-4)
    # a leg that stays free keeps the running path
    aside = rd.init(P)._replace(ruling=jnp.int32(rd.ROUND), action=rd._action(rd.PATH, [[0.5, 0.7], [0.8, 0.6]]))
    ruling, action, new = deliberate(aside, *points_of(blocked), blocked, P, R)
    assert int(ruling) == rd.ROUND and not bool(new)
    np.testing.assert_allclose(np.asarray(action.path), [[0.5, 0.7], [0.8, 0.6]], atol=1e-6)


@pytest.mark.parametrize("alpha, schema, w", [
    (0.7, rd.SERVO, 4.0 * 0.7),  # 40° to turn: it turns on the spot (ω = turn_gain α) and the servo runs on
    (0.0, rd.STOP, 0.0),         # facing the way already: it stops, as collision detection always did
])
def test_collision_detection_stops_the_drive_but_lets_the_servo_turn_on_the_spot(alpha, schema, w):
    """A point 2 cm ahead of the body (past ``halt``, 1 cm) is in the corridor the servo would sweep this tick
    (0.16 cos 0.7 = 0.122 m/s: 1 + 1.6 cm). A disc turning on the spot sweeps nothing, so a servo that has 0.7 rad
    to turn keeps turning, without driving; one facing its checkpoint stops."""
    obs = observation(long_ring(s0=0.02), target=(alpha, 0.27))
    state = rd.init(P)._replace(action=rd._action(rd.SERVO))
    action, _, (v, turn) = execute_jit(state, *points_of(obs), obs, P, KHEPERA)
    assert int(action.schema) == schema and float(v) == 0.0
    assert float(turn) == pytest.approx(w, abs=1e-5)
