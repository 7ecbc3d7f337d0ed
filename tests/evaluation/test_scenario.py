"""The scenario runner (evaluation.scenario): checkpoints, the stop at the goal, collisions, events and
replanning, traps and recovery; and thesis ch. 6.2 as a scenario suite — who reaches the goal where, on
seeds 0–9 (slow), and a quick version."""

import functools
import json

import numpy as np
import pytest

from ekm.errors import InputError
from evaluation.scenario import ScenarioConfig, run_architecture, run_scenario, with_sensed
from robots.controllers.base import Controller
from robots.controllers.spec import parse_architecture
from robots.kinematics import egocentric
from robots.params import KHEPERA
from robots.worldfile import parse_world
from robots.worldnames import load_world

OUTCOME_KEYS = ["world", "architecture", "reached", "time_s", "path_m", "collisions", "checkpoints_reached",
                "replans", "trapped", "final_distance_m"]


def constant(command, name="constant"):
    """A controller that always sends ``command`` (the runner never asks what it runs)."""
    return Controller(name=name, spec=name, sensors=KHEPERA.short_range, init=lambda: 0,
                      step=lambda state, obs: (state, np.asarray(command, float)))


def steering(gain=1.0):
    """An analytic reference: turn towards the checkpoint and slow down near it (no obstacle avoidance)."""

    def step(state, obs):
        alpha, d = float(obs.target[0]), float(obs.target[1])
        v = min(0.12, 1.5 * d) * max(0.0, np.cos(alpha))
        w = 2.0 * alpha
        return state, np.array([v - w * KHEPERA.wheel_base / 2, v + w * KHEPERA.wheel_base / 2]) * gain

    return Controller(name="steer", spec="steer", sensors=KHEPERA.short_range, init=lambda: 0, step=step)


def test_an_open_arena_run_stops_at_the_goal_with_the_outcome_record_of_design_6():
    world = load_world("open-arena")
    rec = run_scenario(world, steering(), seed=0)
    out = rec.outcome()
    assert list(out)[:len(OUTCOME_KEYS)] == OUTCOME_KEYS
    assert out["reached"] and out["arrived"] and out["collisions"] == 0 and not out["trapped"]
    assert out["final_distance_m"] < 0.005 and out["checkpoints_reached"] == 1 and out["replans"] == 0
    straight = np.hypot(0.3, 0.3)
    assert straight <= out["path_m"] < 1.3 * straight
    # time_s is when the stop was sent at the goal; one more period lets the wheels spin down
    assert out["time_s"] == pytest.approx(rec.times[-1] - KHEPERA.avoid_period) and 2.0 < out["time_s"] < 20.0
    json.dumps(out, allow_nan=False)


def test_a_run_is_a_pure_function_of_its_seed():
    world = load_world("three-rooms-moving")
    spec = parse_architecture("fusion")
    config = ScenarioConfig(time_limit=8.0)
    a, b = (run_architecture(world, spec, seed=3, config=config) for _ in range(2))
    assert a.outcome() == b.outcome()
    np.testing.assert_array_equal(a.poses, b.poses)
    c = run_architecture(world, spec, seed=4, config=config)
    assert not np.array_equal(a.poses[:len(c.poses)], c.poses[:len(a.poses)])


def test_driving_into_a_wall_is_counted_as_collisions_and_never_reaches():
    world = parse_world({"name": "box", "size": [0.5, 0.5], "start": [0.25, 0.25, 0.0], "goal": [0.1, 0.25]})
    rec = run_scenario(world, constant([0.12, 0.12]), seed=0, config=ScenarioConfig(time_limit=4.0, trap_after=3.0))
    assert rec.collisions >= 1 and len(rec.collision_log) == rec.collisions
    assert not rec.reached and rec.poses[:, 0].max() <= 0.5 - 0.005 - KHEPERA.radius + 0.003  # the wall holds


def test_a_robot_that_makes_no_progress_is_reported_trapped_after_the_set_time():
    world = load_world("open-arena")
    rec = run_scenario(world, constant([0.0, 0.0]), seed=0, config=ScenarioConfig(trap_after=5.0, recover=False))
    assert rec.trapped and rec.ended == "trapped" and not rec.reached
    assert 5.0 <= rec.time_s <= 5.0 + 2 * KHEPERA.avoid_period + 1e-9  # measured from the first tick's reading
    assert rec.trap_log and rec.trap_log[0][0] == pytest.approx(rec.time_s)


