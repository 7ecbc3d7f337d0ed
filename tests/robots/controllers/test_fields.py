"""Neural fields (robots.controllers.fields, Eq. 5.1–5.6), and the extended form's commitment and guard."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm import indirect
from ekm.config import EKMConfig
from robots.controllers import fields
from robots.controllers.fields import FieldParams, gap_clearance
from robots.params import KHEPERA, LONG_RANGE
from tests.robots.controllers.observations import observation


@pytest.mark.parametrize("form", fields.FORMS)
def test_with_no_obstacle_sensed_the_fields_give_exactly_the_indirect_maps_command(signed_map, form):
    ekm, cfg = signed_map
    ctl = fields.build(fields.FieldParams(form=form), ekm, cfg)
    state = ctl.init()
    control = jax.jit(indirect.control, static_argnames="cfg")  # compiled as the fields' step is (same FMAs)
    for target in [(0.3, 0.25), (-2.5, 0.08), (3.0, 0.6), (0.01, 0.003), (-0.9, 0.14)]:
        obs = observation(np.full(12, np.inf), target=target)
        state, c = ctl.step(state, obs)
        expected, _ = control(ekm, jnp.asarray(target, jnp.float32), cfg)
        # The same arithmetic, compiled inside a larger step: XLA may fuse it differently (last bit of float32).
        np.testing.assert_allclose(np.asarray(c), np.asarray(expected), rtol=1e-6, atol=1e-9)


def test_delta_d_stretches_the_obstacle_field_beyond_the_obstacle_and_not_before_it():
    d_s = 0.06
    assert float(fields.delta_d(d_s, d_s, 0.005)) == pytest.approx(1.0)
    beyond = np.asarray(fields.delta_d(d_s, np.array([0.061, 0.08, 0.11]), 0.005))
    assert np.all((0.02 < beyond) & (beyond < 0.1))  # 1 - gap**0.01 for 1 mm ... 5 cm
    before = np.asarray(fields.delta_d(d_s, np.array([0.055, 0.05, 0.04]), 0.005))
    assert before.tolist() == pytest.approx([2.0, 17.0, 257.0])  # 1 + (gap / tau)**4


@pytest.mark.parametrize("form", fields.FORMS)
def test_the_obstacle_field_inhibits_neurons_beyond_a_sensed_obstacle_along_its_direction_not_before(form):
    """Eq. 5.6 on the regular initial lattice: one sensor straight ahead sees an obstacle 6 cm away."""
    cfg = EKMConfig(neurons=15)
    from ekm.kohonen import initial_weights

    w = initial_weights(cfg)
    ir = np.full(12, np.inf)
    ir[0] = 0.06
    p = fields.FieldParams(form=form)
    if form == "thesis":
        u_obs, seen = fields.obstacle_inputs(jnp.asarray(ir), jnp.asarray(LONG_RANGE.angles, jnp.float32))
        winners = jax.vmap(lambda u: fields.winner(w, u, cfg))(u_obs)
        b = np.asarray(fields.obstacle_field(w, winners, seen, p, cfg))
    else:
        u_obs = jnp.asarray([[0.0, 0.06]], jnp.float32)
        b = np.asarray(fields.body_field(w, u_obs, jnp.asarray([True]), KHEPERA.radius, p, cfg))
    w = np.asarray(w)
    ahead = np.abs(w[:, 0]) < 0.25  # the lattice row straight ahead
    assert np.all(b[ahead & (w[:, 1] >= 0.07)] > 0.5)  # beyond the obstacle: inhibited
    assert np.all(b[ahead & (w[:, 1] <= 0.045)] < 0.05)  # before it: free
    assert np.all(b[np.abs(w[:, 0]) > 2.0] < 1e-3)  # the other way: untouched


def test_an_inhibited_target_makes_another_neuron_win_and_drive_to_its_own_displacement(signed_map):
    """Eq. 5.4/5.5: a wall straight ahead between robot and target; the winner k != s and c = M_k w_k."""
    ekm, cfg = signed_map
    ctl = fields.build(fields.FieldParams(form="thesis"), ekm, cfg)
    ir = np.full(12, np.inf)
    ir[[11, 0, 1]] = 0.05
    state, c = ctl.step(ctl.init(), observation(ir, target=(0.0, 0.4)))
    k, s = int(state.k), int(state.s)
    assert k != s
    np.testing.assert_allclose(np.asarray(c), np.asarray(indirect.command(ekm, ekm.w[k], k, cfg)), rtol=1e-6)
    assert abs(float(ekm.w[k, 0])) > 0.4  # it turns away from the obstacle


def test_committed_robot_keeps_to_one_side_of_a_wall_across_ticks(signed_map):
    """A wall across the way: the extended fields pick a side and keep it while the wall blocks the target."""
    ekm, cfg = signed_map
    ctl = fields.build(fields.FieldParams(), ekm, cfg)
    state = ctl.init()
    sides = []
    for i, y in enumerate(np.linspace(0.0, 0.06, 8)):
        pose = (0.5, 0.5 + y, 0.0)
        ir = np.full(12, np.inf)
        ir[[11, 0, 1]] = [0.09, 0.08, 0.09]  # wall 10.5 cm ahead, centre seen by three rays
        state, _ = ctl.step(state, observation(ir, target=(0.0, 0.5), t=0.128 * i, pose=pose))
        sides.append(float(state.side))
    assert sides[0] != 0 and len(set(sides)) == 1


def test_the_fields_guard_slows_the_wheels_to_half_a_second_from_what_is_ahead_and_keeps_the_turn():
    """guard by hand: a remembered point 3 cm ahead of the body (d = 0.03, α = 0): forward speed at most
    (0.03 − clearance / 2) / guard_s = (0.03 − 0.005) / 0.5 = 0.05 m/s; the command (0.10, 0.14) has v = 0.12
    and turn 0.02, so it becomes (0.03, 0.07). The same point behind the robot does not slow it going forward,
    and a command slow enough is left as it is, to the bit."""
    p = fields.FieldParams()
    u = jnp.asarray([[0.0, 0.03]], jnp.float32)
    c = fields.guard(jnp.asarray([0.10, 0.14]), u, jnp.asarray([True]), 0.025, p)
    np.testing.assert_allclose(np.asarray(c), [0.03, 0.07], atol=1e-7)
    behind = jnp.asarray([[np.pi, 0.03]], jnp.float32)
    np.testing.assert_array_equal(np.asarray(fields.guard(jnp.asarray([0.10, 0.14]), behind, jnp.asarray([True]),
                                                          0.025, p)), np.float32([0.10, 0.14]))
    slow = jnp.asarray([0.04, 0.05], jnp.float32)
    np.testing.assert_array_equal(np.asarray(fields.guard(slow, u, jnp.asarray([True]), 0.025, p)), np.asarray(slow))


# the clearance beside a remembered obstacle follows the sensed gap (fields:gap_share, an extension)
GAP_R = KHEPERA.radius


def across(gap, d=0.1):
    """Two obstacle inputs (α, d from the body surface) straight ahead of the robot's centre, ``gap`` apart
    (surface points at (d + GAP_R, ±gap / 2) in the robot frame), one either side of a target at α = 0."""
    r = math.hypot(d + GAP_R, gap / 2)
    a = math.atan2(gap / 2, d + GAP_R)
    return jnp.array([[a, r - GAP_R], [-a, r - GAP_R]], jnp.float32)


def test_the_clearance_is_a_quarter_of_the_room_a_narrow_gap_leaves_at_most_1_cm():
    p = FieldParams()
    valid = jnp.array([True, True])
    # a 7.5 cm niche leaves the 5 cm body 2.5 cm of room: a quarter of it, 6.25 mm, instead of 1 cm
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 0.0, GAP_R, p), [0.00625, 0.00625], atol=1e-6)
    # a 20 cm doorway: 1/4 of 15 cm is past the 1 cm cap
    np.testing.assert_allclose(gap_clearance(across(0.2), valid, 0.0, GAP_R, p), [0.01, 0.01], atol=1e-7)
    # a gap narrower than the body: no clearance at all (the planner does not send the robot there)
    np.testing.assert_allclose(gap_clearance(across(0.04), valid, 0.0, GAP_R, p), [0.0, 0.0], atol=1e-7)
    # both on one side of the target's direction: no gap across the way, the fixed 1 cm
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 1.0, GAP_R, p), [0.01, 0.01], atol=1e-7)
    # an empty slot is no side of a gap; gap_share = 0 is the fixed clearance of before
    np.testing.assert_allclose(gap_clearance(across(0.075), jnp.array([True, False]), 0.0, GAP_R, p), [0.01, 0.01])
    np.testing.assert_allclose(gap_clearance(across(0.075), valid, 0.0, GAP_R, FieldParams(gap_share=0.0)), [0.01, 0.01])


# Declared movers: where they will be (mover_ahead_s) and out of their way (escape_s)
def test_a_mover_is_placed_where_it_is_and_where_it_will_be():
    """mover_inputs by hand: the robot (radius 2.5 cm) at the origin facing +y; a mover of radius 2 cm at (0, 1)
    coming at it at 0.1 m/s. Over 1 s ahead, in three places: now, after 0.5 s and after 1 s, straight ahead
    (α = 0) at 1 − 0.025 − 0.02 = 0.955 m, then 0.905 and 0.855 m from surface to surface, each of radius 0.02."""
    u, r = fields.mover_inputs(np.array([[0.0, 1.0, 0.0, -0.1, 0.02]], np.float32),
                               np.array([0.0, 0.0, np.pi / 2], np.float32), 0.025, 1.0)
    np.testing.assert_allclose(np.asarray(u), [[0.0, 0.955], [0.0, 0.905], [0.0, 0.855]], atol=1e-6)
    np.testing.assert_allclose(np.asarray(r), [0.02, 0.02, 0.02])


def test_a_mover_crosses_the_line_of_sight_when_its_velocity_is_more_across_it_than_along_it():
    """The robot at the origin, a mover 1 m away along +x: moving along y it crosses; along x (coming or going) it
    does not; at (−0.1, 0.05) m/s its part along the line (0.1) beats the part across (0.05); at (0.05, 0.1) the
    other way round; a mover standing still crosses nothing. Seen from (1, 1) instead, the line is along y."""
    v = [(0.0, 0.1), (-0.1, 0.0), (0.1, 0.0), (-0.1, 0.05), (0.05, 0.1), (0.0, 0.0)]
    markers = np.array([[1.0, 0.0, vx, vy, 0.02] for vx, vy in v], np.float32)
    assert np.asarray(fields.crossing(markers, np.zeros(3, np.float32))).tolist() == [True, False, False, False,
                                                                                      True, False]
    from_above = np.asarray(fields.crossing(markers, np.array([1.0, 1.0, 0.0], np.float32)))
    assert from_above.tolist() == [False, True, True, True, False, False]


@pytest.mark.parametrize("velocity, remembered", [((0.05, 0.0), 1), ((0.0, 0.05), 0)])
def test_the_ir_return_of_a_mover_is_kept_unless_it_crosses(signed_map, velocity, remembered):
    """The robot at (0.5, 0.5) facing +x sees something 10 cm straight ahead (sensor 0), where a declared mover of
    radius 2.5 cm stands at 0.5 + 0.025 + 0.1 + 0.025 = 0.65 m. Going away along the line of sight it does not
    cross: its IR return is remembered as a still point (one), and it is an obstacle as a wall is; crossing the line
    (+y) it is placed by its velocity instead and its return dropped (none remembered)."""
    markers = [[0.65, 0.5, *velocity, 0.025]]
    obs = observation(np.r_[0.1, np.full(11, np.inf)], target=(0.0, 0.3), markers=markers)
    p = FieldParams(mover_ahead_s=1.0)
    ekm, cfg = signed_map
    state, _, _ = fields.fields(fields.init(p), ekm, obs, jnp.asarray(fields.sensor_angles(LONG_RANGE)), p, cfg,
                                radius=0.025, range_m=LONG_RANGE.range_m)
    assert int(np.isfinite(np.asarray(state.memory.seen)).sum()) == remembered


def test_a_mover_on_its_way_closes_the_direction_it_will_cross(signed_map):
    """The checkpoint 30 cm straight ahead, nothing sensed; a mover 20 cm ahead and 10 cm to the left crossing the
    way at 0.1 m/s to the right. Where it is, it does not block the way straight ahead (10 cm off the line; the
    body and clearance need 2.5 + 2.5 + 1 = 6 cm); in a second it is on the line, so with mover_ahead_s = 1 the
    target's direction is inhibited and the winner turns off it — with mover_ahead_s = 0 the robot goes straight."""
    ekm, cfg = signed_map
    mover = [0.7, 0.6, 0.0, -0.1, 0.025]  # robot at (0.5, 0.5) facing +x: 20 cm ahead, 10 cm to the left
    obs = observation(np.full(12, np.inf), target=(0.0, 0.3), markers=[mover])
    ahead = fields.build(fields.FieldParams(escape_s=0.0, mover_ahead_s=1.0), ekm, cfg)
    now = fields.build(fields.FieldParams(escape_s=0.0, mover_ahead_s=0.0), ekm, cfg)
    k_ahead = int(ahead.step(ahead.init(), obs)[0].k)
    k_now = int(now.step(now.init(), obs)[0].k)
    assert abs(float(ekm.w[k_now, 0])) < 0.05  # straight at the checkpoint
    assert abs(float(ekm.w[k_ahead, 0])) > 0.2  # off the mover's coming path


