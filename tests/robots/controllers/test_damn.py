"""DAMN (Arkin §4.5.5): each behaviour's votes, and which heading and which speed win their independent
winner-take-all arbiters — on hand-built observations, with the votes worked out by hand."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.controllers import damn
from robots.controllers.spec import parse_architecture
from robots.params import KHEPERA, LONG_RANGE
from tests.robots.controllers.observations import long_ring, observation

P = damn.DamnParams()
ANGLES = jnp.asarray(LONG_RANGE.angles, jnp.float32)
votes = jax.jit(damn.votes, static_argnames=("p", "robot"))
meets = jax.jit(damn.meets, static_argnames=("p", "radius"))
STRAIGHT = 12  # φ_12 = 2π·12/24 − π = 0


def tick(ir, target=(0.0, 0.3), state=None, **kw):
    state = damn.init(P) if state is None else state
    return votes(state, observation(ir, target=target, **kw), ANGLES, P, KHEPERA)


def test_the_candidates():
    np.testing.assert_allclose(np.degrees(np.asarray(P.headings()))[[0, 9, 12, 15]], [-180, -45, 0, 45], atol=1e-4)
    np.testing.assert_allclose(np.asarray(P.turn_rates())[[11, 12, 13, 14, 15]],
                               [-4 * math.pi / 12, 0, 4 * math.pi / 12, 4 * math.pi / 6, 3.0], atol=1e-5)
    np.testing.assert_allclose(np.asarray(P.speed_set()), [0, 0.01, 0.02, 0.04, 0.08, 0.16], atol=1e-7)


def test_in_the_open_straight_at_the_checkpoint_at_top_speed():
    _, v = tick(long_ring())
    assert int(v.turn_winner) == STRAIGHT and int(v.speed_winner) == 5
    np.testing.assert_allclose(np.asarray(v.turn[0]), 0.0)  # avoid: nothing in the way of any heading
    ctrl = parse_architecture("damn").build()
    np.testing.assert_allclose(np.asarray(ctrl.step(ctrl.init(), observation(long_ring(), target=(0.0, 0.3)))[1]),
                               [0.16, 0.16], atol=1e-6)


def test_a_checkpoint_half_a_radian_left_wins_the_30_degree_heading():
    # goto's vote 1 − |0.5 − φ|/π is highest at φ = 30° (0.5236); v* = 0.16 cos 0.5 = 0.140 is nearest 0.16
    _, v = tick(long_ring(), target=(0.5, 0.3))
    assert int(v.turn_winner) == 14 and int(v.speed_winner) == 5
    ctrl = parse_architecture("damn").build()
    w = np.asarray(ctrl.step(ctrl.init(), observation(long_ring(), target=(0.5, 0.3)))[1])
    # ω = 4 · π/6 = 2.094 rad/s: wheels 0.16 ∓ 0.0555, scaled so the faster is c*
    np.testing.assert_allclose(w, [0.1045 * 0.16 / 0.2155, 0.16], atol=2e-4)


def test_a_point_six_centimetres_ahead():
    _, v = tick(long_ring(s0=0.035))  # the point (0.06, 0): free 0.06 − 0.035 = 0.025 m straight on
    avoid = np.asarray(v.turn[0])
    np.testing.assert_allclose(avoid[[STRAIGHT, 13, 14, 15]], [-(1 - 0.025 / 0.12), -(1 - 0.02659 / 0.12),
                                                              -(1 - 0.03393 / 0.12), 0.0], atol=2e-4)
    # totals: straight −3·0.792 + 1 = −1.375; ±45° 0 + 0.75: a tie, and the first candidate (the right) wins
    assert int(v.turn_winner) == 9
    # speeds: 0.08 and 0.16 cannot stop in 0.5 s before the 2.5 cm: votes −0.375 and −0.6875 (× 3) outweigh goto's
    np.testing.assert_allclose(np.asarray(v.speed[0]), [0, 0, 0, 0, -0.375, -0.6875], atol=1e-5)
    assert int(v.speed_winner) == 3


def test_keep_heading_breaks_the_tie_towards_last_ticks_course():
    state = damn.init(P)._replace(heading=jnp.float32(math.pi / 4))
    _, v = tick(long_ring(s0=0.035), state=state)
    # +45°: 0.75 + 0.2 · 1; −45°: 0.75 + 0.2 · 0.5
    assert int(v.turn_winner) == 15
    np.testing.assert_allclose(float(v.turn_total[15]) - float(v.turn_total[9]), 0.1, atol=1e-5)


def test_the_arbiters_are_independent():
    # speed votes do not depend on where the checkpoint's heading lies, only on its cosine and the way straight on
    _, left = tick(long_ring(), target=(0.4, 0.3))
    _, right = tick(long_ring(), target=(-0.4, 0.3))
    np.testing.assert_array_equal(np.asarray(left.speed_total), np.asarray(right.speed_total))
    assert int(left.turn_winner) + int(right.turn_winner) == 2 * STRAIGHT


def test_a_mover_coming_at_a_robot_that_stands_still():
    # 10 cm ahead, radius 2 cm, 0.1 m/s towards the robot: the gap 0.1 − 0.1 τ − 0.045 falls below 1 cm after
    # 0.45 s; the first of the eight instants (0.1875 s apart) past it is 0.5625 s
    mover = jnp.asarray([[0.1, 0.0, -0.1, 0.0, 0.02]], jnp.float32)
    assert float(meets(mover, 0.0, 0.0, P, KHEPERA.radius)) == pytest.approx(0.5625)
    assert math.isinf(float(meets(mover, math.pi / 2, 0.16, P, KHEPERA.radius)))  # leaving sideways at c*
    _, v = tick(long_ring(), markers=[[0.6, 0.5, -0.1, 0.0, 0.02]])  # the same mover, world frame
    assert float(v.speed[0][0]) == pytest.approx(-(1 - 0.5625 / 1.5))


def test_keep_heading_counts_in_the_world_frame():
    # heading 90° in the world, last tick's course 45° in the world: −45° relative to the robot now
    state = damn.init(P)._replace(heading=jnp.float32(math.pi / 4))
    _, v = tick(long_ring(s0=0.035), state=state, pose=(0.5, 0.5, math.pi / 2))
    assert int(v.turn_winner) == 9


@pytest.mark.parametrize("avoid, winner, behind", [
    ("nearer", 0, 0.0),                          # the way back to the checkpoint is open as far as it
    ("all", STRAIGHT, -(1 - 0.055 / 0.12)),      # blocked 5.5 cm along it: the robot faces on, and stands
])
def test_a_wall_beyond_the_checkpoint_does_not_close_the_way_to_it(avoid, winner, behind):
    """A corridor's bend: the checkpoint 5 cm straight behind the robot, the bend's wall 9 cm behind (points at x =
    −0.09), the corridor's walls 4.5 cm either side. Straight behind (φ_0 = −π) the body comes within the 1 cm
    clearance of the point (−0.09, 0) after 9 − 2.5 − 1 = 5.5 cm. Looking only as far as the checkpoint (5 cm) that
    heading is open, and go-to-checkpoint's vote 1 wins it; looking 12 cm, avoid votes 3 · −(1 − 5.5/12) against
    it and straight ahead (goto 0, nothing in the way) wins, at speed 0 with the checkpoint behind."""
    behind_wall = [(-0.09, y) for y in (-0.04, -0.02, 0.0, 0.02, 0.04)]
    sides = [(x, s * 0.045) for x in np.arange(-0.08, 0.081, 0.02) for s in (-1, 1)]
    points = jnp.asarray(behind_wall + sides, jnp.float32)
    p = damn.DamnParams(avoid=avoid)
    v = damn.vote(points, jnp.ones(len(points), bool), jnp.asarray([math.pi, 0.05], jnp.float32), False, 0.0,
                  jnp.nan, p, KHEPERA)
    assert int(v.turn_winner) == winner and int(v.speed_winner) == 0
    np.testing.assert_allclose(float(v.turn[0][0]), behind, atol=1e-4)