def test_a_known_event_changes_the_map_and_triggers_exactly_one_replan():
    """Fig. 6.5: the lower doorway of three-rooms-changed closes at 6 s; the planner replans through the upper."""
    world = load_world("three-rooms-changed")
    rec = run_architecture(world, parse_architecture("fields"), seed=0, config=ScenarioConfig(time_limit=9.0))
    assert rec.replans == 1 and [p.reason for p in rec.plans] == ["start", "event"]
    event_time = world.events[0].at_s
    assert event_time <= rec.plans[1].t < event_time + 0.13  # at the first tick after the event
    old, new = rec.plans[0].checkpoints, rec.plans[1].checkpoints
    assert old[-2][1] < 0.22 < new[-2][1]  # the checkpoint before the goal moved to the upper doorway
    np.testing.assert_allclose(new[-1], world.goal)


def test_an_unknown_event_changes_the_world_but_not_the_plan():
    doc = {"name": "told-or-not", "size": [1.0, 0.6], "start": [0.1, 0.3, 0.0], "goal": [0.9, 0.3],
           "events": [{"at_s": 1.0, "add": [{"type": "box", "center": [0.5, 0.05], "size": [0.05, 0.05]}],
                       "known": False}]}
    rec = run_scenario(parse_world(doc), steering(), seed=0, config=ScenarioConfig(time_limit=4.0))
    assert rec.replans == 0


def test_checkpoints_count_within_5_mm_on_the_sub_steps():
    world = load_world("three-rooms")
    rec = run_scenario(world, steering(), seed=1, config=ScenarioConfig(checkpoints="thesis"))
    cps = rec.plans[0].checkpoints
    assert rec.checkpoints_reached == len(cps)
    for (t, x, y), cp in zip(rec.checkpoint_log[:-1], cps[:-1]):  # the first passage, on the 16 ms sub-steps
        i = int(np.searchsorted(rec.times, t - 1e-9))
        assert rec.times[i] == pytest.approx(t)
        assert np.linalg.norm(rec.poses[i, :2] - cp) < 0.005
        assert np.all(np.linalg.norm(rec.poses[:i, :2] - cp, axis=1) >= 0.005)


def test_a_moving_goal_is_caught_under_the_robots_body():
    world = load_world("moving-target")
    rec = run_scenario(world, steering(), seed=0)
    assert rec.reached and rec.ended == "caught the moving goal"
    t = rec.times[-1]
    assert np.linalg.norm(rec.poses[-1, :2] - np.asarray(world.goal_at(t))) < KHEPERA.radius + 0.005


def test_recovery_adds_the_sensed_obstacle_to_the_map_and_replans():
    world = load_world("extended-obstacle")
    # ch. 4.4's command fusion, which the long wall traps (the default's turned Z backs it round the wall's end)
    rec = run_architecture(world, parse_architecture("fusion:facing=front,remember=false,lane=1"), seed=0,
                           config=ScenarioConfig(recover=True, trap_after=10.0, time_limit=40.0))
    assert rec.recoveries >= 1 and "recovery" in [p.reason for p in rec.plans]
    first = next(p for p in rec.plans if p.reason == "recovery")
    assert len(first.checkpoints) > 1  # a detour round the wall the planner did not know about
    assert len(first.added) > 0 and np.all(np.abs(first.added[:, 0] - 0.6) < 0.03)  # points of that wall


def test_sensed_points_on_known_walls_are_not_added_again():
    world = load_world("three-rooms")
    on_wall = np.array([[0.4, 0.1], [0.4, 0.5]])
    new = np.array([[0.6, 0.3]])
    grown, added = with_sensed(world, np.vstack([on_wall, new]), [0.02, 0.02, 0.02], 0.01)
    assert len(grown.obstacles) == len(world.obstacles) + 1
    np.testing.assert_allclose(added, [[0.6, 0.3]])
    assert grown.obstacles[-1].center == pytest.approx((0.6, 0.3))


