"""Known answers shared by both engines — the pymunk world and the JAX world (robots.jaxworld) — worked out by hand.

Each test drives an ``engine`` fixture, parametrized over the two, through the same commands and slip draws and
asserts the numbers below; the JAX-only tests check the batch (``vmap`` over runs and scenes) and bad input.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.body import SLOP
from robots.jaxworld import engine as jw
from robots.jaxworld import moving
from robots.jaxworld.scene import scene_of, stack_scenes
from robots.params import KHEPERA
from robots.world import PymunkWorld
from robots.worldfile import parse_world

R, DT, TAU, B = KHEPERA.radius, KHEPERA.dt, KHEPERA.motor_tau, KHEPERA.wheel_base
ZERO = np.zeros((4, 2))

_step = jax.jit(jw.step, static_argnames=("params", "n", "dynamic"))
_ranges = jax.jit(jw.ranges, static_argnames=("sensors", "radius"))
_placed = jax.jit(moving.placed)


class PymunkEngine:
    def __init__(self, world):
        self.sim = PymunkWorld(world, seed=0)

    def drive(self, command, noise=ZERO):
        self.sim.step(np.asarray(command, float), noise=noise)

    pose = property(lambda self: self.sim.pose)
    collisions = property(lambda self: self.sim.collisions)
    contact_s = property(lambda self: self.sim.contact_s)

    def ranges(self, sensors):
        return self.sim.ranges(sensors)


class JaxEngine:
    def __init__(self, world):
        self.scene = scene_of(world)
        self.dynamic = bool(world.moving or world.events)
        self.state = jw.reset(np.asarray(world.start), self.scene)

    def drive(self, command, noise=ZERO):
        self.state, _ = _step(self.state, self.scene, jnp.asarray(command, jnp.float32), jnp.asarray(noise),
                              dynamic=self.dynamic)

    pose = property(lambda self: np.asarray(self.state.robot.pose, float))
    collisions = property(lambda self: int(self.state.collisions))
    contact_s = property(lambda self: float(self.state.contact_s))

    def ranges(self, sensors):
        scene = _placed(self.scene, jw.time_of(self.state), self.state.fired)
        return np.asarray(_ranges(self.state.robot.pose, scene, sensors), float)


@pytest.fixture(params=[PymunkEngine, JaxEngine], ids=["pymunk", "jax"])
def engine(request):
    return request.param


def world(**keys):
    doc = {"name": "hand", "size": [1.0, 0.5], "start": [0.3, 0.25, 0.0], "goal": [0.9, 0.25]}
    doc.update(keys)
    return parse_world(doc, "hand.json")


WALL = [[0.6, 0.0, 0.6, 0.5]]  # 1 cm thick (the default wall_thickness): its face is at x = 0.595


def test_straight_into_a_wall_stops_at_the_wall_less_the_radius(engine):
    # Full speed for 40 ticks (5.12 s, 0.82 m of travel) from x = 0.3 towards the face at x = 0.595: the disc
    # stops touching it, centre at 0.595 - 0.025 = 0.570, pressed in by pymunk's slop (0.1 mm): 0.5701.
    sim = engine(world(walls=WALL))
    for _ in range(40):
        sim.drive([0.16, 0.16])
    x, y, theta = sim.pose
    assert x == pytest.approx(0.6 - 0.005 - R + SLOP, abs=2e-6)
    assert (y, theta) == (pytest.approx(0.25, abs=1e-9), pytest.approx(0.0, abs=1e-9))
    assert sim.collisions == 1
    # pressed in by 0.1 mm, the rim ahead is inside the wall: 0; the sensors at ±30° see the face
    # (0.595 - 0.5701 - 0.025 cos 30°) / cos 30° = 0.003751 m away
    assert sim.ranges(KHEPERA.long_range)[[0, 1, 11]] == pytest.approx([0.0, 0.003751, 0.003751], abs=2e-6)
    # 2.56 mm a sub-step from x = 0.56159 after tick 12 (0-based): the 4th sub-step of tick 13 ends at 0.57183,
    # touching; then 5 sub-steps of tick 13 and all 8 of ticks 14..39 end in contact
    assert sim.contact_s == pytest.approx((5 + 26 * 8) * DT, abs=1e-4)


def test_equal_commands_on_a_hand_set_slip_draw_give_the_same_pose(engine):
    # (0.08, 0.08) m/s from rest, left wheel +10 %, right -10 % for the whole tick. By hand: the set-point
    # c = 0.08 is reached with the lag s_j = c (1 - exp(-j dt / tau)), j = 0..7; v_j = s_j, w_j = -0.2 s_j / b;
    # explicit Euler, heading of the sub-step's start. The heading's change is -0.2 / b * dt * c * sum_j (1 -
    # exp(-0.8 j)) = -3.7736 * 0.016 * 0.08 * (8 - (1 - exp(-6.4)) / (1 - exp(-0.8))) = -0.029885 rad.
    sim = engine(world())
    sim.drive([0.08, 0.08], np.tile([1.0, -1.0], (4, 1)))
    x, y, theta = 0.3, 0.25, 0.0
    for j in range(8):
        s = 0.08 * (1.0 - math.exp(-j * DT / TAU))
        x, y, theta = x + s * math.cos(theta) * DT, y + s * math.sin(theta) * DT, theta - 0.2 * s / B * DT
    assert sim.pose == pytest.approx([x, y, theta], abs=2e-6)
    assert theta == pytest.approx(-0.029885, abs=1e-6)


def test_sliding_along_a_wall_at_45_degrees(engine):
    # Heading 45° into the wall at full speed: once pressed against it, the part of the velocity into the wall
    # is removed and the robot slides up it at 0.16 sin 45° = 0.1131 m/s, heading unchanged.
    sim = engine(world(walls=WALL, start=[0.45, 0.05, math.pi / 4]))
    for _ in range(12):
        sim.drive([0.16, 0.16])
    x0, y0, _ = sim.pose
    assert x0 == pytest.approx(0.5701, abs=2e-4)  # touching since tick 8: the overlap has not all decayed yet
    for _ in range(10):
        sim.drive([0.16, 0.16])
    x, y, theta = sim.pose
    assert x == pytest.approx(0.5701, abs=2e-5)
    assert y - y0 == pytest.approx(0.16 * math.sqrt(0.5) * 1.28, abs=1e-5)
    assert theta == pytest.approx(math.pi / 4, abs=1e-6)
    assert sim.collisions == 1


def test_no_tunnelling_through_a_thin_segment_at_top_speed(engine):
    # An infinitely thin segment obstacle, driven at with both wheels slipping +10 % (0.176 m/s, 2.8 mm a
    # sub-step): the centre ends at its radius from it (and the slop), never beyond.
    sim = engine(world(obstacles=[{"type": "segment", "from": [0.5, 0.1], "to": [0.5, 0.4]}]))
    xs = []
    for _ in range(30):
        sim.drive([0.16, 0.16], np.ones((4, 2)))
        xs.append(sim.pose[0])
    assert max(xs) <= 0.5 - R + 0.003  # one sub-step's overlap at most, pushed out again
    assert xs[-1] == pytest.approx(0.5 - R + SLOP, abs=5e-5)


def test_a_contact_broken_for_less_than_half_a_second_is_one_episode(engine):
    sim = engine(world(walls=WALL))
    for _ in range(20):
        sim.drive([0.16, 0.16])
    sim.drive([-0.16, -0.16])  # 0.128 s off the wall, then back: the same episode
    for _ in range(3):
        sim.drive([0.16, 0.16])
    assert sim.collisions == 1
    for _ in range(8):  # 1.024 s away: a new one
        sim.drive([-0.16, -0.16])
    for _ in range(12):
        sim.drive([0.16, 0.16])
    assert sim.collisions == 2


def test_ir_of_a_hand_built_scene(engine):
    # Robot at (0.5, 0.25) heading +x in a 1 m x 0.5 m arena. Ahead (sensor 0): a box whose face is at x = 0.6,
    # 0.6 - 0.525 = 0.075 from the rim. Left (sensor 3, +90°): a circle of 3 cm at y = 0.40, 0.40 - 0.03 - 0.275
    # = 0.095. Behind (sensor 6): a wall at x = 0.38, 1 cm thick: 0.475 - 0.385 = 0.090. Right (sensor 9): the
    # border is 0.25 - 0.025 - 0.005 = 0.22 away, beyond the 17.5 cm range: inf.
    sim = engine(world(start=[0.5, 0.25, 0.0], walls=[[0.38, 0.05, 0.38, 0.45]],
                       obstacles=[{"type": "box", "center": [0.65, 0.25], "size": [0.1, 0.2]},
                                  {"type": "circle", "center": [0.5, 0.40], "radius": 0.03}]))
    got = sim.ranges(KHEPERA.long_range)
    assert got[[0, 3, 6]] == pytest.approx([0.075, 0.095, 0.090], abs=1e-6)
    assert got[9] == math.inf
    readings = np.round(got[[0, 3, 6]] / 0.005) * 0.005  # noise-free readings, to the 0.5 cm resolution
    assert readings == pytest.approx([0.075, 0.095, 0.090], abs=1e-9)


@pytest.mark.parametrize("ahead, seen", [(0.047, False), (0.045, True)])
def test_the_long_ring_first_sees_a_thin_pillar_just_off_the_line_of_travel_a_centimetre_from_the_body(engine, ahead,
                                                                                                       seen):
    # Twelve directed rays 30° apart (the thesis's long-range ring) leave wedges no ray looks into: a pillar of
    # radius r = 1 cm whose centre is y = 1.5 cm right of the line of travel is never on the 0° ray (1.5 > r) and
    # first on the -30° ray (index 11) when its centre is x = (r + y cos 30°) / sin 30° = 2r + √3 y = 4.60 cm ahead
    # — its surface then √(4.6² + 1.5²) - 2.5 - 1 = 1.34 cm from the body's, while the robot covers 2 cm a tick at
    # top speed. At 4.7 cm the ray passes 4.7 sin 30° - 1.5 cos 30° = 1.05 cm from the pillar's centre (a miss); at
    # 4.5 cm, 0.95 cm (a hit). The arena's border is out of range (22 cm and more from the body).
    sim = engine(world(start=[0.5, 0.25, 0.0], obstacles=[{"type": "circle", "center": [0.5 + ahead, 0.235],
                                                           "radius": 0.01}]))
    assert np.isfinite(sim.ranges(KHEPERA.long_range)).tolist() == [False] * 11 + [seen]


# ------------------------------------------------------------------------------------------------ JAX only
def test_a_batch_of_different_worlds_steps_as_each_alone():
    worlds = [world(walls=WALL), world(obstacles=[{"type": "polygon", "points": [[0.5, 0.1], [0.7, 0.1], [0.7, 0.4],
                                                                                 [0.6, 0.2], [0.5, 0.4]]}])]
    scenes = stack_scenes(worlds)
    starts = jnp.asarray([w.start for w in worlds], jnp.float32)
    batch = jax.vmap(jw.reset)(starts, scenes)
    step = jax.jit(jax.vmap(jw.step, in_axes=(0, 0, None, None)))
    alone = [JaxEngine(w) for w in worlds]
    for _ in range(25):
        batch, _ = step(batch, scenes, jnp.asarray([0.16, 0.12]), jnp.zeros((4, 2)))
        for sim in alone:
            sim.drive([0.16, 0.12])
    for i, sim in enumerate(alone):
        assert np.asarray(batch.robot.pose[i]) == pytest.approx(sim.pose, abs=1e-6)
        assert int(batch.collisions[i]) == sim.collisions == 1


def _pusher(heading=0.0):
    """A disc of 5 cm radius that sets off from x = 0.3 towards the robot standing at x = 0.5."""
    return world(start=[0.5, 0.25, heading], moving=[{"shape": {"type": "circle", "radius": 0.05},
                                                      "path": {"type": "line", "from": [0.3, 0.25], "to": [0.9, 0.25],
                                                               "speed_mps": 0.05, "bounce": False}}])


def test_a_mover_shoves_a_robot_standing_in_its_way(engine):
    # The disc (5 cm) at 5 cm/s meets the robot (2.5 cm) when its centre reaches 0.5 - 0.075 = 0.425 m, at 2.5 s;
    # after that it shoves it ahead: at 48 ticks (6.144 s) the disc is at 0.3 + 0.05 * 6.144 = 0.6072 m and the
    # robot's centre one body-plus-disc ahead, 0.6822 m (within 2 mm: the contact's overlap), on its line; one
    # contact episode that has lasted since 2.5 s.
    sim = engine(_pusher())
    for _ in range(48):
        sim.drive([0.0, 0.0])
    assert sim.pose[0] == pytest.approx(0.6822, abs=2e-3)
    assert sim.pose[1] == pytest.approx(0.25, abs=1e-6)
    assert sim.collisions == 1
    assert sim.contact_s == pytest.approx(6.144 - 2.5, abs=0.05)


def test_the_ir_sees_a_mover_where_its_path_puts_it(engine):
    # The robot at x = 0.5 facing -x (pi), the disc coming at it from 0.3 at 5 cm/s: after 8 ticks (1.024 s) the
    # disc's centre is at 0.3512 m, its near side at 0.4012; the front sensor's ray starts on the robot's surface
    # at 0.475 and reads 0.475 - 0.4012 = 0.0738 m.
    sim = engine(_pusher(heading=math.pi))
    for _ in range(8):
        sim.drive([0.0, 0.0])
    front = int(np.argmin(np.abs(np.asarray(KHEPERA.long_range.angles))))
    assert sim.ranges(KHEPERA.long_range)[front] == pytest.approx(0.0738, abs=1e-4)


def test_a_door_that_shuts_stops_the_robot_only_after_its_time(engine):
    # A 2 cm wide box across the arena at x = 0.6 (its face at 0.59) appears at 6 s. Driven at 0.05 m/s from
    # x = 0.3 the robot's front would reach 0.59 at (0.59 - 0.325) / 0.05 = 5.3 s: it passes before the door is
    # there, and is beyond it at 6 s. The same robot sent at the door after 6 s is stopped by it.
    door = [{"at_s": 6.0, "add": [{"type": "box", "center": [0.6, 0.25], "size": [0.02, 0.5]}], "known": True}]
    sim = engine(world(events=door))
    for _ in range(60):  # 7.68 s at 5 cm/s, less the motors' lag: about 0.68 m
        sim.drive([0.05, 0.05])
    assert sim.pose[0] > 0.6 + 0.01 + R and sim.collisions == 0
    back = engine(world(start=[0.3, 0.25, 0.0], events=door))
    for _ in range(60):
        back.drive([0.0, 0.0])  # wait until the door is shut
    for _ in range(60):
        back.drive([0.16, 0.16])
    assert back.pose[0] == pytest.approx(0.59 - R, abs=2e-4)
    assert back.collisions == 1


def test_a_door_shut_on_the_robot_waits_until_the_robot_has_left():
    # The door at x = 0.3 is due at 0.3 s, when the robot driven from there at 0.1 m/s has not gone 3 cm: it
    # appears only once the robot's body is clear of it (its face at 0.31, the centre beyond 0.335); the robot then
    # drives on without a collision, and the rear sensor sees the door at its surface's distance from it.
    door = [{"at_s": 0.3, "add": [{"type": "box", "center": [0.3, 0.25], "size": [0.02, 0.5]}], "known": True}]
    for make in (PymunkEngine, JaxEngine):
        sim = make(world(events=door))
        for _ in range(12):
            sim.drive([0.1, 0.1])
        assert sim.collisions == 0 and sim.pose[0] > 0.4, make.__name__
        back = int(np.argmax(np.abs(np.asarray(KHEPERA.long_range.angles))))
        reading = sim.ranges(KHEPERA.long_range)[back]
        assert reading == pytest.approx(sim.pose[0] - R - 0.31, abs=1e-4), make.__name__


@pytest.mark.parametrize("name", ["three-rooms", "concave-obstacle"])
def test_the_engines_trace_the_same_path_through_a_named_world(name):
    # 200 ticks (25.6 s) of seeded random commands and slip draws, with contacts: the engines differ only by
    # float32 against float64 rounding, so the paths stay within 0.1 mm, the contact episodes are the same, and so
    # are the true IR ranges along the way (within 0.1 mm where either sees something)
    from robots.worldnames import load_world

    w = load_world(name)
    rng = np.random.default_rng(3)
    a, b = PymunkEngine(w), JaxEngine(w)
    worst, ranges = 0.0, []
    for tick in range(200):
        command = rng.uniform(-0.05, 0.16, 2) if tick % 25 else np.array([0.16, 0.16])
        noise = rng.uniform(-1, 1, (4, 2))
        a.drive(command, noise)
        b.drive(command, noise)
        worst = max(worst, float(np.linalg.norm(a.pose[:2] - b.pose[:2])))
        ranges.append((a.ranges(KHEPERA.long_range), b.ranges(KHEPERA.long_range)))
    assert worst < 1e-4
    assert a.collisions == b.collisions >= 1
    ra, rb = (np.array(r) for r in zip(*ranges))
    assert np.array_equal(np.isinf(ra), np.isinf(rb))
    assert np.max(np.abs(ra[np.isfinite(ra)] - rb[np.isfinite(rb)])) < 1e-4


def test_a_segment_s_clearance_is_its_least_distance_to_the_shapes():
    # In a 1 m x 0.5 m arena (walls 1 cm thick): the vertical line x = 0.1 from y = 0.1 to 0.4 passes a circle of
    # 5 cm at (0.2, 0.25) at 0.1 - 0.05 = 0.05 m and the border at x = 0 at 0.1 - 0.005 = 0.095; a line that enters
    # the circle reads 0.
    from robots.jaxworld.collide import clearance

    scene = jax.tree.map(jnp.asarray, scene_of(world(obstacles=[{"type": "circle", "center": [0.2, 0.25],
                                                                  "radius": 0.05}])))
    assert float(clearance(jnp.array([0.1, 0.1]), jnp.array([0.1, 0.4]), scene)) == pytest.approx(0.05, abs=1e-6)
    assert float(clearance(jnp.array([0.1, 0.1]), jnp.array([0.1, 0.12]), scene)) == pytest.approx(0.095, abs=1e-6)
    assert float(clearance(jnp.array([0.1, 0.25]), jnp.array([0.3, 0.25]), scene)) == 0.0
    # crossing a wall from (0.3, 0.2) to (0.7, 0.2) in the middle, every end point 0.1 m or more from the other
    walled = jax.tree.map(jnp.asarray, scene_of(world(walls=[[0.3, 0.2, 0.7, 0.2]])))
    assert float(clearance(jnp.array([0.5, 0.1]), jnp.array([0.5, 0.4]), walled)) == 0.0
