"""Samba on this package's robot: Riekki's experiments (1999, Figs. 29, 30, 31, 50) reproduced in the pymunk
world, the stop at a fixed goal, the arbiter's hysteresis, the binding of object markers and the moving target."""

import dataclasses
import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.angles import wrap
from ekm.errors import InputError
from evaluation.scenario import ScenarioConfig, run_architecture, run_scenario
from robots.controllers import actionmaps as am
from robots.controllers import samba
from robots.controllers.base import Observation, velocity_to_wheels
from robots.controllers.spec import ARCHITECTURES, parse_architecture
from robots.kinematics import is_stop_command
from robots.params import KHEPERA
from robots.world import PymunkWorld
from robots.worldfile import LinePath, parse_world

#: Fig. 29/30: a stationary obstacle (a declared "moving" one that stands still, so that it is a known object
from robots.worldnames import load_world
#: marker) straight between the robot and its target.
BEHIND = parse_world({
    "name": "target-behind-obstacle", "size": [1.0, 0.6],
    "moving": [{"shape": {"type": "circle", "radius": 0.04},
                "path": {"type": "line", "from": [0.5, 0.3], "to": [0.5, 0.3], "speed_mps": 0.001}}],
    "start": [0.1, 0.3, 0.0], "goal": [0.9, 0.3]})
GROWN = 0.04 + KHEPERA.radius + samba.SambaParams().clearance  # the obstacle as the Avoid map sees it


@partial(jax.jit, static_argnames=("p", "robot"))
def _tick(state, obs, p, robot):
    """samba.step, also returning the tick's maps and choice (one compilation per parameter set)."""
    tick = samba.maps(state, obs, p, robot)
    return tick, jnp.where(tick.go, velocity_to_wheels(tick.direction, tick.speed, robot), 0.0)


_RUNS: dict = {}


def logged_run(world, arch, seed=0):
    """Run ``arch`` through ``world`` (cached); also return per tick (t, pose, chosen direction, speed, go,
    command, checkpoint (α, d))."""
    key = (world.name, arch, seed)
    if key not in _RUNS:
        controller = parse_architecture(arch).build()
        log = []

        def step(state, obs):
            tick, command = _tick(state, obs, p=controller.params, robot=controller.robot)
            log.append((float(obs.t), np.asarray(obs.pose, float), float(tick.direction), float(tick.speed),
                        bool(tick.go), np.asarray(command, float), np.asarray(obs.target, float)))
            return tick.state, command

        # Riekki's experiments are reactive: the checkpoint is the goal straight behind the obstacle, so the plan
        # must not keep off the standing mover's lane (ScenarioConfig.lane_margin).
        _RUNS[key] = run_scenario(world, dataclasses.replace(controller, step=step), seed=seed,
                                  config=ScenarioConfig(lane_margin=None)), log
    return _RUNS[key]


def test_samba_is_an_architecture_that_drives_no_map():
    arch = ARCHITECTURES["samba"]
    assert arch.default_chart is None and arch.params is samba.SambaParams
    spec = parse_architecture("samba:avoid_ttc=0.25,goto=msa")
    assert spec.label == "samba:goto=msa,avoid_ttc=0.25" and not spec.uses_map
    assert str(parse_architecture("samba")).startswith("samba:sensors=long,goto=osa,")
    for bad, message in (("samba:tie=1.5", "tie"), ("samba:goto=best", "goto: must be one of osa, msa"),
                         ("samba:avoid_ttc=0", "avoid_ttc must be > 0")):
        with pytest.raises(InputError, match=message):
            parse_architecture(bad)


def test_the_robot_stops_at_a_fixed_goal_by_a_zero_command():
    rec, log = logged_run(load_world("open-arena"), "samba")
    assert rec.reached and rec.ended == "stopped at the goal" and rec.final_distance_m < 0.005
    assert is_stop_command(log[-1][5], KHEPERA) and not log[-1][4]  # no action left: the arbiter sends zero
    # the Goto's speed falls with the distance (speeds above d / brake_s filtered) instead of overshooting
    speeds = [(tgt[1], s) for *_, s, go, _, tgt in log if go]
    assert all(s <= d / samba.SambaParams().brake_s + 0.02 + 1e-6 for d, s in speeds)
    assert rec.time_s < 4.0 and rec.path_m < 1.1 * math.hypot(0.3, 0.3)