def test_a_world_the_planner_cannot_route_through_is_an_input_error():
    doc = {"name": "walled-off", "size": [1.0, 0.5], "walls": [[0.5, 0.0, 0.5, 0.5]], "start": [0.2, 0.25, 0.0],
           "goal": [0.8, 0.25]}
    with pytest.raises(InputError, match="no route"):
        run_scenario(parse_world(doc), steering(), seed=0)


def test_egocentric_target_is_what_the_controller_sees():
    seen = []

    def step(state, obs):
        seen.append((np.asarray(obs.pose, float), np.asarray(obs.target, float)))
        return state, np.zeros(2)

    ctl = Controller(name="look", spec="look", sensors=KHEPERA.long_range, init=lambda: 0, step=step)
    world = load_world("open-arena")
    run_scenario(world, ctl, seed=0, config=ScenarioConfig(time_limit=0.5))
    pose, target = seen[0]
    np.testing.assert_allclose(target, egocentric(pose, np.asarray(world.goal)), rtol=1e-5)


def test_a_moving_obstacle_that_shoves_the_robot_into_a_wall_is_a_collision_not_a_tunnel():
    """The mover (infinite mass) drives the standing robot into the arena's wall: the wall holds the robot,
    the contact is counted, the run goes on."""
    world = parse_world({"name": "squeeze", "size": [1.0, 0.4], "start": [0.5, 0.2, 0.0], "goal": [0.1, 0.1],
                         "moving": [{"shape": {"type": "circle", "radius": 0.025},
                                     "path": {"type": "line", "from": [0.1, 0.2], "to": [0.97, 0.2],
                                              "speed_mps": 0.1, "bounce": False}}]})
    rec = run_scenario(world, constant([0.0, 0.0]), seed=0, config=ScenarioConfig(time_limit=12.0, trap_after=30.0))
    inside = 1.0 - 0.5 * world.wall_thickness - KHEPERA.radius
    assert rec.ended == "time limit" and rec.collisions >= 1 and not rec.reached
    assert np.all(np.isfinite(rec.poses)) and rec.poses[:, 0].max() <= inside + 0.003  # shoved up to the wall, not through
    assert rec.poses[-1, 0] > inside - 0.01


# --------------------------------------------------------------------------- issue 21: recovery, look-ahead

def test_recovery_leaves_an_8_cm_doorway_open_that_its_jambs_noisy_points_would_close():
    """A wall across the arena with a door 8 cm wide between the walls' surfaces (the robot is 5 cm across).
    Points sensed on the jambs from 15 cm away carry up to 3 × 10 % noise: one seen 1.5 cm inside the door,
    explained by the jamb within 3 · 0.1 · 0.15 + 0.5 cm, must not join the map; the planner still routes
    through the door. A point in the middle of the door, seen from 3 cm, is an obstacle: the door closes."""
    from planner import NoRouteError, plan

    doc = {"name": "door", "size": [1.0, 0.6], "walls": [[0.5, 0.0, 0.5, 0.255], [0.5, 0.345, 0.5, 0.6]],
           "start": [0.2, 0.3, 0.0], "goal": [0.8, 0.3]}
    world = parse_world(doc, "door.json")  # door: y 0.26 .. 0.34 between the surfaces (caps 5 mm round the ends)
    jambs = np.array([[0.5, 0.26 + 0.015], [0.5, 0.34 - 0.015]])
    grown, added = with_sensed(world, jambs, [0.15, 0.15], 0.005)
    assert len(added) == 0 and grown == world
    assert plan(grown).route
    blocker = np.array([[0.5, 0.30]])
    grown, added = with_sensed(world, blocker, [0.03], 0.005)
    np.testing.assert_allclose(added, blocker)
    with pytest.raises(NoRouteError):
        plan(grown)


