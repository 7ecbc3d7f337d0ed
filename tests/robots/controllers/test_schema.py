"""Motor schemas (Arkin ch. 3.3.2, 4.4): each schema's vector as Arkin defines it, their sum through
velocity_to_wheels, runs through the scenario runner, and the classic local minimum that noise gets out of."""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from evaluation.scenario import ScenarioConfig, run_architecture, run_scenario
from robots.controllers import memory as mem
from robots.controllers import schema
from robots.controllers.base import Controller, Observation, velocity_to_wheels
from robots.controllers.spec import parse_architecture
from robots.params import KHEPERA, LONG_RANGE
from robots.worldfile import parse_world
from robots.worldnames import load_world
from tests.robots.controllers.worlds import dead_end

P = schema.SchemaParams()
ARKIN = dataclasses.replace(P, beside=0.0)  # every sensed point pushes straight away (Arkin's avoid-static-obstacle)
ANGLES = jnp.asarray(LONG_RANGE.angles, jnp.float32)  # 0° first, 30° apart, + = left

# The schemas jitted (one compilation each instead of one per primitive: keeps this file fast).
move_to_goal = jax.jit(schema.move_to_goal, static_argnames="p")
avoid_static = jax.jit(schema.avoid_static, static_argnames="p")
avoid_markers = jax.jit(schema.avoid_markers, static_argnames=("radius", "p"))
noise = jax.jit(schema.noise, static_argnames="p")
schemas = jax.jit(schema.schemas, static_argnames=("p", "robot"))
avoid_lane = jax.jit(schema.avoid_lane, static_argnames=("p", "radius"))
to_wheels = jax.jit(schema.to_wheels, static_argnames="robot")


def observation(ir=None, target=(0.0, 0.5), t=0.0, pose=(0.5, 0.5, 0.0), markers=None, final=False):
    ir = np.full(len(LONG_RANGE.angles), np.inf) if ir is None else ir
    return Observation(t=np.float32(t), ir=np.asarray(ir, np.float32), target=np.asarray(target, np.float32),
                       target_id=np.int32(0), final=np.bool_(final), pose=np.asarray(pose, np.float32),
                       target_velocity=np.zeros(2, np.float32),
                       markers=np.zeros((0, 5), np.float32) if markers is None else np.asarray(markers, np.float32))


def one_reading(sensor: int, reading: float):
    ir = np.full(len(LONG_RANGE.angles), np.inf)
    ir[sensor] = reading
    return ir


def direction(v):
    return math.atan2(float(v[1]), float(v[0]))


# ------------------------------------------------------------------------------------------ the schemas

@pytest.mark.parametrize("alpha", [0.0, 0.7, -2.5])
def test_move_to_goal_points_at_the_checkpoint_saturates_far_away_and_falls_to_zero_at_it(alpha):
    for d, expected in [(1.0, P.goal_gain), (P.slow, P.goal_gain), (P.slow / 2, P.goal_gain / 2), (0.0, 0.0)]:
        v = np.asarray(move_to_goal(jnp.asarray([alpha, d]), P))
        assert np.linalg.norm(v) == pytest.approx(expected, abs=1e-7)
        if expected:
            assert direction(v) == pytest.approx(alpha, abs=1e-6)


def test_the_goal_is_reached_within_half_a_speed_unit_well_inside_5_mm():
    """Move-to-goal falls below 4 mm/s (what rounds to a zero wheel speed) within slow · 4 mm/s / goal_gain."""
    d_stop = P.slow * 0.5 * KHEPERA.speed_unit / P.goal_gain
    assert d_stop < 0.001  # 0.6 mm with the defaults
    assert np.asarray(to_wheels(move_to_goal(jnp.asarray([0.3, 0.99 * d_stop]), P))).tolist() == [0, 0]