@pytest.mark.parametrize("place, velocity, track_near", [((0.08, 0.05), (0.0, -0.04), False),
                                                      ((0.06, 0.05), (0.0, -0.04), True),
                                                      ((0.06, 0.05), (0.0, 0.04), False),
                                                      ((0.06, 0.05), (0.0, 0.0), False),
                                                      ((0.04, 0.04), (0.0, 0.0), True)])
def test_a_mover_is_near_when_its_track_passes_the_robot(place, velocity, track_near):
    """The robot (radius 2.5 cm) at the origin; a mover of radius 3 cm within mover_near = 15 cm in every case. By
    its track (the clearance 1 cm): coming down along x = 8 cm it passes 8 − 3 − 2.5 = 2.5 cm from the body (not
    near: the lane beside a corridor's mover), along x = 6 cm 0.5 cm (near); going away from (6, 5) cm or standing
    there, it counts where it is, hypot(6, 5) − 5.5 = 2.31 cm (not near); standing at (4, 4) cm, 0.16 cm (near).
    Without the track every one is near."""
    obs = observation(np.full(12, np.inf), target=(0.0, 0.3), markers=[[*place, *velocity, 0.03]], pose=(0, 0, 0))
    assert bool(fields.movers_near(obs, 0.025, 0.15, 0.01)) is track_near
    assert bool(fields.movers_near(obs, 0.025, 0.15))