def test_fig_29_without_filtering_the_robot_starts_round_the_obstacle_at_once():
    rec, log = logged_run(BEHIND, "samba:avoid_ttc=1000")  # nothing filtered: every colliding action inhibited
    assert rec.reached and rec.collisions == 0
    first = log[0]
    assert abs(math.degrees(first[2])) > 10.0  # the very first action already points past the obstacle
    gap = 0.5 - 0.1 - GROWN
    assert gap / KHEPERA.max_wheel_speed > 1.5  # ... while a collision was still 1.5 s away at full speed
    poses = np.array([p for _, p, *_ in log])
    moved = np.argmax(poses[:, 0] > 0.12)
    assert abs(poses[moved, 1] - 0.3) > 0.002 and abs(math.degrees(poses[moved, 2])) > 10.0


def test_fig_30_with_the_half_second_filter_it_drives_at_the_obstacle_until_the_collision_is_half_a_second_off():
    rec, log = logged_run(BEHIND, "samba")  # avoid_ttc = 0.5 s, Riekki's Fig. 30
    assert samba.SambaParams().avoid_ttc == 0.5 and rec.reached and rec.collisions == 0
    turn = next(k for k, (_, _, d, *_) in enumerate(log) if abs(math.degrees(d)) > 5.0)
    before = np.array([p for _, p, *_ in log[:turn]])
    assert np.all(np.abs(before[:, 1] - 0.3) < 0.002) and np.all(np.abs(np.degrees(before[:, 2])) < 3.0)
    ttc = lambda pose: (math.hypot(0.5 - pose[0], 0.3 - pose[1]) - GROWN) / KHEPERA.max_wheel_speed
    assert ttc(log[turn - 1][1]) > 0.5 >= ttc(log[turn][1]) > 0.3  # it turns as the time falls below 0.5 s
    assert log[turn][1][0] > 0.33  # 8 cm before the grown obstacle, not at the start


def test_the_arbiters_hysteresis_stops_the_left_right_dithering_behind_an_obstacle():
    """The target straight behind the obstacle: left and right tie, and as the robot turns the grid's
    directions move under the tie — without hysteresis the winner flips side tick after tick."""

    def flips(log, until_x=0.3):
        sides = [np.sign(wrap(d - tgt[0])) for _, p, d, _, go, _, tgt in log if go and p[0] < until_x]
        return sum(a != b for a, b in zip(sides, sides[1:]))

    with_h, log_h = logged_run(BEHIND, "samba:avoid_ttc=1000")
    without, log_0 = logged_run(BEHIND, "samba:avoid_ttc=1000,tie=0")
    assert with_h.reached and without.reached
    assert flips(log_0) >= 8 and flips(log_h) <= 2
    assert without.time_s > with_h.time_s + 2.0  # seconds lost turning on the spot


def test_fig_50_a_moving_target_is_intercepted_on_a_nearly_constant_heading():
    rec = run_architecture(load_world("moving-target"), parse_architecture("samba"), seed=0)
    assert rec.reached and rec.ended == "caught the moving goal" and rec.time_s < 5.0
    heading = np.degrees(rec.poses[:, 2])
    after = heading[rec.times > 1.0]  # after the first turn
    assert np.ptp(after) < 10.0
    catch = rec.poses[-1, :2]
    assert rec.path_m < 1.05 * np.linalg.norm(catch - np.asarray(rec.world.start[:2]))


def test_moving_target_is_caught_in_every_seed_far_sooner_than_by_pursuit():
    world, spec = load_world("moving-target"), parse_architecture("samba")
    recs = [run_architecture(world, spec, seed=s) for s in range(10)]
    assert sum(r.reached for r in recs) >= 9
    assert np.mean([r.time_s for r in recs if r.reached]) < 0.5 * 17.7  # the EKM architectures: 17.7-17.9 s