def test_avoid_points_away_from_the_obstacle_is_zero_outside_the_sphere_and_grows_as_it_nears():
    sensor = 2  # 60° left
    phi = float(ANGLES[sensor])
    gaps = [P.margin + 0.001, 0.02, 0.03, 0.04, P.influence]
    magnitudes = []
    for g in gaps:
        v = np.asarray(avoid_static(jnp.asarray(one_reading(sensor, g)), ANGLES, ARKIN))
        magnitudes.append(np.linalg.norm(v))
        if g < P.influence:
            assert direction(v) == pytest.approx(phi - math.pi, abs=1e-5)  # straight away from the point
    assert all(a > b for a, b in zip(magnitudes, magnitudes[1:])) and magnitudes[-1] == pytest.approx(0.0, abs=1e-7)
    # Arkin's linear law between R and S: G (S − g) / (S − R)
    assert magnitudes[1] == pytest.approx(P.avoid_gain * (P.influence - 0.02) / (P.influence - P.margin), rel=1e-5)
    for beyond in (P.influence + 0.005, 0.15, np.inf):
        assert np.asarray(avoid_static(jnp.asarray(one_reading(sensor, beyond)), ANGLES, ARKIN)).tolist() == [0, 0]
    inside = np.asarray(avoid_static(jnp.asarray(one_reading(sensor, P.margin / 2)), ANGLES, ARKIN))
    assert np.linalg.norm(inside) == pytest.approx(P.margin_gain)  # Arkin's "infinity" within the safety margin
    assert P.margin_gain > P.goal_gain + P.noise_gain  # ... which nothing else outweighs


def test_a_point_the_body_passes_pushes_it_aside_not_back():
    """``beside`` 1 cm: a point at 60° left, 20 mm from the body, lies (25 + 20) · sin 60° = 39.0 mm to the side of
    the line of travel, beyond the 25 mm radius + 10 mm, so of its push G (S − g) / (S − R) = 0.24 · 30 / 40 =
    0.18 m/s only the sideways part is left: (0, −0.18 sin 60°) = (0, −0.1559). At 30° it lies 22.5 mm to the
    side, in the strip: the whole push, as Arkin's. The two walls of a passage at ±60° push the robot neither
    back nor aside (Arkin's law: 0.18 m/s back); behind the robot (120°) a point pushes straight away."""
    at60 = np.asarray(avoid_static(jnp.asarray(one_reading(2, 0.02)), ANGLES, P))
    assert at60 == pytest.approx([0.0, -0.18 * math.sin(math.pi / 3)], abs=1e-6)
    at30 = np.asarray(avoid_static(jnp.asarray(one_reading(1, 0.02)), ANGLES, P))
    assert at30 == pytest.approx([-0.18 * math.cos(math.pi / 6), -0.18 * math.sin(math.pi / 6)], abs=1e-6)
    walls = one_reading(2, 0.02)
    walls[10] = 0.02  # −60°
    assert np.asarray(avoid_static(jnp.asarray(walls), ANGLES, P)) == pytest.approx([0.0, 0.0], abs=1e-6)
    assert np.asarray(avoid_static(jnp.asarray(walls), ANGLES, ARKIN)) == pytest.approx([-0.18, 0.0], abs=1e-6)
    at120 = np.asarray(avoid_static(jnp.asarray(one_reading(4, 0.02)), ANGLES, P))
    assert at120 == pytest.approx([0.18 * 0.5, -0.18 * math.sin(2 * math.pi / 3)], abs=1e-6)
    # 60° at 15 mm: 34.6 mm to the side, inside 35 mm — pushed straight away.
    near = np.asarray(avoid_static(jnp.asarray(one_reading(2, 0.015)), ANGLES, P))
    assert direction(near) == pytest.approx(math.radians(60) - math.pi, abs=1e-5)


def test_each_sensed_point_repels_on_its_own_and_the_pushes_add_up():
    both = one_reading(1, 0.02)
    both[11] = 0.02  # 30° left and 30° right: the sideways pushes cancel, the backward ones add
    v = np.asarray(avoid_static(jnp.asarray(both), ANGLES, P))
    single = np.linalg.norm(avoid_static(jnp.asarray(one_reading(1, 0.02)), ANGLES, P))
    assert v[1] == pytest.approx(0.0, abs=1e-6) and v[0] == pytest.approx(-2 * single * math.cos(math.pi / 6), rel=1e-5)


def remembered(points, seen, moving=None):
    """A memory holding ``points`` (world frame) last sensed at ``seen`` s."""
    m = mem.empty(P.memory_points)
    k = len(points)
    return m._replace(points=m.points.at[:k].set(jnp.asarray(points, jnp.float32)),
                      seen=m.seen.at[:k].set(jnp.asarray(seen, jnp.float32)),
                      moving=m.moving.at[:k].set(jnp.asarray([False] * k if moving is None else moving)))