def test_the_fields_step_straight_out_of_a_movers_way(signed_map):
    """As Samba's test (tests/robots/controllers/test_samba.py): the robot at (0.5, 0.5) facing +x, its checkpoint
    to its left; a mover of radius 2.5 cm 12 cm to its left comes at it at 0.1 m/s. Standing, the discs grown by
    the 1 cm clearance (6 cm) meet after 0.6 s < escape_s = 1.5 s. Straight ahead at v the nearest approach is
    0.12 v / sqrt(v² + 0.01): 4.5 cm at 0.04 m/s (hit), 6.2 cm at 0.06 m/s (never): both wheels 0.06 m/s. With
    escape_s = 0 the fields' own command stands."""
    ekm, cfg = signed_map
    mover = [0.5, 0.62, 0.0, -0.1, 0.025]
    obs = observation(np.full(12, np.inf), target=(np.pi / 2, 0.3), markers=[mover])
    ctl = fields.build(fields.FieldParams(), ekm, cfg)
    np.testing.assert_allclose(np.asarray(ctl.step(ctl.init(), obs)[1]), [0.06, 0.06], atol=1e-6)
    off = fields.build(fields.FieldParams(escape_s=0.0), ekm, cfg)
    assert not np.allclose(np.asarray(off.step(off.init(), obs)[1]), [0.06, 0.06], atol=1e-3)


