"""The controllers' definitions: Braitenberg (Eq. 4.10), command fusion (Eq. 4.11), neural fields (Eq. 5.1–5.6)
and the extended form's memory and commitment."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm import indirect
from ekm.config import EKMConfig
from ekm.data import load_default_map
from ekm.errors import InputError
from robots.controllers import braitenberg, fields, fusion, memory
from robots.controllers.base import Observation, proximity
from robots.controllers.spec import parse_architecture, parse_architectures
from robots.params import KHEPERA, LONG_RANGE, SHORT_RANGE


def observation(ir, target=(0.3, 0.25), t=0.0, target_id=0, pose=(0.5, 0.5, 0.0)):
    return Observation(t=np.float32(t), ir=np.asarray(ir, np.float32), target=np.asarray(target, np.float32),
                       target_id=np.int32(target_id), final=np.bool_(False), pose=np.asarray(pose, np.float32),
                       target_velocity=np.zeros(2, np.float32), markers=np.zeros((0, 5), np.float32))


@pytest.fixture(scope="module")
def signed_map():
    saved = load_default_map("signed")
    return jax.tree.map(lambda a: a[0], saved.ekm), saved.cfg


# ------------------------------------------------------------------------------------------ Braitenberg

@pytest.mark.parametrize("sensors", [SHORT_RANGE, LONG_RANGE], ids=["short", "long"])
def test_an_obstacle_ahead_left_turns_the_robot_right(sensors):
    """Ch. 4.4: "the right motor will rotate backward faster than the left motor's rotation forward"."""
    z = braitenberg.z_matrix(sensors, cross=4.0, same=0.4)
    angles = np.degrees(np.asarray(sensors.angles))
    ahead_left = np.argmin(np.where(angles > 0, np.abs(angles - 30.0), np.inf))  # the forward sensor nearest 30° left
    ir = np.full(len(angles), np.inf)
    ir[ahead_left] = 0.4 * sensors.range_m
    left, right = np.asarray(braitenberg.avoid(z, proximity(ir, sensors)))
    assert right < 0 < left and abs(right) > abs(left)


def test_z_has_large_negative_cross_weights_from_forward_sensors_and_small_positive_others():
    z = braitenberg.z_matrix(SHORT_RANGE, cross=4.0, same=0.4)
    # Khepera order: 85, 45, 10, -10, -45, -85, -160, 160 degrees.
    assert z[1, 1] == z[1, 2] == -4.0 and z[0, 3] == z[0, 4] == -4.0  # forward-left -> right motor, and mirrored
    assert z[0, 1] == z[0, 2] == 0.4 and z[1, 3] == z[1, 4] == 0.4
    others = np.r_[z[:, [0, 5, 6, 7]].ravel()]
    assert np.all(others > 0) and np.all(others <= 0.4)
    long = braitenberg.z_matrix(LONG_RANGE, cross=4.0, same=0.4)
    assert long[0, 0] == long[1, 0] == pytest.approx(-1.8)  # straight ahead: both motors, split evenly


def test_proximity_is_zero_for_nothing_seen_and_one_at_contact():
    u = np.asarray(proximity(np.array([np.inf, 0.0, 0.025, 0.05]), SHORT_RANGE))
    assert u.tolist() == pytest.approx([0.0, 1.0, 0.5, 0.0])


# ---------------------------------------------------------------------------------------- command fusion

def fusion_controller(signed_map, **params):
    ekm, cfg = signed_map
    return fusion.build(fusion.FusionParams(**params), ekm, cfg)


def test_fusion_without_obstacles_sends_beta_times_the_map_command(signed_map):
    ekm, cfg = signed_map
    ctl = fusion_controller(signed_map, beta=0.85)
    obs = observation(np.full(8, np.inf))
    _, c = ctl.step(ctl.init(), obs)
    c_p, _ = indirect.control(ekm, jnp.asarray(obs.target), cfg)
    np.testing.assert_allclose(np.asarray(c), 0.85 * np.asarray(c_p), rtol=1e-6)


def test_fusion_target_reaching_keeps_its_period_and_reacts_at_once_to_a_new_checkpoint(signed_map):
    ctl = fusion_controller(signed_map, refresh="clock", period=1.024)
    free = np.full(8, np.inf)
    state, c0 = ctl.step(ctl.init(), observation(free, target=(0.3, 0.25), t=0.0))
    state, c1 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=0.128))  # same checkpoint id: held
    np.testing.assert_array_equal(np.asarray(c0), np.asarray(c1))
    _, c2 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=0.256, target_id=1))  # new checkpoint
    assert not np.allclose(np.asarray(c2), np.asarray(c1))
    _, c3 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=1.024))  # period up
    np.testing.assert_array_equal(np.asarray(c3), np.asarray(c2))


def test_fusion_with_refresh_sensed_recomputes_target_reaching_while_an_obstacle_is_sensed(signed_map):
    ir = np.full(8, np.inf)
    ir[0] = 0.04  # a wall on the left, not ahead
    for refresh, changes in (("clock", False), ("sensed", True)):
        ctl = fusion_controller(signed_map, refresh=refresh)
        state, _ = ctl.step(ctl.init(), observation(ir, target=(0.3, 0.25), t=0.0))
        state, _ = ctl.step(state, observation(ir, target=(-1.0, 0.1), t=0.128))
        held = np.asarray(state.c_p)
        c_new, _ = indirect.control(signed_map[0], jnp.asarray([-1.0, 0.1]), signed_map[1])
        assert np.allclose(held, np.asarray(c_new)) == changes


# ----------------------------------------------------------------------------------------- neural fields

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


# ------------------------------------------------------------------------------------ extended: memory

def test_memory_keeps_hits_merges_repeats_clears_what_a_ray_sees_through_and_forgets_old_points():
    angles = jnp.asarray(LONG_RANGE.angles, jnp.float32)
    kw = dict(radius=0.025, range_m=0.175, merge=0.01, forget_after=10.0)
    m = memory.empty(16)
    pose = jnp.asarray([0.5, 0.5, 0.0])
    ir = np.full(12, np.inf)
    ir[0] = 0.1  # a point 12.5 cm ahead of the centre
    m = memory.update(m, pose, jnp.asarray(ir), angles, 0.0, **kw)
    assert int(jnp.sum(jnp.isfinite(m.seen))) == 1
    np.testing.assert_allclose(np.asarray(m.points[0]), [0.625, 0.5], atol=1e-6)
    m = memory.update(m, pose, jnp.asarray(ir * 1.02), angles, 1.0, **kw)  # the same point again: refreshed
    assert int(jnp.sum(jnp.isfinite(m.seen))) == 1 and float(m.seen[0]) == 1.0
    u, valid = memory.egocentric(m, jnp.asarray([0.5, 0.4, math.pi / 2]), radius=0.025)
    np.testing.assert_allclose(np.asarray(u[0]), [-math.atan2(0.125, 0.1), math.hypot(0.125, 0.1) - 0.025], atol=1e-6)
    kept = memory.update(m, pose, jnp.full(12, jnp.inf), angles, 5.0, **{**kw, "range_m": 0.05})  # ray too short
    assert int(jnp.sum(jnp.isfinite(kept.seen))) == 1
    cleared = memory.update(m, pose, jnp.full(12, jnp.inf), angles, 2.0, **kw)  # the ray now sees through it
    assert int(jnp.sum(jnp.isfinite(cleared.seen))) == 0
    forgotten = memory.update(m, jnp.asarray([0.1, 0.1, 0.0]), jnp.full(12, jnp.inf), angles, 11.5, **kw)
    assert int(jnp.sum(jnp.isfinite(forgotten.seen))) == 0


def test_blocked_along_uses_the_bodys_width_at_the_obstacles_distance():
    u = jnp.asarray([[0.0, 0.2]])  # an obstacle 20 cm ahead (from the surface)
    dirs = jnp.radians(jnp.asarray([0.0, 5.0, 8.8, 9.2]))
    blocked = np.asarray(memory.blocked_along(dirs, 0.5, u, jnp.asarray([True]), radius=0.025, clearance=0.01))
    assert blocked.tolist() == [True, True, True, False]  # asin(0.035 / 0.225) = 8.95 degrees
    assert not bool(memory.blocked_along(dirs[:1], 0.15, u, jnp.asarray([True]), radius=0.025, clearance=0.01)[0])


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


# ------------------------------------------------------------------------------------------ architectures

def test_architecture_specs_parse_parameters_and_spell_them_all():
    specs = parse_architectures("fusion:sensors=long,beta=0.6,fields,fields:form=thesis,commit=false")
    assert [s.name for s in specs] == ["fusion", "fields", "fields"]
    assert specs[0].params.sensors == "long" and specs[0].params.beta == 0.6
    assert specs[2].params.form == "thesis" and specs[2].params.commit is False
    assert specs[0].label == "fusion:sensors=long,beta=0.6" and specs[1].label == "fields"
    assert str(parse_architecture(str(specs[0]))) == str(specs[0])  # the full spelling parses back


@pytest.mark.parametrize("text, message", [
    ("fuson", "architecture 'fuson': unknown (choose from fusion, fields"),
    ("fusion:foo=1", "architecture fusion: unknown parameter 'foo' (known: sensors, beta,"),
    ("fusion:beta=x", "architecture fusion: beta: must be a number, got 'x'"),
    ("fusion:beta=2", "architecture fusion: beta must be in (0, 1], got 2.0"),
    ("fusion:sensors=mid", "architecture fusion: sensors: must be one of short, long, got 'mid'"),
    ("fields:commit=maybe", "architecture fields: commit: must be true or false, got 'maybe'"),
    ("fusion:beta", "architecture fusion: 'beta' is not k=v"),
    ("beta=1", "parameter 'beta=1' before any architecture name"),
    ("fusion,,fields", "empty item between commas"),
    ("", "architecture: empty"),
])
def test_bad_architecture_specs_are_one_line_errors(text, message):
    with pytest.raises(InputError) as err:
        parse_architectures(text)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_an_architecture_refuses_a_direct_map():
    from ekm.direct import init as direct_init

    cfg = EKMConfig(mapping="direct", neurons=3)
    with pytest.raises(InputError, match="needs an indirect map"):
        parse_architecture("fields").build(direct_init(cfg), cfg)


# ------------------------------------------------------------------------- holonomic velocity -> wheels

def test_velocity_to_wheels_drives_ahead_turns_towards_the_side_and_turns_on_the_spot_for_behind():
    from robots.controllers.base import velocity_to_wheels

    ahead = np.asarray(velocity_to_wheels(0.0, 0.1))
    assert ahead == pytest.approx([0.1, 0.1])
    left = np.asarray(velocity_to_wheels(0.5, 0.1))
    assert left[1] > left[0] > 0  # forward and turning left
    behind = np.asarray(velocity_to_wheels(3.0, 0.1))
    assert behind[0] == pytest.approx(-behind[1]) and behind[1] > 0  # on the spot, left about
    fast = np.asarray(velocity_to_wheels(1.0, 1.0))
    assert np.max(np.abs(fast)) == pytest.approx(KHEPERA.max_wheel_speed)  # scaled, not clipped
    v, omega = np.cos(1.0), 4.0 * 1.0  # unscaled: forward speed and turn rate
    assert (fast[1] - fast[0]) / (fast[1] + fast[0]) == pytest.approx(omega * KHEPERA.wheel_base / (2 * v), rel=1e-5)


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