def test_recovery_plans_round_the_near_readings_where_all_it_sensed_closes_every_way():
    """The door of the test above, 8 cm between its jambs, the robot (5 cm across) before it. Sensor 2 (+10°) of
    the short-range ring read 4 cm to a point in the middle of the door, and 1 cm to one far from it. Everything
    sensed closes the door (the planner finds no route); with ``sensed_near`` 2 cm the recovery plans round the
    1 cm reading alone and goes through the door; a 1 cm reading in the door closes it at every step but the
    last, the map as it was."""
    from evaluation.scenario import first_plan, recovery
    from planner import NoRouteError, plan

    doc = {"name": "door", "size": [1.0, 0.6], "walls": [[0.5, 0.0, 0.5, 0.255], [0.5, 0.345, 0.5, 0.6]],
           "start": [0.2, 0.3, 0.0], "goal": [0.8, 0.3]}
    world = parse_world(doc, "door.json")
    ctl, config = steering(), ScenarioConfig(sensed_near=0.02)
    ray = np.array([np.cos(np.radians(10)), np.sin(np.radians(10))])

    def seen(point, reading):  # a tick on which sensor 2 read ``reading`` (m) to ``point``
        readings = np.full(8, np.inf)
        readings[2] = reading
        return (0.0, np.append(np.asarray(point) - (0.025 + reading) * ray, 0.0), readings, np.zeros((0, 5)))

    in_door, far_off = np.array([0.5, 0.3]), np.array([0.2, 0.1])
    with pytest.raises(NoRouteError):
        plan(with_sensed(world, np.array([in_door]), [0.04], 0.005)[0])
    start = first_plan(world, KHEPERA, config)
    found = recovery(start, world, [seen(in_door, 0.04), seen(far_off, 0.01)], ctl, (0.3, 0.3), 1.0, config)
    assert found is not None
    current, known, added = found
    np.testing.assert_allclose(added, [far_off], atol=0.005)  # snapped to the 5 mm discs' grid
    assert len(known.obstacles) == len(world.obstacles) + 1
    assert current.checkpoints[-1].tolist() == [0.8, 0.3]
    current, known, added = recovery(start, world, [seen(in_door, 0.01)], ctl, (0.3, 0.3), 1.0, config)
    assert len(added) == 0 and known == world and current.checkpoints[-1].tolist() == [0.8, 0.3]


def test_points_the_ir_saw_on_a_declared_mover_never_join_the_map():
    from evaluation.scenario import sensed_points

    ctl = steering()  # short-range ring: 8 sensors
    readings = np.full(8, np.inf)
    readings[2] = 0.02  # sensor at +10 degrees sees something 2 cm off the rim
    pose = np.array([0.5, 0.5, 0.0])
    hit = np.array([0.5 + (0.025 + 0.02) * np.cos(np.radians(10)), 0.5 + (0.025 + 0.02) * np.sin(np.radians(10))])
    mover_there = np.array([[hit[0] + 0.02, hit[1], 0.05, 0.0, 0.025]])
    mover_away = np.array([[0.1, 0.1, 0.0, 0.0, 0.025]])
    pts, _ = sensed_points([(0.0, pose, readings, mover_there)], ctl)
    assert len(pts) == 0
    pts, r = sensed_points([(0.0, pose, readings, mover_away)], ctl)
    np.testing.assert_allclose(pts, [hit], atol=1e-12) and np.testing.assert_allclose(r, [0.02])


def test_a_checkpoint_is_blocked_by_an_unexplained_point_within_the_robots_radius_of_it():
    from evaluation.scenario import blocked_checkpoint
    from planner.bitmap import padded_obstacles

    ctl = steering()  # short-range ring: sensor 2 at +10 degrees; radius 2.5 cm
    world = parse_world({"name": "wall", "size": [1.0, 1.0], "walls": [[0.5, 0.0, 0.5, 0.4]], "start": [0.1, 0.1, 0.0],
                         "goal": [0.9, 0.1]}, "wall.json")
    sight = padded_obstacles(world, 0.0, KHEPERA.radius)
    readings = np.full(8, np.inf)
    readings[2] = 0.02
    ray = np.array([np.cos(np.radians(10)), np.sin(np.radians(10))])
    pose = np.array([0.3, 0.7, 0.0])
    hit = pose[:2] + 0.045 * ray  # (0.34432, 0.70781), in the open, 30 cm from the wall's end
    tick = [(0.0, pose, readings, np.zeros((0, 5)))]
    # the reading's doubt, one standard deviation: 10 % of 2 cm = 2 mm; blocked within 2.5 - 0.2 = 2.3 cm
    assert blocked_checkpoint(tick, ctl, hit + (0.022, 0.0), sight)  # the disc overlaps the point, had it erred 2 mm
    assert not blocked_checkpoint(tick, ctl, hit + (0.024, 0.0), sight)  # within the radius, but not beyond doubt
    assert not blocked_checkpoint(tick, ctl, hit + (0.03, 0.0), sight)  # 3 cm: the disc fits beside it
    assert not blocked_checkpoint([(0.0, pose, np.full(8, np.inf), np.zeros((0, 5)))], ctl, hit, sight)  # saw nothing
    on_mover = np.array([[hit[0] + 0.01, hit[1], 0.05, 0.0, 0.025]])
    assert not blocked_checkpoint([(0.0, pose, readings, on_mover)], ctl, hit + (0.005, 0.0), sight)
    # the wall's face (x = 0.495, its half thickness 5 mm) read at 2 cm from (0.4446, 0.2): a checkpoint 5 mm off it
    # is within 2.3 cm of the point, but the map explains the point (a wall's point, the reading's noise): no
    wall_pose = np.array([0.495 - 0.045 * ray[0], 0.2, 0.0])
    face = wall_pose[:2] + 0.045 * ray
    assert abs(face[0] - 0.495) < 1e-12
    assert not blocked_checkpoint([(0.0, wall_pose, readings, np.zeros((0, 5)))], ctl, face - (0.005, 0.0), sight)


