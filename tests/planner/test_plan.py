"""Planning (planner.plan): every decomposition labels the free cells; planning through the named worlds —
doorways, free checkpoints, replanning after a known event (Fig. 6.5)."""

import numpy as np
import pytest

from ekm.errors import InputError
from planner import METHODS, NoRouteError, decompose, map_changed, plan, replan
from planner.bitmap import FREE
from planner.examples import random_bitmap
from robots.worldfile import parse_world
from robots.worldnames import load_world, named_worlds
from tests.planner.checks import assert_checkpoints_on_shared_boundaries, check_decomposition


# ------------------------------------------------------------------------------------------- decompositions

@pytest.mark.parametrize("method", ["slippery", "quadtree", "grid"])
def test_every_decomposition_labels_exactly_the_free_cells(method):
    W = random_bitmap((30, 50), 0.3, np.random.default_rng(7))
    check_decomposition(W, decompose(W, method, tuple(np.argwhere(W == FREE)[0])))


def test_grid_makes_one_cell_per_free_bitmap_cell():
    W = random_bitmap((30, 50), 0.3, np.random.default_rng(3))
    assert decompose(W, "grid").max() == (W == FREE).sum()


# ----------------------------------------------------------------------------------------- the named worlds

def crossing_y(p, x_wall):
    """Heights at which the checkpoint path start → checkpoints crosses the vertical line ``x = x_wall``."""
    pts = np.vstack([np.asarray(p.start)[None], p.checkpoints])
    ys = []
    for (x0, y0), (x1, y1) in zip(pts[:-1], pts[1:]):
        if (x0 - x_wall) * (x1 - x_wall) < 0 or (x1 == x_wall and x0 != x_wall):
            ys.append(y0 + (x_wall - x0) * (y1 - y0) / (x1 - x0))
    return ys


def passes_doorway(p, x_wall, lo, hi):
    """The checkpoint path crosses ``x = x_wall`` once, between ``lo`` and ``hi``, with a checkpoint there."""
    ys = crossing_y(p, x_wall)
    at_door = [c for c in p.checkpoints if abs(c[0] - x_wall) <= 0.05 and lo <= c[1] <= hi]
    return len(ys) == 1 and lo - 1e-9 <= ys[0] <= hi + 1e-9 and bool(at_door)


