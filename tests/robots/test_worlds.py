"""The named worlds (robots/worlds; docs/design.md §2, thesis Figs. 6.3–6.8)."""

import math

import numpy as np
import pytest

from robots.geometry import distance
from robots.params import KHEPERA, LONG_RANGE, SHORT_RANGE
from robots.plot import plot_world, save_figure
from robots.world import PymunkWorld
from robots.worldfile import CirclePath, LinePath
from robots.worldnames import load_world, named_worlds

R = KHEPERA.radius
REACH = R + LONG_RANGE.range_m  # a long-range sensor sees 20 cm from the robot's centre (thesis ch. 6.2.2)


def line(a, b, n=200):
    return np.linspace(a, b, n)


def test_all_eight_worlds_are_shipped():
    assert named_worlds() == ["concave-obstacle", "extended-obstacle", "moving-target", "open-arena", "three-rooms",
                              "three-rooms-changed", "three-rooms-moving", "three-rooms-static"]


@pytest.mark.parametrize("name", named_worlds())
def test_each_world_loads_keeps_start_and_goal_clear_and_plots(name, tmp_path):
    world = load_world(name)
    assert world.name == name
    assert world.clearance(np.asarray(world.start[:2])) >= R + 0.02  # room to turn at the start
    goals = (np.array([world.goal_at(t) for t in np.linspace(0, 60, 601)]) if world.moving_goal
             else np.asarray([world.goal]))
    assert world.clearance(goals).min() >= R  # the robot's centre can reach the goal
    ax = plot_world(world, sensors=SHORT_RANGE)
    assert ax.get_aspect() == 1.0
    png = save_figure(ax.figure, tmp_path / f"{name}.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert [p.name for p in tmp_path.iterdir()] == [f"{name}.png"]  # no temp file left behind
    PymunkWorld(world, seed=0).step([0.05, 0.05])  # the physics accepts every shape in it


@pytest.mark.parametrize("name", ["three-rooms-static", "three-rooms-moving", "three-rooms-changed"])
def test_three_rooms_variants_keep_the_three_rooms_layout(name):
    base, world = load_world("three-rooms"), load_world(name)
    assert (world.size, world.start) == (base.size, base.start)
    if name != "three-rooms-changed":  # that one opens a second doorway on purpose (Fig. 6.5)
        assert world.walls == base.walls and world.goal == base.goal


def test_static_obstacle_blocks_the_way_between_the_doorways_but_leaves_room_around():
    world = load_world("three-rooms-static")
    (box,) = world.unforeseen
    between = line((0.4, 0.3), (0.8, 0.16))  # doorway to doorway (Fig. 6.3: between checkpoints 1 and 2)
    assert distance(between, box).min() == 0.0
    x0, y0 = np.min(box.vertices(), axis=0)
    x1, y1 = np.max(box.vertices(), axis=0)
    assert 0.4 < x0 < x1 < 0.8
    assert min(y0, 0.6 - y1) > 2 * R + 0.05  # the robot can go round either side


def test_moving_obstacle_is_robot_sized_and_circles_anticlockwise_in_the_middle_room():
    world = load_world("three-rooms-moving")
    (mover,) = world.moving
    assert mover.shape.radius == R  # "a mobile robot ... served as the moving obstacle" (Fig. 6.4)
    assert isinstance(mover.path, CirclePath) and mover.path.direction == "ccw"
    x0, y0, x1, y1 = mover.path.extent()
    assert 0.4 + R < x0 - R and x1 + R < 0.8 - R  # never touches the room's walls
    crossing = line((0.4, 0.3), (0.8, 0.16))
    assert np.min(np.abs(np.hypot(*(crossing - mover.path.center).T) - mover.path.radius)) < 0.005  # crosses the way


def test_extended_obstacle_is_longer_than_the_sensors_can_see_across_the_straight_way():
    world = load_world("extended-obstacle")
    (wall,) = world.unforeseen
    assert distance(line(world.start[:2], world.goal), wall).min() == 0.0
    face_x = np.min(wall.vertices()[:, 0])
    in_front = np.array([face_x - R - 0.01, world.start[1]])  # pressed against its middle
    corners = wall.vertices()
    assert np.hypot(*(corners - in_front).T).min() > REACH  # from there no sensor sees either end
    gaps = (np.min(corners[:, 1]), world.size[1] - np.max(corners[:, 1]))
    assert min(gaps) > 2 * R + 0.05  # but there is a way round


def test_concave_trap_opens_towards_the_robot_and_is_deeper_than_the_sensors_reach():
    world = load_world("concave-obstacle")
    sim = PymunkWorld(world, seed=0)
    y = world.start[1]
    assert distance(line(world.start[:2], world.goal), world.unforeseen[0]).min() == 0.0
    sim.place((0.47, y, 0.0))  # just inside the mouth, heading for the goal
    at_mouth = sim.ranges()
    assert at_mouth[0] == np.inf  # the bottom is still out of sight: the robot drives in
    assert np.isfinite(at_mouth[3]) and np.isfinite(at_mouth[9])  # both arms are seen (±90 degrees)
    sim.place((0.70, y, 0.0))
    assert world.clearance(sim.pose[:2]) > R + 0.02  # room inside to turn round
    assert np.isfinite(sim.ranges()[[0, 1, 3, 9, 11]]).all()  # deep inside: walls ahead and on both sides


def test_moving_target_crosses_the_arena_on_a_line():
    world = load_world("moving-target")
    assert isinstance(world.goal, LinePath) and world.goal.bounce
    assert math.dist(world.goal_at(0.0), world.goal_at(10.0)) == pytest.approx(0.4)
    assert world.counts()["moving_goal"] is True
