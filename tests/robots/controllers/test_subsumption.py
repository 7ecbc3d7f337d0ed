"""Subsumption (Arkin §4.3): which layer speaks, which suppresses which, what collide inhibits and when back
out starts — on hand-built observations, with the answers worked out from the module's rules."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.controllers import subsumption as sub
from robots.controllers.spec import parse_architecture
from robots.params import KHEPERA, LONG_RANGE
from tests.robots.controllers.observations import long_ring, observation

P = sub.SubsumptionParams()
ANGLES = jnp.asarray(LONG_RANGE.angles, jnp.float32)
layers = jax.jit(sub.layers, static_argnames=("p", "radius", "range_m"))


def tick(ir, target=(0.0, 0.3), state=None, p=P, **kw):
    state = sub.init(p) if state is None else state
    return layers(state, observation(ir, target=target, **kw), ANGLES, p, KHEPERA.radius, LONG_RANGE.range_m)


def wheels(ir, target=(0.0, 0.3), **kw):
    ctrl = parse_architecture("subsumption").build()
    return np.asarray(ctrl.step(ctrl.init(), observation(ir, target=target, **kw))[1])


def test_with_nothing_sensed_goto_suppresses_wander_and_cruises():
    _, t = tick(long_ring())
    assert int(t.layer) == sub.LAYERS.index("goto") and int(t.response) == sub.CRUISE and int(t.avoid) == -1
    np.testing.assert_allclose(wheels(long_ring()), [0.16, 0.16], atol=1e-6)


@pytest.mark.parametrize("alpha, d, final, response", [
    (0.0, 0.3, False, sub.CRUISE), (0.3, 0.3, False, sub.ARC_LEFT), (-0.3, 0.3, False, sub.ARC_RIGHT),
    (0.8, 0.3, False, sub.SPIN_LEFT), (-0.8, 0.3, False, sub.SPIN_RIGHT),  # |α| > spin_above 0.6
    (0.0, 0.03, False, sub.SLOW), (0.15, 0.03, False, sub.SLOW),  # within slow_within no arcs; |α| < fine 0.2
    (0.3, 0.03, False, sub.SPIN_LEFT), (0.0, 0.008, False, sub.CREEP),  # |α| > fine; within creep_within
    (0.0, 0.002, True, sub.STOP), (0.0, 0.002, False, sub.CREEP)])  # stops only at the goal
def test_goto_rules(alpha, d, final, response):
    _, t = tick(long_ring(), target=(alpha, d), final=final)
    assert int(t.goto) == response and int(t.response) == response


def test_avoid_suppresses_goto_and_turns_away_from_the_side_that_senses():
    # 2 cm out on the 30°-left sensor: the point (0.039, 0.0225) is in the corridor (|y| < 2.5 + 1.2 cm, 1.4 cm ahead)
    _, t = tick(long_ring(s1=0.02))
    assert int(t.layer) == 0 and int(t.avoid) == sub.SPIN_RIGHT and int(t.goto) == sub.CRUISE
    np.testing.assert_allclose(wheels(long_ring(s1=0.02)), [1.5 * 0.0265, -1.5 * 0.0265], atol=1e-6)
    _, t = tick(long_ring(s11=0.02))
    assert int(t.avoid) == sub.SPIN_LEFT
    # a jamb straight beside the body is not in its way: goto drives on
    _, t = tick(long_ring(s3=0.005, s9=0.005))
    assert int(t.layer) == 2 and int(t.response) == sub.CRUISE


def test_goto_suppresses_what_avoid_sees_beyond_the_checkpoint():
    # a point 3 cm ahead of the body: within near (4 cm), so avoid turns away ...
    _, t = tick(long_ring(s0=0.03))
    assert int(t.layer) == 0 and int(t.response) == sub.SPIN_RIGHT  # no side senses more: right
    # ... but with the goal 4 cm from the centre, avoid's reach is 1.5 cm and the point lies beyond the goal
    _, t = tick(long_ring(s0=0.03), target=(0.0, 0.04), final=True)
    assert int(t.avoid) == -1 and int(t.layer) == 2 and int(t.response) == sub.SLOW


def test_collide_inhibits_forward_motion_whatever_layer_drives():
    # 8 mm ahead, goal 3 cm from the centre: avoid's reach (5 mm) misses it, goto sends slow, collide (1 cm) halts it
    _, t = tick(long_ring(s0=0.008), target=(0.0, 0.03), final=True)
    assert int(t.response) == sub.SLOW and bool(t.halted)
    np.testing.assert_allclose(wheels(long_ring(s0=0.008), target=(0.0, 0.03), final=True), [0.0, 0.0], atol=1e-9)


def test_backout_starts_after_three_avoid_episodes_without_progress_then_turns_away():
    state, dt = sub.init(P), 0.128
    seen = [False, True, False, True, False, True]  # three episodes of avoid, the checkpoint never closer
    for k, on in enumerate(seen):
        state, t = tick(long_ring(s1=0.02) if on else long_ring(), state=state, t=k * dt)
        assert int(t.backout) == (-1 if k < 5 else sub.BACK)
    assert int(t.layer) == 3 and int(t.response) == sub.BACK
    state, t = tick(long_ring(), state=state, t=5 * dt + 1.1)  # back_s 1.024 over: the spin away from the left
    assert int(t.layer) == 3 and int(t.response) == sub.SPIN_RIGHT
    _, t = tick(long_ring(), state=state, t=5 * dt + 2.1)  # turn_s over: goto again
    assert int(t.layer) == 2


def test_progress_resets_the_count_of_avoid_episodes():
    state = sub.init(P)
    for k, (on, d) in enumerate([(False, 0.3), (True, 0.3), (False, 0.28), (True, 0.28), (False, 0.26), (True, 0.26)]):
        state, t = tick(long_ring(s1=0.02) if on else long_ring(), target=(0.0, d), state=state, t=k * 0.128)
    assert int(t.backout) == -1 and int(t.layer) == 0


@pytest.mark.parametrize("mover, response", [
    ((0.46, 0.47, 0.0, 0.1, 0.02), sub.CRUISE),  # from behind-right across the robot's line: drive on, out of it
    ((0.45, 0.5, 0.1, 0.0, 0.02), sub.SPIN_LEFT),  # straight from behind: the way out is its left, 90° off
    ((0.5, 0.45, 0.0, 0.1, 0.02), sub.BACK),  # straight from the right: its left is behind the robot
    ((0.5, 0.45, 0.0, -0.1, 0.02), -1),  # moving away: no threat
    ((0.44, 0.45, 0.0, 0.1, 0.02), -1)])  # closing, but its line passes 6 - 2 - 2.5 = 1.5 cm beside the body (> 1.2)
def test_runaway_gets_out_of_the_line_of_a_closing_mover(mover, response):
    _, t = tick(long_ring(), markers=[mover])
    assert int(t.avoid) == response


def test_runaway_starts_while_a_closing_mover_is_within_flee_of_the_body():
    """A mover of 2 cm radius 11 cm from the robot's centre (0.5, 0.5), straight from the right and closing: 6.5 cm
    between the bodies (11 - 2 - 2.5). Within the default 8 cm it backs out of its line; within 4 cm it does not
    yet."""
    mover = (0.5, 0.39, 0.0, 0.1, 0.02)
    _, t = tick(long_ring(), markers=[mover])
    assert P.flee == 0.08 and int(t.avoid) == sub.BACK
    _, t = tick(long_ring(), markers=[mover], p=sub.SubsumptionParams(flee=0.04))
    assert int(t.avoid) == -1


def test_a_closing_mover_suppresses_back_out_and_the_robot_gets_out_of_its_line():
    """Three avoid episodes without progress start back out (``back``); a mover then closing from straight behind
    (its line through the robot's centre) makes the runaway speak above it: the way out is the robot's left, 90°
    off, so ``spin-left`` — backing would drive into the mover's line."""
    state = sub.init(P)
    for k, on in enumerate([False, True, False, True, False, True]):
        state, t = tick(long_ring(s1=0.02) if on else long_ring(), state=state, t=k * 0.128)
    assert int(t.backout) == sub.BACK and int(t.response) == sub.BACK
    _, t = tick(long_ring(), state=state, t=6 * 0.128, markers=[(0.42, 0.5, 0.1, 0.0, 0.02)])
    assert int(t.backout) == sub.BACK and int(t.layer) == 0 and int(t.response) == sub.SPIN_LEFT


@pytest.mark.parametrize("mover, keep_back, response", [
    ((0.62, 0.5, 0.05, 0.0, 0.025), None, sub.STOP),  # 7 cm ahead, going on: stop until it has gone 8 cm on
    ((0.62, 0.5, 0.05, 0.0, 0.025), 0.0, sub.CRUISE),  # never: goto cruises after it
    ((0.62, 0.5, 0.05, 0.0, 0.025), 0.05, sub.CRUISE),  # 7 cm > 5 cm: not yet
    ((0.62, 0.56, 0.05, 0.0, 0.025), None, sub.CRUISE)])  # beside the corridor: its nearest point 4.9 cm off the line
def test_a_mover_ahead_going_on_stops_the_robot_until_it_has_gone(mover, keep_back, response):
    """The robot (radius 2.5 cm) at (0.5, 0.5) facing +x, its checkpoint 30 cm ahead. A mover of 2.5 cm radius at
    (0.62, 0.5) going on at 5 cm/s: its nearest point 9.5 cm from the robot's centre, 7 cm from the body (beyond
    avoid's 4 cm), in the corridor the body sweeps — within keep_back (8 cm by default) the robot stops (a mover
    shuttling along a corridor turns back on a robot following it, tuning movers:4); at (0.62, 0.56) the nearest
    point, (12, 6) cm · 10.9 / 13.4 = (9.8, 4.9) cm from the centre, lies beyond the corridor's 2.5 + 1.2 cm: goto
    cruises."""
    p = P if keep_back is None else sub.SubsumptionParams(keep_back=keep_back)
    _, t = tick(long_ring(), markers=[mover], p=p)
    assert int(t.response) == response


@pytest.mark.parametrize("bad", ["keep_back=-0.01", "margin=-0.001"])
def test_a_negative_distance_is_refused_with_its_name(bad):
    with pytest.raises(ValueError, match=bad.split("=")[0] + " must be >= 0"):
        parse_architecture(f"subsumption:{bad}")