def test_a_remembered_point_in_the_lane_ahead_that_no_ray_reads_now_repels_as_a_reading_there_would():
    """The robot at (0.5, 0.5) faces +x; a wall's end 4.5 cm from its centre at −20°, 15.4 mm right of the line of
    travel — inside the 25 mm + 10 mm lane, and 7.8 mm and 15.4 mm off the −30° and 0° rays, which miss it. Sensed
    a tick ago (t = 1.0 s, now 1.128 s), it pushes straight away from itself as a reading of 20 mm (45 − 25) would:
    G (S − g) / (S − R) = 0.24 · 30 / 40 = 0.18 m/s, pointing at 160°."""
    end = (0.5 + 0.045 * math.cos(math.radians(-20)), 0.5 + 0.045 * math.sin(math.radians(-20)))
    obs = observation(t=1.128, target=(0.0, 0.5))
    v = np.asarray(avoid_lane(remembered([end], [1.0]), obs, P, KHEPERA.radius))
    assert np.linalg.norm(v) == pytest.approx(0.18, rel=1e-4)
    assert direction(v) == pytest.approx(math.radians(160), abs=1e-4)
    # Only the nearest point in the lane pushes: a second one behind it adds nothing.
    farther = (0.5 + 0.06, 0.5 - 0.01)
    assert np.asarray(avoid_lane(remembered([end, farther], [1.0, 1.0]), obs, P, KHEPERA.radius)) == \
        pytest.approx(v, abs=1e-7)
    # Not in the lane: 4 cm right of the line (beyond 35 mm), or behind the robot; a point a ray read this tick
    # (this tick's reading answers it); one sensed on a declared mover (its marker answers it); the rule off.
    for point, seen, moving, q in [((0.53, 0.46), 1.0, False, P), ((0.46, 0.49), 1.0, False, P),
                                   (end, 1.128, False, P), (end, 1.0, True, P),
                                   (end, 1.0, False, dataclasses.replace(P, lane=0.0))]:
        _, vs = schemas(schema.init(q)._replace(memory=remembered([point], [seen], [moving])), obs, ANGLES, q, KHEPERA)
        assert np.asarray(vs.avoid).tolist() == [0, 0], (point, seen, moving, q.lane)
    # Through the schemas (the memory updated with this tick's empty readings first: no ray passes within 5 mm).
    _, vs = schemas(schema.init(P)._replace(memory=remembered([end], [1.0])), obs, ANGLES, P, KHEPERA)
    assert np.asarray(vs.avoid) == pytest.approx(v, abs=1e-6)


def test_declared_moving_obstacles_repel_from_their_current_position_by_the_gap_between_the_bodies():
    pose = jnp.asarray([0.5, 0.5, math.pi / 2])  # facing +y
    mover = [[0.5, 0.56, 0.3, 0.0, 0.01]]  # 6 cm ahead, radius 1 cm: gap 6 − 1 − 2.5 = 2.5 cm; velocity ignored
    v = np.asarray(avoid_markers(jnp.asarray(mover), pose, KHEPERA.radius, P))
    assert v[0] < 0 and abs(v[1]) < 1e-6  # straight back, in the robot's frame
    expected = P.marker_gain * (P.influence - 0.025) / (P.influence - P.margin)
    assert np.linalg.norm(v) == pytest.approx(expected, rel=1e-4)
    far = [[0.5, 0.7, 0.0, 0.0, 0.01]]
    assert np.asarray(avoid_markers(jnp.asarray(far), pose, KHEPERA.radius, P)).tolist() == [0, 0]
    assert np.asarray(avoid_markers(jnp.zeros((0, 5)), pose, KHEPERA.radius, P)).tolist() == [0, 0]