def test_the_first_plan_keeps_off_a_declared_movers_lane_unless_lanes_are_off():
    """The corridor of tests/planner/test_lanes.py: a box shuttles down its middle, and the straight route from
    start to goal runs along the box's lane. Both engines follow the plan that keeps off it (planner.plan's
    ``lanes`` with the config's margin and detour); ``lane_margin=None`` and the thesis's checkpoints the plain
    plan."""
    from evaluation.jaxrun import start_run
    from planner import plan
    from tests.planner.test_lanes import corridor

    world = corridor()
    assert not np.array_equal(plan(world, lanes=(0.01, 1.3)).checkpoints, plan(world).checkpoints)
    for config, lanes in [(ScenarioConfig(time_limit=0.3), (0.01, 1.3)),
                          (ScenarioConfig(time_limit=0.3, lane_margin=None), None),
                          (ScenarioConfig(time_limit=0.3, checkpoints="thesis"), None)]:  # the thesis's set-up
        expected = plan(world, checkpoints=config.checkpoints, lanes=lanes)
        rec = run_scenario(world, constant([0.0, 0.0]), seed=0, config=config)
        np.testing.assert_array_equal(rec.plans[0].checkpoints, expected.checkpoints)
        assert rec.plans[0].avoided == expected.avoided  # what the run plot hatches
        run = start_run(world, constant([0.0, 0.0]), 0, config, "constant")
        np.testing.assert_array_equal(run.plan.checkpoints, expected.checkpoints)
        assert run.plan.avoided == expected.avoided


def test_the_look_ahead_sees_a_kept_off_lane_as_an_obstacle():
    """The look past a checkpoint is made on the map the plan was made on: the lane, padded by the robot's radius."""
    from evaluation.scenario import sight_of
    from planner import plan
    from tests.planner.test_lanes import corridor

    world = corridor()
    kept = plan(world, lanes=(0.01, 1.3))
    sight = sight_of(world, 0.0, kept, 0.025)
    assert (kept.avoided[0], 0.025) in sight and len(sight) == len(sight_of(world, 0.0, plan(world), 0.025)) + 1


@pytest.mark.parametrize("bad, match", [({"lane_margin": -0.01}, "lane_margin must be a number >= 0 or None"),
                                        ({"lane_margin": float("nan")}, "lane_margin"),
                                        ({"lane_detour": 0.9}, "lane_detour must be >= 1")])
def test_bad_lane_settings_are_refused_with_one_line(bad, match):
    with pytest.raises(InputError, match=match):
        ScenarioConfig(**bad)