@pytest.mark.parametrize("see_through, remembered", [(None, 1), (0.01, 0)])
def test_the_fields_keep_a_wall_end_a_ray_passes_8_mm_beside(signed_map, see_through, remembered):
    """Tick 1 at (0.5, 0.5) facing +x: sensor 0 sees a wall's end 10 cm ahead, remembered at (0.625, 0.5). Tick 2
    at (0.5, 0.508): sensor 0's ray misses it (nothing seen) and passes 8 mm beside it, 10 cm along. By default
    (see_through 5 mm, the points' radius merge / 2) the end is kept; with the 1 cm of before it was forgotten,
    as the ends of niche walls were beside the rays that missed them (niches:0, docs/reproduce/every-kind.md)."""
    ekm, cfg = signed_map
    p = FieldParams() if see_through is None else FieldParams(see_through=see_through)
    angles = jnp.asarray(fields.sensor_angles(LONG_RANGE))
    kw = dict(radius=0.025, range_m=LONG_RANGE.range_m)
    seen = observation(np.r_[0.1, np.full(11, np.inf)], target=(0.0, 0.3))
    state, _, _ = fields.fields(fields.init(p), ekm, seen, angles, p, cfg, **kw)
    missed = observation(np.full(12, np.inf), target=(0.0, 0.3), t=0.128, pose=(0.5, 0.508, 0.0))
    state, _, _ = fields.fields(state, ekm, missed, angles, p, cfg, **kw)
    assert int(np.isfinite(np.asarray(state.memory.seen)).sum()) == remembered