def test_the_noise_schema_keeps_its_compass_direction_for_its_persistence_then_draws_another():
    state = schema.init(P)
    headings, vectors = [], []
    for k in range(40):  # 40 ticks of 0.128 s = 5.12 s: draws at 0, 2.048 and 4.096 s
        t = k * KHEPERA.avoid_period
        theta = 0.1 * k  # the robot turns; the noise keeps its compass direction
        state, v = noise(state, observation(t=t, pose=(0.5, 0.5, theta)), P)
        headings.append(float(state.heading))
        vectors.append(direction(v) + theta)
        assert float(np.linalg.norm(v)) == pytest.approx(P.noise_gain, rel=1e-5)
    per = round(P.persistence / KHEPERA.avoid_period)  # 16 ticks
    for start in (0, per, 2 * per):
        block = headings[start:start + per]
        assert all(h == block[0] for h in block)
        assert np.allclose(np.angle(np.exp(1j * (np.asarray(vectors[start:start + per]) - block[0]))), 0, atol=1e-5)
    assert headings[0] != headings[per] != headings[2 * per]
    # near the checkpoint the noise fades with move-to-goal, so it cannot hold the robot off the goal
    _, v = noise(schema.init(P), observation(target=(0.0, P.slow / 4)), P)
    assert float(np.linalg.norm(v)) == pytest.approx(P.noise_gain / 4, rel=1e-5)


def test_the_sum_is_clipped_to_c_star_and_driven_with_velocity_to_wheels():
    ir = one_reading(1, 0.02)
    obs = observation(ir=ir, target=(0.4, 0.3), t=0.0)
    state, v = schemas(schema.init(P), obs, ANGLES, P, KHEPERA)
    total = np.asarray(v.goal + v.avoid + v.markers + v.noise)
    assert np.asarray(v.total) == pytest.approx(total)
    _, wheels = schema.step(schema.init(P), obs, ANGLES, p=P, robot=KHEPERA)
    expected = jax.jit(velocity_to_wheels)(direction(total), min(np.linalg.norm(total), KHEPERA.max_wheel_speed))
    assert np.asarray(wheels) == pytest.approx(np.asarray(expected), abs=1e-6)
    # a vanishing sum is no motion at all, not a spin towards its direction
    assert np.asarray(to_wheels(jnp.asarray([-0.003, 0.001]))).tolist() == [0, 0]


def test_schema_is_registered_drives_no_map_and_spells_its_parameters():
    spec = parse_architecture("schema:sensors=short,noise_gain=0")
    assert not spec.uses_map and spec.default_chart is None
    assert spec.label == "schema:sensors=short,noise_gain=0"
    controller = spec.build()
    assert controller.sensors == KHEPERA.short_range and controller.name == "schema"
    with pytest.raises(Exception, match="margin must be < influence"):
        parse_architecture("schema:margin=0.06")


# ------------------------------------------------------------------------------------------ runs

def test_the_robot_stops_at_the_goal_in_the_open_arena():
    rec = run_architecture(load_world("open-arena"), parse_architecture("schema"), seed=0)
    out = rec.outcome()
    assert out["reached"] and out["ended"] == "stopped at the goal" and out["collisions"] == 0
    assert out["final_distance_m"] < 0.005 and out["map"] is None and out["trial"] is None
    assert np.hypot(0.3, 0.3) <= out["path_m"] < 1.1 * np.hypot(0.3, 0.3)


def recording(controller: Controller, log: list) -> Controller:
    """The controller, with the noise schema's direction logged every tick."""

    def step(state, obs):
        state, command = controller.step(state, obs)
        log.append(float(state.heading))
        return state, command

    return dataclasses.replace(controller, step=step)


def test_a_run_is_a_pure_function_of_its_seed_and_another_seed_draws_other_noise():
    world, spec = load_world("three-rooms-moving"), parse_architecture("schema")
    config = ScenarioConfig(time_limit=8.0)
    logs = [[], [], []]
    a, b, c = (run_scenario(world, recording(spec.build(), log), seed=seed, config=config)
               for log, seed in zip(logs, (3, 3, 4)))
    assert a.outcome() == b.outcome() and logs[0] == logs[1]
    np.testing.assert_array_equal(a.poses, b.poses)
    assert not np.array_equal(a.poses, c.poses)
    per = round(schema.SchemaParams().persistence / KHEPERA.avoid_period)
    draws = lambda log: log[::per]  # noqa: E731 - one direction per persistence period
    assert draws(logs[0])[0] == draws(logs[2])[0]  # the first draw: the same start pose for every seed
    assert draws(logs[0])[1:] != draws(logs[2])[1:]  # then the seed's motor noise has moved the robot elsewhere


# ------------------------------------------------------------------------------------------ local minima

#: A world without noise (no wheel slip, exact unquantised IR): Arkin's Fig. 4.13A, "exact counterbalancing".
IDEAL = dataclasses.replace(KHEPERA, actuator_noise=0.0,
                            long_range=dataclasses.replace(KHEPERA.long_range, noise=0.0, resolution_m=0.0))