def test_a_robot_whose_detour_brings_a_later_checkpoint_into_view_moves_on_to_it():
    """Three rooms in a row; the robot is placed in the last room, from where the goal is in view: the runner
    passes the checkpoints in the doorways behind it within its first looks (every 0.5 s, three checkpoints
    ahead at a time) and steers for the goal, 0.16 m away, instead of driving back through the doors."""
    from dataclasses import replace

    world = load_world("three-rooms")
    moved = replace(world, start=(1.0, 0.3, 0.0))
    rec = run_scenario(moved, steering(), seed=0, config=ScenarioConfig(time_limit=10.0))
    assert rec.reached and rec.plans[0].checkpoints.shape[0] == 1  # planned from there: the goal only
    # The same start, with the plan of the original start forced on it: behaves as if the doors were passed.
    from evaluation import scenario

    original = scenario.plan

    def old_plan(w, **kw):
        return original(world, **kw)

    scenario.plan = old_plan
    try:
        rec = run_scenario(moved, steering(), seed=0, config=ScenarioConfig(time_limit=10.0))
    finally:
        scenario.plan = original
    assert rec.reached and rec.checkpoints_reached == len(original(world).checkpoints)
    assert all(t <= 1.0 for t, *_ in rec.checkpoint_log[:-1])  # every doorway checkpoint passed at the first looks
    assert rec.path_m < 0.3


# ------------------------------------------------------------------------------------------- thesis ch. 6.2

# A run succeeds when the robot stops at the goal without a single collision (``reached``). One set of
# parameters per architecture, the defaults, for every world; the runs are set up as the thesis's were —
# its greedy checkpoints (ch. 3.2.3) and no recovery, so the trap monitor ends a trapped run.

# Command fusion with ch. 4.4's vehicle: Z's forward-facing sensors always the robot's front, reading its sensors
# alone (the defaults turn Z round while the map reverses and read the memory near the body, extensions measured on
# the generated suite: docs/reproduce/architectures.md).
FUSION = "fusion:facing=front,remember=false,lane=1,escape_s=0"
# ch. 6.2.2: 12 long-range sensors, both modules at 0.128 s
FUSION_LONG = "fusion:sensors=long,period=0.128,facing=front,remember=false,lane=1,escape_s=0"
THESIS = ScenarioConfig(checkpoints="thesis", recover=False)


@functools.lru_cache(maxsize=None)
def outcome(world: str, architecture: str, seed: int) -> dict:
    return run_architecture(load_world(world), parse_architecture(architecture), seed=seed, config=THESIS).outcome()


def runs(world, architecture, seeds):
    return [outcome(world, architecture, s) for s in seeds]


def count(records, key):
    return sum(bool(r[key]) for r in records)


# ----------------------------------------------------------------------------------------------- quick

def test_quick_fusion_reaches_the_goal_past_a_small_unforeseen_obstacle():
    assert count(runs("three-rooms-static", FUSION, range(3)), "reached") == 3


def test_quick_neural_fields_negotiate_the_trap_obstacles_that_trap_command_fusion():
    for world in ("extended-obstacle", "concave-obstacle"):
        assert count(runs(world, "fields", range(3)), "reached") == 3, world
    assert count(runs("concave-obstacle", FUSION, range(3)), "trapped") == 3


# ------------------------------------------------------------------------------------- seeds 0–9 (slow)

@pytest.mark.slow
@pytest.mark.parametrize("world", ["three-rooms-static", "three-rooms-moving", "three-rooms-changed"])
def test_ch_6_2_1_command_fusion_with_short_range_sensors_reaches_the_goal(world):
    records = runs(world, FUSION, range(10))
    assert count(records, "reached") >= 9, [r["ended"] for r in records]
    if world == "three-rooms-changed":
        assert all(r["replans"] >= 1 for r in records if r["reached"])  # through the upper doorway


@pytest.mark.slow
@pytest.mark.parametrize("world", ["three-rooms-static", "extended-obstacle", "concave-obstacle"])
def test_ch_6_2_2_neural_fields_with_long_range_sensors_reach_the_goal(world):
    assert count(runs(world, "fields", range(10)), "reached") >= 8


@pytest.mark.slow
def test_ch_6_2_2_neural_fields_take_a_shorter_path_than_command_fusion_where_both_succeed():
    for world in ("three-rooms-static", "extended-obstacle", "concave-obstacle"):
        both = [(f["path_m"], c["path_m"]) for f, c in zip(runs(world, "fields", range(10)),
                                                           runs(world, FUSION, range(10)))
                if f["reached"] and c["reached"]]
        if both:
            fields_path, fusion_path = np.mean(both, axis=0)
            assert fields_path < fusion_path, (world, both)