def test_fig_31_a_sector_filter_reaches_a_moving_object_while_making_progress_to_a_goal():
    """Riekki's Fig. 31 stepped by hand: the Goto map (MSA) of a moving object, unfiltered or filtered to the
    directions within 30° of the way to a goal location G."""
    grid = am.VelocityGrid(72, 8, KHEPERA.max_wheel_speed)
    goal = np.array([0.8, 0.85])
    obj = LinePath((0.75, 0.15), (0.75, 0.95), 0.03, bounce=False)
    world = parse_world({"name": "fig31", "size": [1.0, 1.0], "start": [0.15, 0.2, 0.0], "goal": goal.tolist()})

    @jax.jit
    def choose(pose, p_obj, v_obj, sector):
        c, s = jnp.cos(pose[2]), jnp.sin(pose[2])
        rot = lambda v: jnp.stack([c * v[0] + s * v[1], -s * v[0] + c * v[1]])
        w = am.msa(rot(p_obj - pose[:2]), rot(v_obj), grid)
        g = rot(jnp.asarray(goal, jnp.float32) - pose[:2])
        w = jnp.where(sector > 0, am.apply_mask(w, am.sector_mask(grid, jnp.arctan2(g[1], g[0]), sector)), w)
        i, j = am.best(w)
        return jnp.asarray(grid.angles())[i], jnp.asarray(grid.speed_values())[j], jnp.arctan2(g[1], g[0])

    def run(sector):
        sim, off = PymunkWorld(world, seed=0), []
        while sim.t < 40.0:
            o = np.array(obj.position(sim.t))
            if np.linalg.norm(sim.pose[:2] - o) < KHEPERA.radius + 0.02:
                return sim, o, off
            d, s, g = choose(jnp.asarray(sim.pose, jnp.float32), jnp.asarray(o, jnp.float32),
                             jnp.asarray(obj.velocity(sim.t), jnp.float32), sector)
            off.append(abs(float(wrap(d - g))))
            sim.step(np.asarray(velocity_to_wheels(d, s)), period=KHEPERA.avoid_period)
        raise AssertionError(f"sector {sector}: the object was not reached")

    free, o_free, _ = run(0.0)
    kept, o_kept, off = run(math.radians(30.0))
    to_goal = lambda sim: float(np.linalg.norm(sim.pose[:2] - goal))
    start = float(np.linalg.norm(np.asarray(world.start[:2]) - goal))  # 0.92 m
    assert free.collisions == 0 and kept.collisions == 0
    assert to_goal(free) > 0.55  # unfiltered: the earliest meeting, off the way to G (0.60 of 0.92 m left)
    assert to_goal(kept) < to_goal(free) - 0.15 and to_goal(kept) < 0.5 * start  # filtered: 0.36 m left
    assert max(off) <= math.radians(30.0) + 1e-4  # every action within the sector
    assert o_kept[1] > o_free[1] + 0.15  # it met the object further along, nearer G


def test_ir_returns_on_a_declared_mover_are_bound_to_its_marker_not_remembered():
    p = samba.SambaParams()
    angles = np.asarray(KHEPERA.long_range.angles)
    ir = np.full(12, np.inf, np.float32)
    ir[0] = 0.05  # straight ahead, 5 cm from the rim: the point (0.5 + 0.075, 0.5)
    obs = Observation(t=np.float32(0.0), ir=ir, target=np.array([0.0, 0.5], np.float32), target_id=np.int32(0),
                      final=np.bool_(True), pose=np.array([0.5, 0.5, 0.0], np.float32),
                      target_velocity=np.zeros(2, np.float32), markers=np.zeros((0, 5), np.float32))
    bind = jax.jit(samba.bind, static_argnames=("p", "robot"))
    memory, objects, valid = bind(samba.init(p), obs, p=p, robot=KHEPERA)
    assert int(np.sum(np.isfinite(np.asarray(memory.seen)))) == 1  # an unknown obstacle point: remembered
    mover = np.array([[0.6, 0.5, -0.02, 0.0, 0.025]], np.float32)  # a declared mover right there
    memory, objects, valid = bind(samba.init(p), obs._replace(markers=mover), p=p, robot=KHEPERA)
    assert int(np.sum(np.isfinite(np.asarray(memory.seen)))) == 0  # bound to the mover instead
    # the mover's marker, in the robot frame, with its velocity
    np.testing.assert_allclose(np.asarray(objects)[-1], [0.1, 0.0, -0.02, 0.0, 0.025], atol=1e-6)
    assert bool(np.asarray(valid)[-1]) and angles.shape == (12,)


