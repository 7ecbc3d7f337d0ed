"""The pymunk world (robots.world): agreement with the JAX kinematics, walls that hold, seeds, moving
obstacles, events and the input checks of step()."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.angles import wrap
from robots import kinematics
from robots.geometry import polygon_contains, signed_area
from robots.params import KHEPERA
from robots.world import PymunkWorld, convex_pieces
from robots.worldfile import parse_world
from robots.worldnames import load_world

C = KHEPERA.max_wheel_speed


def free_space():
    """An arena so large that 100 target-reaching steps (<= 16.4 m) never reach its border."""
    return parse_world({"name": "free", "size": [40.0, 40.0], "start": [20.0, 20.0, 0.3], "goal": [21.0, 20.0]})


def box_arena(size=0.6, **extra):
    doc = {"name": "box", "size": [size, size], "start": [size / 2, size / 2, 0.0], "goal": [size / 2, size / 4]}
    return parse_world({**doc, **extra})


def varied_commands(n, seed, period=KHEPERA.avoid_period):
    """Straight runs, arcs, spins on the spot, reversing and commands beyond c* (clipped by the motors),
    with slip draws for control periods of ``period``."""
    rng = np.random.default_rng(seed)
    commands = rng.uniform(-1.2 * C, 1.2 * C, (n, 2))
    commands[::10] = [C, C]  # full speed ahead
    commands[1::10] = [-C, C]  # spin on the spot
    commands[2::10] = [0.5 * C, C]  # arc to the left
    commands[3::10] = [0.0, 0.0]  # stop
    return commands, rng.uniform(-1.0, 1.0, (n,) + KHEPERA.noise_shape(period))


# ----------------------------------------------------------------------------- (a) agreement with JAX

def test_pymunk_robot_traces_the_jitted_jax_kinematics_within_1mm_over_100_target_steps():
    n = KHEPERA.substeps(KHEPERA.target_period)  # 64 sub-steps of 16 ms per 1.024 s step
    commands, noise = varied_commands(100, seed=3, period=KHEPERA.target_period)

    @jax.jit
    def rollout(state, commands, noise):
        def one(s, cn):
            return kinematics.step(s, cn[0], cn[1], n, KHEPERA, jnp)

        return jax.lax.scan(one, state, (commands, noise))

    world = free_space()
    _, jax_traces = rollout(kinematics.initial_state(jnp.asarray(world.start), jnp), jnp.asarray(commands),
                            jnp.asarray(noise))
    sim = PymunkWorld(world, seed=0)
    sim_traces = np.stack([sim.step(c, xi, period=KHEPERA.target_period)[1] for c, xi in zip(commands, noise)])

    jax_traces = np.asarray(jax_traces, dtype=float)
    assert sim_traces.shape == jax_traces.shape == (100, n, 3)
    gap = np.linalg.norm(sim_traces[..., :2] - jax_traces[..., :2], axis=-1)  # every sub-step
    assert gap.max() < 1e-3, gap.max()
    assert np.abs(wrap(sim_traces[..., 2] - jax_traces[..., 2])).max() < 1e-3  # heading (rad)
    assert sim.collisions == 0
    path = np.linalg.norm(np.diff(sim_traces.reshape(-1, 3)[:, :2], axis=0), axis=1).sum()
    assert path > 3.0  # the robot really drove (metres), it did not sit still
    assert sim.t == pytest.approx(100 * KHEPERA.target_period)


def test_in_free_space_pymunk_integrates_exactly_like_the_numpy_kinematics():
    """Same explicit Euler: float64 against float64 agree to rounding, not just to a millimetre."""
    commands, noise = varied_commands(30, seed=4)
    world = free_space()
    sim = PymunkWorld(world, seed=0)
    state = kinematics.initial_state(np.asarray(world.start))
    for c, xi in zip(commands, noise):
        state, trace = kinematics.step(state, c, xi, 8, KHEPERA, np)
        _, sim_trace = sim.step(c, xi)
        np.testing.assert_allclose(sim_trace, trace, atol=1e-10)
    np.testing.assert_allclose(sim.wheels, state.wheels, atol=1e-12)


# ------------------------------------------------------------------------------ (b) walls that hold

# A velocity-controlled body may overlap a wall by at most one sub-step of travel at top speed, with
# the largest slip (1.1 * 0.16 m/s * 16 ms = 2.8 mm), before the contact stops it.
MAX_OVERLAP = (1 + KHEPERA.actuator_noise) * C * KHEPERA.dt


def ram(world, aim, steps=1000, seed=0):
    """Drive at full speed, always steering towards ``aim`` (beyond a wall); all sub-step poses."""
    sim = PymunkWorld(world, seed=seed)
    traces = []
    for _ in range(steps):
        x, y, theta = sim.pose
        err = float(wrap(math.atan2(aim[1] - y, aim[0] - x) - theta))
        turn = float(np.clip(0.1 * err, -2 * C, 2 * C))
        traces.append(sim.step([C - turn, C + turn])[1])
    return sim, np.concatenate(traces)


@pytest.mark.parametrize("aim", [(3.0, 0.3), (3.0, 3.0), (-3.0, 0.05)], ids=["wall", "corner", "glancing"])
def test_at_full_speed_the_robot_never_passes_the_arena_border(aim):
    world = box_arena()
    sim, trace = ram(world, aim)
    assert trace.shape == (8000, 3)  # 1,000 avoidance steps of 8 sub-steps, every one checked
    clearance = world.clearance(trace[:, :2])  # centre to the nearest wall surface
    assert clearance.min() > KHEPERA.radius - MAX_OVERLAP
    inner = 0.5 * world.wall_thickness + KHEPERA.radius - MAX_OVERLAP
    assert np.all((trace[:, :2] > inner) & (trace[:, :2] < 0.6 - inner))
    assert sim.collisions >= 1


@pytest.mark.parametrize("aim", [(0.9, 0.5), (0.9, 0.95), (0.9, 0.0)], ids=["head-on", "towards-top", "into-corner"])
def test_a_thin_interior_wall_across_the_arena_is_never_crossed(aim):
    world = parse_world({"name": "thin", "size": [1.0, 1.0], "wall_thickness": 0.0, "walls": [[0.5, 0.0, 0.5, 1.0]],
                         "start": [0.3, 0.5, 0.0], "goal": [0.2, 0.5]})
    sim, trace = ram(world, aim)
    assert trace[:, 0].max() < 0.5 - KHEPERA.radius + MAX_OVERLAP  # stays on its side, every sub-step
    assert world.clearance(trace[:, :2]).min() > KHEPERA.radius - MAX_OVERLAP
    assert sim.collisions >= 1


def test_a_thin_segment_obstacle_is_slid_along_and_around_never_through():
    world = parse_world({"name": "thin", "size": [1.0, 1.0], "unforeseen": [
        {"type": "segment", "from": [0.5, 0.3], "to": [0.5, 0.7]}], "start": [0.3, 0.5, 0.0], "goal": [0.2, 0.5]})
    sim, trace = ram(world, (0.7, 0.8), steps=400)  # hits it at a slant, slides up and round its end
    assert world.clearance(trace[:, :2]).min() > KHEPERA.radius - MAX_OVERLAP
    crossings = np.flatnonzero(np.diff(np.sign(trace[:, 0] - 0.5)) != 0)
    assert len(crossings) >= 1
    assert np.all(trace[crossings, 1] > 0.7)  # past x = 0.5 only beyond the segment's upper end


@pytest.mark.parametrize("wall_angle", np.radians(np.arange(0, 180, 30)).tolist(), ids=lambda a: f"wall{math.degrees(a):.0f}")
@pytest.mark.parametrize("incidence", np.radians([0.0, 20.0, 45.0, 60.0]).tolist(), ids=lambda a: f"in{math.degrees(a):.0f}")
def test_at_top_speed_with_noise_the_robot_never_tunnels_through_a_thin_wall(wall_angle, incidence):
    """24 thin (zero-thickness) walls and approach directions: full speed on both wheels, 10 % slip noise, 2 s."""
    centre = np.array([0.5, 0.5])
    along = np.array([math.cos(wall_angle), math.sin(wall_angle)])
    normal = np.array([-along[1], along[0]])
    a, b = centre - 0.4 * along, centre + 0.4 * along
    heading = math.atan2(*(normal * math.cos(incidence) + along * math.sin(incidence))[::-1])
    start = centre - 0.15 * normal  # 15 cm before the wall, driving at it
    world = parse_world({"name": "thin", "size": [1.0, 1.0], "wall_thickness": 0.0,
                         "walls": [[*a.tolist(), *b.tolist()]], "start": [*start.tolist(), heading], "goal": [0.1, 0.1]})
    sim = PymunkWorld(world, seed=int(1000 * wall_angle + 10 * incidence))
    trace = np.concatenate([sim.step([C, C])[1] for _ in range(16)])
    side = (trace[:, :2] - centre) @ normal  # signed distance of the centre from the wall's line
    assert side.max() < -KHEPERA.radius + MAX_OVERLAP  # never past the wall, every 16 ms sub-step
    assert sim.collisions >= 1


def test_a_pushing_moving_obstacle_shoves_the_robot_instead_of_overlapping_it():
    world = parse_world({"name": "push", "size": [1.0, 0.4], "start": [0.5, 0.2, 0.0], "goal": [0.9, 0.2],
                         "moving": [{"shape": {"type": "circle", "radius": 0.025},
                                     "path": {"type": "line", "from": [0.1, 0.2], "to": [0.9, 0.2],
                                              "speed_mps": 0.05, "bounce": False}}]})
    sim = PymunkWorld(world, seed=0)
    for _ in range(60):  # 7.68 s: the mover touches the standing robot at 7 s, then pushes it for 0.68 s
        sim.step([0.0, 0.0])
    gap = np.hypot(*(sim.pose[:2] - sim.moving_positions()[0]))
    assert sim.collisions == 1
    assert sim.pose[0] == pytest.approx(0.5 + 0.05 * 0.68, abs=MAX_OVERLAP)  # pushed along +x at its speed
    assert gap > 2 * KHEPERA.radius - MAX_OVERLAP


# ---------------------------------------------------------------------------------------- (e) seeds

def drive(seed, sense_between=False):
    sim = PymunkWorld(load_world("three-rooms-static"), seed=seed)
    commands, _ = varied_commands(60, seed=9)
    for c in commands:
        if sense_between:
            sim.sense()
        sim.step(0.5 * np.abs(c))
    return sim


def test_same_seed_same_trajectory_and_readings_different_seed_different():
    a, b, c = drive(5), drive(5), drive(6)
    np.testing.assert_array_equal(a.pose, b.pose)
    np.testing.assert_array_equal(a.trace, b.trace)
    np.testing.assert_array_equal(a.sense(), b.sense())
    assert np.linalg.norm(a.pose[:2] - c.pose[:2]) > 1e-4  # slip noise is small but real


def test_reading_the_sensors_does_not_change_the_motor_noise():
    np.testing.assert_array_equal(drive(5).trace, drive(5, sense_between=True).trace)


# ----------------------------------------------------------------- (f) moving obstacles and events

def test_moving_obstacles_sit_on_their_paths_after_every_step():
    world = load_world("three-rooms-moving")
    sim = PymunkWorld(world, seed=0)
    path = world.moving[0].path
    start = sim.moving_positions()[0].copy()
    for _ in range(int(path.period_s / KHEPERA.avoid_period)):  # one full lap, the robot standing still
        sim.step([0.0, 0.0])
        np.testing.assert_allclose(sim.moving_positions()[0], path.position(sim.t), atol=1e-9)
    assert sim.t == pytest.approx(path.period_s, abs=KHEPERA.avoid_period)
    swept = np.hypot(*(np.asarray(path.position(6.0)) - start))  # half a lap: across the circle
    assert swept == pytest.approx(2 * path.radius)


def test_line_paths_bounce_between_their_ends():
    world = parse_world({"name": "line", "size": [1.0, 0.4], "start": [0.1, 0.1, 0.0], "goal": [0.9, 0.1],
                         "moving": [{"shape": {"type": "box", "size": [0.04, 0.04]},
                                     "path": {"type": "line", "from": [0.3, 0.3], "to": [0.7, 0.3],
                                              "speed_mps": 0.1}}]})
    sim = PymunkWorld(world, seed=0)
    xs = []
    for _ in range(80):  # 10.24 s: 1.024 m of travel, 2.5 passes of the 0.4 m line
        sim.step([0.0, 0.0])
        xs.append(sim.moving_positions()[0, 0])
    assert min(xs) == pytest.approx(0.3, abs=0.013) and max(xs) == pytest.approx(0.7, abs=0.013)
    assert sim.moving_positions()[0] == pytest.approx(world.moving[0].path.position(sim.t))


def test_events_add_their_shapes_when_their_time_comes():
    world = load_world("three-rooms-changed")  # the lower doorway at x = 0.8 closes at 6 s
    event = world.events[0]
    sim = PymunkWorld(world, seed=0)
    sim.place([0.7, 0.16, 0.0])  # looking through the lower doorway
    ahead = 0  # the first long-range sensor looks straight ahead
    while sim.t + 1e-9 < event.at_s:
        assert sim.ranges()[ahead] == np.inf
        sim.step([0.0, 0.0])
    sim.step([0.0, 0.0])
    # The new box's face is at x = 0.79; the rim is at 0.725.
    assert sim.ranges()[ahead] == pytest.approx(0.79 - 0.725, abs=1e-9)


def test_the_goal_of_moving_target_moves():
    world = load_world("moving-target")
    sim = PymunkWorld(world, seed=0)
    before = sim.goal
    for _ in range(10):
        sim.step([0.0, 0.0])
    assert sim.goal == pytest.approx(world.goal.position(1.28))
    assert np.hypot(sim.goal[0] - before[0], sim.goal[1] - before[1]) == pytest.approx(0.04 * 1.28)


# --------------------------------------------------------------------------------------- polygons

def test_concave_polygons_are_split_into_convex_pieces_that_tile_them():
    world = load_world("concave-obstacle")
    u = world.unforeseen[0]
    pieces = convex_pieces(u.vertices())
    assert len(pieces) >= 3  # a U needs at least three convex parts
    assert sum(signed_area(p) for p in pieces) == pytest.approx(abs(signed_area(u.vertices())), rel=1e-12)
    sim = PymunkWorld(world, seed=0)
    xs, ys = np.meshgrid(np.arange(0.4413, 0.78, 0.0041), np.arange(0.2507, 0.55, 0.0039))  # off the edges
    grid = np.stack([xs.ravel(), ys.ravel()], axis=1)
    in_space = np.array([bool(sim.space.point_query((float(x), float(y)), 0.0, _static_only())) for x, y in grid])
    inside = polygon_contains(grid, u.vertices())
    assert inside.sum() > 100
    assert np.array_equal(in_space, inside)  # the U's mouth is empty: not the convex hull


def _static_only():
    import pymunk

    from robots.body import ROBOT_CATEGORY

    return pymunk.ShapeFilter(mask=pymunk.ShapeFilter.ALL_MASKS() ^ ROBOT_CATEGORY)


def test_a_star_shaped_polygon_is_split_into_convex_pieces():
    star = [(0.5 + (0.1 if k % 2 == 0 else 0.04) * math.cos(math.pi * k / 5),
             0.5 + (0.1 if k % 2 == 0 else 0.04) * math.sin(math.pi * k / 5)) for k in range(10)]
    pieces = convex_pieces(star[::-1])  # clockwise input is fine too
    assert len(pieces) >= 3
    assert sum(signed_area(p) for p in pieces) == pytest.approx(abs(signed_area(star)), rel=1e-12)
    for p in pieces:  # each piece convex and counter-clockwise: every turn is to the left
        d = np.diff(np.vstack([p, p[:2]]), axis=0)
        assert np.all(d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0] > -1e-15)


# ------------------------------------------------------------------------------------ bad arguments

@pytest.mark.parametrize("command, message", [([0.1], "shape"), ([np.nan, 0.1], "finite"), ("fast", "numbers")])
def test_step_refuses_bad_commands_clearly(command, message):
    sim = PymunkWorld(load_world("open-arena"), seed=0)
    with pytest.raises(ValueError, match=f"step: command.*{message}"):
        sim.step(command)


def test_step_refuses_a_period_that_is_not_whole_sub_steps():
    sim = PymunkWorld(load_world("open-arena"), seed=0)
    with pytest.raises(ValueError, match="0.1 s is not a whole number"):
        sim.step([0.1, 0.1], period=0.1)


@pytest.mark.parametrize("seed", [-1, 1.5, "0", True])
def test_seed_must_be_a_non_negative_integer(seed):
    with pytest.raises(ValueError, match="seed"):
        PymunkWorld(load_world("open-arena"), seed=seed)


# ----------------------------------------------------------------------------- issue 21: contact episodes

def jitter_against_wall(seed=0, pause=0.0):
    """Drive into the east wall, then alternate 0.128 s towards it and 0.128 s away (a robot jittering against a
    jamb); ``pause`` s away from the wall in the middle. Returns the world after it."""
    sim = PymunkWorld(box_arena(), seed=seed)
    sim.place((0.6 - 0.005 - KHEPERA.radius - 0.01, 0.3, 0.0))
    for _ in range(4):
        sim.step([0.1, 0.1])
    for k in range(20):
        sim.step([0.05, 0.05] if k % 2 == 0 else [-0.05, -0.05])
    if pause:
        for _ in range(round(pause / 0.128)):
            sim.step([-0.05, -0.05])
        for _ in range(8):
            sim.step([0.1, 0.1])
    return sim


def test_jitter_against_a_wall_is_one_collision_with_its_contact_time():
    sim = jitter_against_wall()
    assert sim.collisions == 1
    assert 0.1 < sim.contact_s <= sim.t


def test_contacts_apart_by_more_than_half_a_second_are_two_collisions():
    sim = jitter_against_wall(pause=1.5)
    assert sim.collisions == 2


def test_an_event_waits_until_the_robot_is_clear_of_its_shapes():
    """A door that closes on the robot (a box appearing where the robot stands at 0.1 s) appears only once the
    robot has driven out of it, so it never counts as a collision."""
    world = box_arena(events=[{"at_s": 0.1, "add": [{"type": "box", "center": [0.3, 0.3], "size": [0.02, 0.2]}]}])
    sim = PymunkWorld(world, seed=0)
    sim.place((0.3, 0.3, 0.0))
    for _ in range(3):
        sim.step([0.0, 0.0])
    assert sim._pending and sim.collisions == 0  # still waiting: the robot stands in the box
    for _ in range(12):
        sim.step([0.12, 0.12])
    assert not sim._pending and sim.collisions == 0 and sim.pose[0] > 0.3 + 0.01 + KHEPERA.radius