# narrow places (issue 35, niches): where the commitment starts, and a guard that lets the robot run beside a wall

def passage(width, offset, r=GAP_R):
    """Remembered points (α, d from the body surface) of two walls parallel to the robot's heading, ``width`` apart
    (surface to surface), every centimetre from 2 to 15 cm ahead, the robot's centre ``offset`` off the passage's
    centre line towards the left wall."""
    x = np.arange(0.02, 0.155, 0.01)
    pts = np.concatenate([np.stack([x, np.full_like(x, width / 2 - offset)], 1),
                          np.stack([x, np.full_like(x, -width / 2 - offset)], 1)])
    return jnp.asarray(np.stack([np.arctan2(pts[:, 1], pts[:, 0]), np.hypot(pts[:, 0], pts[:, 1]) - r], 1), jnp.float32)


@pytest.mark.parametrize("narrow_start", [True, False])
def test_in_a_narrow_passage_the_commitment_starts_only_when_the_body_itself_would_touch(narrow_start):
    """By hand, body radius R = 2.5 cm (GAP_R), target 20 cm straight ahead. An 8 cm passage leaves the body 3 cm of
    room: a quarter, 7.5 mm, of clearance. 8 mm off its centre line the robot's straight way passes the left wall
    at 4 − 0.8 = 3.2 cm from its centre: more than R (the body passes), less than R + 7.5 mm = 3.25 cm (the body
    and its clearance do not). So the commitment starts only without narrow_start. A 20 cm passage keeps 1 cm of
    clearance: a wall 3.2 cm from the way (the robot 6.8 cm off centre) starts it either way (R + 1 cm = 3.5 cm)."""
    p = FieldParams(narrow_start=narrow_start)
    target = jnp.asarray([0.0, 0.2], jnp.float32)
    for width, offset, expected in [(0.08, 0.008, not narrow_start), (0.08, 0.0, False), (0.2, 0.068, True)]:
        u = passage(width, offset)
        valid = jnp.ones(u.shape[0], bool)
        clear = gap_clearance(u, valid, 0.0, GAP_R, p)
        assert float(jnp.max(clear)) == pytest.approx(min(0.25 * (width - 2 * GAP_R), 0.01), abs=2e-4)
        assert bool(fields.commitment_starts(target, u, valid, clear, p, radius=GAP_R)) == expected, (width, offset)