def test_the_maps_of_a_recorded_tick_give_the_command_the_run_sent():
    from evaluation.actionmap_plot import record_tick

    rec, moment = record_tick(load_world("moving-target"), parse_architecture("samba"), at=2.0, seed=1)
    assert abs(moment.t - 2.0) <= 0.064 and rec.reached
    controller = parse_architecture("samba").build()
    _, command = controller.step(moment.state, moment.obs)
    sent = {round(t, 3): (vl, vr) for t, vl, vr in rec.commands}[round(moment.t, 3)]
    np.testing.assert_allclose(np.asarray(command), sent, atol=1e-6)
    tick = moment.tick
    assert tick.goto.shape == tick.avoid.shape == tick.composite.shape == (72, 8)
    np.testing.assert_array_equal(np.asarray(tick.composite), np.asarray(am.mav(tick.goto, tick.avoid)))
    assert float(np.max(tick.avoid)) <= 0.0 <= float(np.min(tick.goto))


def test_with_no_positive_action_samba_takes_the_free_action_that_closes_fastest():
    """closer_when_stuck by hand: a target straight ahead (α = 0) 0.3 m away, still. Straight ahead collides
    within 0.1 s at every speed; every other action is free. The free action closing fastest is the top speed
    at the direction nearest ahead, ±5°: closing 0.16 cos 5° m/s. With a positive action left, nothing changes;
    at a fixed goal 3 mm away, where the Goto map allows no speed (3 mm / 0.2 s < the slowest 0.02 m/s), the
    robot stays stopped."""
    p = samba.SambaParams()
    grid = p.grid(KHEPERA)
    times = np.full(grid.shape, np.inf, np.float32)
    times[0, :] = 0.1
    obs = Observation(t=np.float32(0), ir=np.full(12, np.inf, np.float32), target=np.array([0.0, 0.3], np.float32),
                      target_id=np.int32(0), final=np.bool_(True), pose=np.zeros(3, np.float32),
                      target_velocity=np.zeros(2, np.float32), markers=np.zeros((0, 5), np.float32))
    i, j, go = samba.closer_when_stuck(0, 0, False, jnp.asarray(times), obs, p, grid)
    assert bool(go) and int(j) == grid.speeds - 1 and int(i) in (1, grid.directions - 1)
    assert (int(i), int(j), bool(go)) == tuple(map(lambda a: a.item(), samba.closer_when_stuck(
        int(i), int(j), False, jnp.asarray(times), obs, p, grid)))  # deterministic
    i, j, go = samba.closer_when_stuck(7, 3, True, jnp.asarray(times), obs, p, grid)
    assert (int(i), int(j), bool(go)) == (7, 3, True)
    at_goal = obs._replace(target=np.array([0.0, 0.003], np.float32))
    assert not bool(samba.closer_when_stuck(0, 0, False, jnp.asarray(times), at_goal, p, grid)[2])


def test_samba_never_stands_beside_a_post_while_a_free_action_brings_it_closer():
    """Issue 21's freeze: a target crossing the arena at 0.1 m/s past a small post. With ``closer`` the robot
    never sends a zero command for more than one tick before it catches the target; without it, it stood still
    beside the post for 3.6 s (seed 0)."""
    doc = {"name": "post", "size": [1.2, 0.8], "unforeseen": [{"type": "circle", "center": [0.685, 0.634],
                                                                 "radius": 0.02}],
           "start": [0.186, 0.206, 1.57],
           "goal": {"path": {"type": "line", "from": [0.1, 0.5919], "to": [1.1, 0.5919], "speed_mps": 0.1,
                             "bounce": False}}}
    world = parse_world(doc, "post.json")

    def longest_stop(arch):
        rec = run_architecture(world, parse_architecture(arch), seed=0)
        zero = [max(abs(l), abs(r)) < 1e-12 for _, l, r in rec.commands]
        run = best = 0
        for z in zero:
            run = run + 1 if z else 0
            best = max(best, run)
        return rec, best

    rec, stop = longest_stop("samba")
    assert rec.reached and stop <= 1
    _, stop = longest_stop("samba:closer=false")
    assert stop * KHEPERA.avoid_period > 2.0


