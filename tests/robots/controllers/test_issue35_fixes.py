"""Issue 35's two controller fixes, by hand: the fields' clearance follows the sensed gap (a narrow niche stays
open), and Samba steps straight out of a mover's way rather than stand in it."""

import math

import jax.numpy as jnp
import numpy as np

from robots.controllers import samba
from robots.controllers.base import Observation
from robots.controllers.fields import FieldParams, gap_clearance
from robots.params import KHEPERA

R = KHEPERA.radius


def across(gap, d=0.1):
    """Two obstacle inputs (α, d from the body surface) straight ahead of the robot's centre, ``gap`` apart
    (surface points at (d + R, ±gap / 2) in the robot frame), one either side of a target at α = 0."""
    r = math.hypot(d + R, gap / 2)
    a = math.atan2(gap / 2, d + R)
    return jnp.array([[a, r - R], [-a, r - R]], jnp.float32)


def test_the_clearance_is_a_quarter_of_the_room_a_narrow_gap_leaves_at_most_1_cm():
    p = FieldParams()
    valid = jnp.array([True, True])
    # a 7.5 cm niche leaves the 5 cm body 2.5 cm of room: a quarter of it, 6.25 mm, instead of 1 cm
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 0.0, R, p), [0.00625, 0.00625], atol=1e-6)
    # a 20 cm doorway: 1/4 of 15 cm is past the 1 cm cap
    np.testing.assert_allclose(gap_clearance(across(0.2), valid, 0.0, R, p), [0.01, 0.01], atol=1e-7)
    # a gap narrower than the body: no clearance at all (the planner does not send the robot there)
    np.testing.assert_allclose(gap_clearance(across(0.04), valid, 0.0, R, p), [0.0, 0.0], atol=1e-7)
    # both on one side of the target's direction: no gap across the way, the fixed 1 cm
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 1.0, R, p), [0.01, 0.01], atol=1e-7)
    # an empty slot is no side of a gap; gap_share = 0 is the fixed clearance of before
    np.testing.assert_allclose(gap_clearance(across(0.075), jnp.array([True, False]), 0.0, R, p), [0.01, 0.01])
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 0.0, R, FieldParams(gap_share=0.0)), [0.01, 0.01])


def observation(markers):
    return Observation(t=np.float32(0), ir=np.full(12, np.inf, np.float32), target=np.array([math.pi / 2, 0.3],
                                                                                            np.float32),
                       target_id=np.int32(0), final=np.bool_(True), pose=np.array([0.5, 0.5, 0.0], np.float32),
                       target_velocity=np.zeros(2, np.float32), markers=np.asarray(markers, np.float32).reshape(-1, 5))


def test_samba_steps_straight_out_of_a_movers_way():
    """The robot at (0.5, 0.5) facing +x, its checkpoint to its left (α = 90°, so it would turn on the spot). A
    mover of radius 2.5 cm 12 cm to its left comes at it at 0.1 m/s: standing, the discs (grown by the 1 cm
    clearance: 6 cm) meet after (0.12 − 0.06) / 0.1 = 0.6 s, within escape_s = 1.5 s. Driving straight ahead at v,
    the nearest approach of (−v t, 0.12 − 0.1 t) is 0.12 v / sqrt(v² + 0.01): 4.5 cm at 0.04 m/s (hit), 6.2 cm at
    0.06 m/s (never hit). Of the straight motions never hit, the grid's first (the slowest, 0.06 m/s) is taken:
    both wheels 0.06 m/s. Without the mover, or with escape_s = 0, Samba's own command stands."""
    p = samba.SambaParams()
    mover = [0.5, 0.62, 0.0, -0.1, 0.025]
    _, wheels = samba.step(samba.init(p), observation([mover]), p=p, robot=KHEPERA)
    np.testing.assert_allclose(np.asarray(wheels), [0.06, 0.06], atol=1e-6)
    still = samba.step(samba.init(p), observation([]), p=p, robot=KHEPERA)[1]
    off = samba.SambaParams(escape_s=0.0)
    assert not np.allclose(np.asarray(still), [0.06, 0.06])
    assert not np.allclose(np.asarray(samba.step(samba.init(off), observation([mover]), p=off, robot=KHEPERA)[1]),
                           [0.06, 0.06])
    # a mover passing by far off (it would meet the standing robot only after 3 s) changes nothing
    far = [0.5, 0.86, 0.0, -0.1, 0.025]
    np.testing.assert_allclose(np.asarray(samba.step(samba.init(p), observation([far]), p=p, robot=KHEPERA)[1]),
                               np.asarray(still), atol=1e-6)