@pytest.mark.parametrize("name", named_worlds())
@pytest.mark.parametrize("method", METHODS)
def test_thesis_checkpoints_lie_in_free_space_on_shared_boundaries(name, method):
    world = load_world(name)
    p = plan(world, method=method, checkpoints="thesis")
    assert_checkpoints_on_shared_boundaries(p)
    assert world.clearance(p.checkpoints, 0.0, known_only=True).min() >= 0.025 - 1e-9
    # The legs between checkpoints: those of convex cells (quadtree, grid) keep the whole cushion; a slippery
    # cell need not be convex, so its legs may cut a cushion's corner (Plan's docstring) but never a wall.
    pts = np.vstack([np.asarray(p.start)[None], p.checkpoints])
    legs = np.concatenate([a + np.linspace(0.0, 1.0, 200)[:, None] * (b - a) for a, b in zip(pts[:-1], pts[1:])])
    closest = world.clearance(legs, 0.0, known_only=True).min()
    assert closest >= (0.025 - 1e-9 if method != "slippery" else 0.015), closest
    assert p.length == pytest.approx(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


@pytest.mark.parametrize("method", METHODS)
def test_three_rooms_route_passes_both_doorways(method):
    p = plan(load_world("three-rooms"), method=method, checkpoints="thesis")
    assert passes_doorway(p, 0.4, 0.24, 0.36)
    assert passes_doorway(p, 0.8, 0.10, 0.22)


@pytest.mark.parametrize("name", named_worlds())
@pytest.mark.parametrize("method", METHODS)
def test_visible_checkpoints_are_joined_by_legs_that_keep_the_cushion(name, method):
    """Every leg start → checkpoint → … → goal keeps the robot radius from every known wall and obstacle
    (the rule's promise, measured here with the world's own clearance, not the planner's slack)."""
    world = load_world(name)
    p = plan(world, method=method)
    assert p.rule == "visible"
    pts = np.vstack([np.asarray(p.start)[None], p.checkpoints])
    legs = np.concatenate([a + np.linspace(0.0, 1.0, 400)[:, None] * (b - a) for a, b in zip(pts[:-1], pts[1:])])
    assert world.clearance(legs, 0.0, known_only=True).min() >= 0.025 - 0.003 - 1e-9
    np.testing.assert_array_equal(p.checkpoints[-1], world.goal_at(0.0))


def test_slippery_plan_of_three_rooms():
    p = plan(load_world("three-rooms"), checkpoints="thesis")
    assert p.method == "slippery" and p.cells == 5 and len(p.route) == 3
    assert np.allclose(p.checkpoints, [[0.44, 0.28], [0.84, 0.18], [1.1, 0.42]])


def test_three_rooms_changed_uses_the_lower_doorway_then_replans_through_the_upper():
    world = load_world("three-rooms-changed")
    lower, upper = (0.10, 0.22), (0.40, 0.52)
    before = plan(world, checkpoints="thesis")
    assert passes_doorway(before, 0.8, *lower)

    assert not map_changed(world, 0.0, 5.9) and map_changed(world, 5.9, 6.0)
    for position in [(0.6, 0.3), (0.6, 0.2), (0.5, 0.1), (0.7, 0.5)]:  # the robot somewhere in the middle room
        after = replan(before, world, position, t=6.0)
        assert (after.method, after.cell, after.goal) == (before.method, before.cell, before.goal)
        assert after.start == position
        assert passes_doorway(after, 0.8, *upper), (position, after.checkpoints)
        assert_checkpoints_on_shared_boundaries(after)


def test_replanning_starts_where_the_robot_is_even_inside_the_cushion():
    """A robot pressed against a wall (centre 22 mm from it, inside the 25 mm cushion) still gets a plan
    from its own position; plan() would refuse such a start as user input."""
    world = load_world("three-rooms-changed")
    before = plan(world, checkpoints="thesis")
    against_wall = (0.4 + 0.005 + 0.022, 0.45)
    with pytest.raises(InputError, match="not in the free space"):
        plan(world, against_wall)
    after = replan(before, world, against_wall, t=6.0)
    assert after.start == against_wall and passes_doorway(after, 0.8, 0.40, 0.52)


def test_replanning_with_reach_starts_at_the_nearest_free_point_when_the_robot_stands_in_a_new_cushion():
    """Recovery adds the obstacle the robot is pressed against: its centre is then deep in the new cushion."""
    import dataclasses

    from robots.geometry import Circle

    world = load_world("three-rooms-changed")
    before = plan(world)
    blocked = dataclasses.replace(world, obstacles=(Circle((0.6, 0.33), 0.02),))
    robot = (0.6, 0.3)  # 1 cm from the new disc: 3.5 cm inside its 4.5 cm cushion
    with pytest.raises(InputError, match="no free bitmap cell"):
        replan(before, blocked, robot, t=6.0)
    after = replan(before, blocked, robot, t=6.0, reach=0.06)
    moved = np.hypot(after.start[0] - robot[0], after.start[1] - robot[1])
    assert 0.0 < moved <= 0.06 and passes_doorway(after, 0.8, 0.40, 0.52)


def test_replanning_labels_from_the_robots_new_cell():
    world = load_world("three-rooms-changed")
    after = replan(plan(world), world, (0.6, 0.3), t=6.0)
    assert after.route[0] == 1  # the first slippery cell grows from the robot's cell (Fig. 3.3b)


@pytest.mark.parametrize("start, goal, match", [
    ((0.4, 0.1), None, "start \\(0.4, 0.1\\): not in the free space"),  # inside the wall
    ((0.01, 0.3), None, "start .*not in the free space"),  # within the cushion of the border
    ((1.5, 0.3), None, "start .*not in the free space"),  # outside the arena
    (None, (0.8, 0.3), "goal \\(0.8, 0.3\\): not in the free space"),  # inside the wall
])
def test_start_or_goal_outside_the_free_space_is_refused(start, goal, match):
    with pytest.raises(InputError, match=match):
        plan(load_world("three-rooms"), start, goal)


def test_goal_walled_off_by_a_known_event_has_no_route():
    doc = {"name": "closed", "size": [1.2, 0.6], "walls": [[0.6, 0.0, 0.6, 0.25], [0.6, 0.35, 0.6, 0.6]],
           "events": [{"at_s": 1.0, "add": [{"type": "box", "center": [0.6, 0.3], "size": [0.02, 0.1]}]}],
           "start": [0.2, 0.3, 0.0], "goal": [1.0, 0.3]}
    world = parse_world(doc, "closed.json")
    assert plan(world, t=0.0).route  # through the doorway
    with pytest.raises(NoRouteError):
        plan(world, t=1.0)


def test_unknown_method_is_refused():
    with pytest.raises(InputError, match="method: must be one of slippery, quadtree, grid"):
        plan(load_world("three-rooms"), method="voronoi")


def test_a_plan_is_remembered_shared_read_only_and_equal_to_a_fresh_one():
    from planner.plan import _plan
    from robots.params import KHEPERA

    world = load_world("three-rooms")
    first, again = plan(world), plan(world, start=np.array(world.start[:2]))
    assert again is first  # the same start given as an array finds the remembered plan
    fresh = _plan(world, world.start[:2], world.goal, first.cell, first.method, 0.0, KHEPERA.radius, check=("start", "goal"),
                  checkpoints="visible")
    np.testing.assert_array_equal(first.checkpoints, fresh.checkpoints)
    np.testing.assert_array_equal(first.labels, fresh.labels)
    for a in (first.bitmap, first.labels, first.checkpoints):
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 0
    assert plan(world, cell=0.025) is not first