@pytest.mark.parametrize("guard_room, expected", [(True, [0.10, 0.10]), (False, [0.0070522, 0.0070522])])
def test_the_guard_lets_the_robot_run_beside_a_wall_it_is_already_nearer_than_the_clearance(guard_room, expected):
    """By hand, R = 2.5 cm: a remembered point 1 cm ahead and 3.2 cm to the left of the robot's centre, 3.3526 cm
    from it, d = 8.5261 mm from the body. With the fixed 1 cm clearance the straight way ahead (3.2 < R + 1 cm = 3.5
    cm) meets it: the forward speed is held to (d − clearance / 2) / guard_s = (0.0085261 − 0.005) / 0.5 =
    0.0070522 m/s, and the robot stands beside the wall. With guard_room the clearance is the room it has, less
    guard_margin: 8.526 − 3 = 5.526 mm, and R + 5.526 mm = 3.05 cm < 3.2 cm: the point is beside its way, and the
    command (0.10, 0.10) passes as it is."""
    p = FieldParams(guard_room=guard_room)
    x, y = 0.01, 0.032
    u = jnp.asarray([[math.atan2(y, x), math.hypot(x, y) - 0.025]], jnp.float32)
    c = fields.guard(jnp.asarray([0.10, 0.10], jnp.float32), u, jnp.asarray([True]), 0.025, p)
    np.testing.assert_allclose(np.asarray(c), expected, atol=2e-6)


@pytest.mark.parametrize("guard_reads, limit", [(True, 0.034), (False, 0.05)])
def test_the_guard_counts_this_ticks_return_where_the_memory_holds_the_wall_farther(guard_reads, limit):
    """By hand, R = 2.5 cm, the long ring's sensor 0 straight ahead. Tick 1 reads a wall 3 cm ahead of the body:
    remembered there. Tick 2 reads it 2.2 cm ahead: 8 mm from the remembered point, within merge (1 cm), which
    refreshes that point where it was. The guard holds the forward speed to (d − clearance / 2) / guard_s: with
    this tick's return counted (0.022 − 0.005) / 0.5 = 0.034 m/s, from the memory alone (0.03 − 0.005) / 0.5 =
    0.05 m/s; the command (0.10, 0.14) keeps its turn, ±0.02."""
    p = FieldParams(guard_reads=guard_reads)
    angles = jnp.asarray(LONG_RANGE.angles, jnp.float32)
    memory = fields.init(p).memory
    ir = np.full(12, np.inf)
    for t, reading in [(0.0, 0.03), (0.128, 0.022)]:
        ir[0] = reading
        obs = observation(ir, t=t)
        memory = fields.mem.update(memory, obs.pose, jnp.asarray(obs.ir), angles, obs.t, radius=0.025,
                                   range_m=LONG_RANGE.range_m, merge=p.merge, forget_after=p.memory_s,
                                   through=p.see_through)
    still = jnp.isfinite(memory.seen)
    assert int(jnp.sum(still)) == 1  # one point, refreshed where tick 1 put it
    u, counts = fields.guard_inputs(memory, still, obs, angles, 0.025, p)
    c = fields.guard(jnp.asarray([0.10, 0.14], jnp.float32), u, counts, 0.025, p)
    np.testing.assert_allclose(np.asarray(c), [limit - 0.02, limit + 0.02], atol=2e-6)