def across_the_way(width: float):
    """A 2 cm thin obstacle ``width`` across, exactly midway on the straight line from the start to the goal."""
    return parse_world({"name": "across", "size": [1.2, 1.0], "start": [0.2, 0.5, 0.0], "goal": [0.9, 0.5],
                        "unforeseen": [{"type": "box", "center": [0.5, 0.5], "size": [0.02, width]}]})


def test_a_point_straight_ahead_of_the_goal_balances_move_to_goal_where_arkins_laws_say():
    """The local minimum in numbers: one sensed point straight between robot and goal, ``g*`` from the body,
    with G_goal = G_avoid (S − g*) / (S − R): g* = S − (S − R) G_goal / G_avoid = 23.3 mm with the defaults."""
    p = dataclasses.replace(P, noise_gain=0.0)
    g_star = p.influence - (p.influence - p.margin) * p.goal_gain / p.avoid_gain
    assert g_star == pytest.approx(0.02333, abs=1e-5)

    def total(gap, noise_gain=0.0):
        q = dataclasses.replace(p, noise_gain=noise_gain)
        _, v = schemas(schema.init(q), observation(one_reading(0, gap), target=(0.0, 0.3)), ANGLES, q, KHEPERA)
        return np.asarray(v.total)

    assert np.linalg.norm(total(g_star)) < 1e-6  # the summed vector vanishes ...
    _, wheels = schema.step(schema.init(p), observation(one_reading(0, g_star), target=(0.0, 0.3)), ANGLES, p=p,
                            robot=KHEPERA)
    assert np.asarray(wheels).tolist() == [0, 0]  # ... and the robot stands
    assert total(g_star + 0.005)[0] > 0 > total(g_star - 0.005)[0]  # pulled in from further, pushed out from nearer
    assert np.linalg.norm(total(g_star, noise_gain=P.noise_gain)) == pytest.approx(P.noise_gain, rel=1e-4)  # noise


def test_without_noise_an_obstacle_straight_across_the_way_is_a_local_minimum_and_the_noise_schema_gets_past():
    """Arkin Fig. 4.13: without noise the forces counterbalance and the robot stalls short of an 8 cm obstacle
    straight across its way; with the noise schema (default gains) it gets round and stops at the goal. Arkin's
    radial pushes (``beside=0``): with ``beside`` (the default) the robot gets round even without the noise."""
    world = across_the_way(0.08)
    config = ScenarioConfig(time_limit=40.0, recover=False)  # the local minimum itself, not the recovery from it
    still = run_scenario(world, schema.build(dataclasses.replace(ARKIN, noise_gain=0.0), robot=IDEAL), config=config)
    assert still.trapped and still.collisions == 0
    x, y = still.poses[-1][:2]
    assert 0.42 < x < 0.44 and abs(y - 0.5) < 0.03  # 2.6 ± 1 cm from the obstacle's face (x = 0.49) to the body
    last = still.times >= still.times[-1] - 15.0
    assert np.ptp(still.poses[last, 0]) < 0.005 and np.ptp(still.poses[last, 1]) < 0.005  # not a millimetre of way
    for seed in range(3):
        free = run_scenario(world, schema.build(dataclasses.replace(ARKIN, seed=seed), robot=IDEAL), config=config)
        assert free.reached and free.collisions == 0 and free.time_s < 15.0


def test_the_robot_stops_at_a_goal_beside_a_wall_only_when_nothing_beyond_the_goal_repels_it():
    """A goal 1.5 cm (body to wall) before a wall straight ahead (:func:`~tests.robots.controllers.worlds.dead_end`). Arkin's laws balance
    move-to-goal against one point straight ahead at g* = 23.3 mm from the body (above), so repelled by every
    reading the robot stops at least g* − 15 mm = 8.3 mm short of the goal; repelled by none beyond the goal it
    stops within 5 mm of it."""
    config = ScenarioConfig(time_limit=30.0, recover=False)
    near = run_architecture(dead_end(0.015), parse_architecture("schema"), seed=0, config=config)
    assert near.reached and near.collisions == 0 and near.final_distance_m < 0.005
    every = run_architecture(dead_end(0.015), parse_architecture("schema:avoid=all"), seed=0, config=config)
    assert not every.arrived and every.collisions == 0 and every.final_distance_m > 0.0083