@pytest.mark.slow
@pytest.mark.parametrize("world", ["extended-obstacle", "concave-obstacle"])
@pytest.mark.parametrize("architecture", [FUSION, FUSION_LONG])
def test_ch_6_2_2_command_fusion_is_trapped_by_extended_and_concave_obstacles(world, architecture):
    records = runs(world, architecture, range(10))
    assert count(records, "trapped") >= 8 and count(records, "reached") <= 1


def test_a_caught_moving_goal_has_no_stop_distance_and_a_still_one_has_its_own():
    """Precision is where the robot stopped at a still goal (within the 5 mm); a moving goal is caught within the
    body's radius, which says nothing of the robot's precision."""
    spec = parse_architecture("schema")
    caught = run_architecture(load_world("moving-target"), spec, seed=0).outcome()
    assert caught["arrived"] and caught["stop_distance_m"] is None
    still = run_architecture(load_world("open-arena"), spec, seed=0).outcome()
    assert still["arrived"] and still["stop_distance_m"] == pytest.approx(still["final_distance_m"], abs=1e-5)
    assert still["stop_distance_m"] < 0.005


#: A wall from the bottom up to y = 0.5, the goal behind it; the look ahead took the robot past the checkpoint
#: above the wall's end (index 1) on to the goal (index 2).
JAMB = parse_world({"name": "jamb", "size": [1.0, 0.8], "walls": [[0.5, 0.0, 0.5, 0.5]], "start": [0.3, 0.35, 0.0],
                    "goal": [0.8, 0.3]}, "jamb.json")
JAMB_CHECKPOINTS = np.array([[0.2, 0.6], [0.5, 0.6], [0.8, 0.3]])


def looked_back(position, tick, looked_past=(1, 1), look_back=3):
    """The checkpoint a robot at ``position`` heads for after the runner's passing on ``tick``, having headed for
    the goal (index 2) of :data:`JAMB`; with the monitor's checkpoint."""
    from types import SimpleNamespace

    from evaluation.monitor import TrapMonitor
    from evaluation.scenario import Course, pass_checkpoints
    from planner.bitmap import padded_obstacles

    shell = SimpleNamespace(config=ScenarioConfig(look_back=look_back), sim=SimpleNamespace(pose=np.array([*position, 0.0])),
                            rec=SimpleNamespace(checkpoint_log=[]), monitor=TrapMonitor(20.0, 0.01))
    plan = SimpleNamespace(checkpoints=JAMB_CHECKPOINTS, rule="visible")
    course = Course(plan, JAMB, padded_obstacles(JAMB, 0.0, KHEPERA.radius), index=2, target_id=5,
                    looked_past=looked_past)
    after = pass_checkpoints(shell, course, 0.0, tick)
    return after.index, after.target_id, shell.monitor.index


def test_a_robot_that_a_wall_cuts_off_from_its_checkpoint_turns_back_to_the_one_it_was_looked_past():
    """At (0.3, 0.35) the straight way to the goal (0.8, 0.3) crosses the wall at y = 0.33; the way to the checkpoint
    above the wall's end passes the end 6.25 cm off, 3.6 cm clear of the body (1.2 cm are asked): on a look (every
    4th tick) the robot turns back to it, a new target for the controller and the monitor."""
    assert looked_back((0.3, 0.35), tick=4) == (1, 6, 1)
    assert looked_back((0.3, 0.35), tick=5) == (2, 5, 0)  # looks come every 4th tick only
    assert looked_back((0.3, 0.35), tick=4, looked_past=(0, -1)) == (2, 5, 0)  # it reached 1: it does not go back
    assert looked_back((0.3, 0.35), tick=4, look_back=0) == (2, 5, 0)
    assert looked_back((0.6, 0.6), tick=4) == (2, 5, 0)  # past the wall's end: the goal in clear view


def test_a_robot_pressed_against_a_wall_s_end_does_not_turn_back_when_its_way_keeps_clear_of_it():
    """At (0.525, 0.51) the body is 3.1 mm into the wall's end (the end's corner 26.9 mm from the centre, 5 mm of
    wall and 25 of body): every straight way from there starts that close; the way to the goal (0.8, 0.3) only draws
    away from the end, so no wall comes between. The look ahead took the robot on at this slack (its need, the
    slack less 3 mm): the look back must not undo it (before, it did, and the two alternated every look)."""
    assert looked_back((0.525, 0.51), tick=4) == (2, 5, 0)