# Samba steps out of a declared mover's way (samba:escape_s)
def mover_observation(markers):
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
    _, wheels = samba.step(samba.init(p), mover_observation([mover]), p=p, robot=KHEPERA)
    np.testing.assert_allclose(np.asarray(wheels), [0.06, 0.06], atol=1e-6)
    still = samba.step(samba.init(p), mover_observation([]), p=p, robot=KHEPERA)[1]
    off = samba.SambaParams(escape_s=0.0)
    assert not np.allclose(np.asarray(still), [0.06, 0.06])
    assert not np.allclose(np.asarray(samba.step(samba.init(off), mover_observation([mover]), p=off, robot=KHEPERA)[1]),
                           [0.06, 0.06])
    # a mover passing by far off (it would meet the standing robot only after 3 s) changes nothing
    far = [0.5, 0.86, 0.0, -0.1, 0.025]
    np.testing.assert_allclose(np.asarray(samba.step(samba.init(p), mover_observation([far]), p=p, robot=KHEPERA)[1]),
                               np.asarray(still), atol=1e-6)


# Samba squeezes through a gap its clearance closes (samba:squeeze, samba:squeeze_s)
def slot_world(gap: float):
    """An unforeseen wall across a 1.0 x 0.6 m arena at x = 0.5 with one opening ``gap`` (m) wide between its
    faces, centred on the straight route from (0.3, 0.3) to (0.8, 0.3): the plan goes straight through it."""
    lo, hi = 0.3 - gap / 2, 0.3 + gap / 2
    return parse_world({"name": "slot", "size": [1.0, 0.6], "start": [0.3, 0.3, 0.0], "goal": [0.8, 0.3],
                        "unforeseen": [{"type": "box", "center": [0.5, lo / 2], "size": [0.02, lo]},
                                       {"type": "box", "center": [0.5, (hi + 0.6) / 2], "size": [0.02, 0.6 - hi]}]},
                       "slot.json")


def test_samba_squeezes_through_a_gap_narrower_than_its_body_and_two_clearances():
    """A 6.6 cm opening: the 5 cm robot passes with 8 mm a side, but with the 1 cm clearance every way through is
    closed (it needs 7 cm). At the default squeeze (3 mm after 2 s without an action) it goes through and stops at
    the goal; with the squeeze off (squeeze = clearance) it noses into the opening and never passes (no
    recovery)."""
    world = slot_world(0.066)
    config = ScenarioConfig(time_limit=40.0, recover=False)
    rec = run_architecture(world, parse_architecture("samba"), seed=0, config=config)
    assert rec.reached and rec.collisions == 0
    off = run_architecture(world, parse_architecture("samba:squeeze=0.01"), seed=0, config=config)
    assert not off.reached and off.poses[:, 0].max() < 0.5  # its centre never reaches the wall's middle


@pytest.mark.parametrize("points, expected", [
    ([[0.01, 0.033], [0.01, -0.033]], True),     # a pillar either side, beside the way: a gap
    ([[0.01, 0.033], [0.03, 0.034]], False),     # a wall on the left only
    ([[0.01, 0.033], [0.06, -0.033]], False),    # the right-hand point 6 cm ahead: beyond two radii
    ([[-0.03, 0.033], [0.01, -0.033]], False),   # the left-hand point 3 cm behind: more than a radius back
    ([[0.01, 0.036], [0.01, -0.033]], True),     # 3.6 cm off the line on the left: 6.9 cm across, under 7 cm
    ([[0.01, 0.038], [0.01, -0.033]], False),    # 3.8 cm on the left: 7.1 cm across, over 2 (R + clearance)
    ([[0.01, 0.020], [0.0, -0.05], [0.04, -0.045]], True),  # the robot 1.5 cm off a 6.5 cm slot's centre line
])
def test_a_gap_is_remembered_points_on_both_sides_of_the_way_nearer_each_other_than_two_radii_and_clearances(
        points, expected):
    """By hand, R = 2.5 cm, clearance 1 cm: a gap when the nearest points left and right of the way, from R behind
    to 2R ahead, are less than 2 (R + clearance) = 7 cm apart across it, wherever the robot is between them."""
    pts = jnp.asarray(points, jnp.float32)
    assert bool(samba.in_a_gap(pts, jnp.ones(len(pts), bool), 0.0, 0.025, 0.035)) is expected
    turned = pts @ jnp.asarray([[0.0, 1.0], [-1.0, 0.0]])  # the same scene turned by +90°, the way along +y
    assert bool(samba.in_a_gap(turned, jnp.ones(len(pts), bool), math.pi / 2, 0.025, 0.035)) is expected
    assert not bool(samba.in_a_gap(pts, jnp.zeros(len(pts), bool), 0.0, 0.025, 0.035))  # none valid
