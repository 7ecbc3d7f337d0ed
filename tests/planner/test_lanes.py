"""Declared movers' lanes (planner.lanes, planner.plan's ``lanes``): the lane is the ground a straight mover sweeps;
the route keeps beside it where that is cheap and plans as before where it is not. Numbers worked out by hand."""

import math

import numpy as np
import pytest

from planner import plan
from planner.lanes import convex_hull, lanes
from robots.worldfile import parse_world

R = 0.025  # m: the Khepera's radius, the planner's default padding


def corridor(mover_y=0.22, door=None, mover=None):
    """A 1.2 x 0.4 m arena (walls' faces at 5 mm and 395 mm), start (0.1, 0.2), goal (1.1, 0.2). The default
    mover: a 6 x 5 cm box shuttling from (0.2, mover_y) to (1.0, mover_y) — lane x 0.17..1.03, y mover_y ± 0.025."""
    doc = {"name": "lane", "size": [1.2, 0.4], "start": [0.1, 0.2, 0.0], "goal": [1.1, 0.2],
           "moving": [mover or {"shape": {"type": "box", "center": [0.0, 0.0], "size": [0.06, 0.05]},
                                "path": {"type": "line", "from": [0.2, mover_y], "to": [1.0, mover_y],
                                         "speed_mps": 0.05}}]}
    if door is not None:  # a wall across at x = 0.6 with one doorway between y = door[0] and door[1] (faces)
        doc["walls"] = [[0.6, 0.0, 0.6, door[0] - 0.005], [0.6, door[1] + 0.005, 0.6, 0.4]]
    return parse_world(doc, "lane.json")


def route(p, n=400):
    """Points along start -> checkpoints, ``n`` per leg."""
    ends = np.vstack([np.asarray(p.start)[None], p.checkpoints])
    s = np.linspace(0.0, 1.0, n)[:, None]
    return np.concatenate([a + s * (b - a) for a, b in zip(ends[:-1], ends[1:])])


def to_box(points, x0, y0, x1, y1):
    """Distance of each point to the axis-aligned box [x0, x1] x [y0, y1] (0 inside)."""
    dx = np.maximum(np.maximum(x0 - points[:, 0], points[:, 0] - x1), 0.0)
    dy = np.maximum(np.maximum(y0 - points[:, 1], points[:, 1] - y1), 0.0)
    return np.hypot(dx, dy)


def test_the_lane_of_a_box_shuttling_along_a_line_is_the_rectangle_it_sweeps():
    (lane,) = lanes(corridor())
    corners = {(round(x, 9), round(y, 9)) for x, y in lane.vertices()}
    assert corners == {(0.17, 0.195), (1.03, 0.195), (1.03, 0.245), (0.17, 0.245)}


def test_the_lane_of_a_disc_holds_the_disc_at_both_ends_within_its_16_gon():
    disc = {"shape": {"type": "circle", "radius": 0.02},
            "path": {"type": "line", "from": [0.5, 0.15], "to": [0.7, 0.15], "speed_mps": 0.05}}
    (lane,) = lanes(corridor(mover=disc))
    v = np.asarray(lane.vertices())
    far = 0.02 / math.cos(math.pi / 16)  # the circumscribed 16-gon's corner: 20.39 mm from the centre
    np.testing.assert_allclose([v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), v[:, 1].max()],
                               [0.5 - far, 0.7 + far, 0.15 - far, 0.15 + far], atol=1e-9)
    assert len(v) == 18  # 9 corners of each end's half 16-gon (two of them on the vertical diameter)


def test_a_mover_on_a_circle_has_no_lane():
    circling = {"shape": {"type": "circle", "radius": 0.02},
                "path": {"type": "circle", "center": [0.6, 0.2], "radius": 0.1, "period_s": 10.0}}
    assert lanes(corridor(mover=circling)) == ()


def test_convex_hull_drops_inner_and_collinear_points():
    pts = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 0.5), (0, 1), (0, 0.5)]
    assert convex_hull(pts).tolist() == [[0, 0], [2, 0], [2, 1], [0, 1]]


def test_the_route_keeps_the_robot_the_margin_beside_a_lane_down_the_corridors_middle():
    """Start and goal at y = 0.2 either side of the lane (y 0.195..0.245): the straight route runs through it; kept
    off, every point of it lies at least radius + margin = 3.5 cm from the lane (below, where 19 cm of room is)."""
    world = corridor()
    plain = plan(world)
    assert to_box(route(plain), 0.17, 0.195, 1.03, 0.245).min() == 0.0  # the plain route crosses the lane
    kept = plan(world, lanes=(0.01, 1.3))
    assert len(kept.avoided) == 1
    assert to_box(route(kept), 0.17, 0.195, 1.03, 0.245).min() >= R + 0.01 - 1e-9
    assert plain.length < kept.length <= 1.3 * plain.length


@pytest.mark.parametrize("lanes_arg, why", [((0.01, 1.0), "any detour is too long"),
                                            ((0.2, 1.3), "no route leaves 20 cm beside the lane"),
                                            (None, "lanes off")])
def test_the_plan_is_the_plain_one_where_keeping_off_the_lane_is_not_cheap(lanes_arg, why):
    world = corridor()
    p = plan(world, lanes=lanes_arg)
    assert p.avoided == () and np.array_equal(p.checkpoints, plan(world).checkpoints), why


def test_a_lane_across_the_only_doorway_leaves_the_plan_as_without_lanes():
    """A 10 cm doorway (y 0.15..0.25) in a wall at x = 0.6; the box shuttles along y = 0.2 through it, its lane
    leaving 2.5 cm each side — less than the robot's 5 cm: no route keeps off, so the plan goes through the door."""
    world = corridor(door=(0.15, 0.25))
    p = plan(world, lanes=(0.01, 1.3))
    assert p.avoided == () and np.array_equal(p.checkpoints, plan(world).checkpoints)
    xs = route(p)
    at_wall = xs[np.abs(xs[:, 0] - 0.6) < 1e-3]
    assert len(at_wall) and np.all((0.15 + R - 1e-3 <= at_wall[:, 1]) & (at_wall[:, 1] <= 0.25 - R + 1e-3))


def test_a_replan_keeps_off_the_lane_too():
    from planner import replan

    world = corridor()
    p = replan(plan(world), world, (0.3, 0.1), 0.0, lanes=(0.01, 1.3))
    assert len(p.avoided) == 1 and to_box(route(p), 0.17, 0.195, 1.03, 0.245).min() >= R + 0.01 - 1e-9


def test_a_lane_no_route_can_keep_off_does_not_stop_the_route_keeping_off_another():
    """The doorway of the test above, a 6 x 5 cm box shuttling through it (y = 0.2, x 0.55..0.65: lane x 0.52..0.68,
    y 0.175..0.225, 2.5 cm each side in the 10 cm doorway) and a second box shuttling beyond it along y = 0.22, x
    0.75..1.0 (lane x 0.72..1.03, y 0.195..0.245) across the straight way to the goal (1.1, 0.2). No route keeps off
    both; one keeps off the second's lane, below it (19 cm of room): it is planned, through the doorway, and keeps
    radius + margin = 3.5 cm from that lane."""
    doc = {"name": "two-lanes", "size": [1.2, 0.4], "start": [0.1, 0.2, 0.0], "goal": [1.1, 0.2],
           "walls": [[0.6, 0.0, 0.6, 0.145], [0.6, 0.255, 0.6, 0.4]],
           "moving": [{"shape": {"type": "box", "center": [0.0, 0.0], "size": [0.06, 0.05]},
                       "path": {"type": "line", "from": [x0, y], "to": [x1, y], "speed_mps": 0.05}}
                      for x0, x1, y in ((0.55, 0.65, 0.2), (0.75, 1.0, 0.22))]}
    world = parse_world(doc, "two-lanes.json")
    p = plan(world, lanes=(0.01, 1.3))
    assert len(p.avoided) == 1
    xs = route(p)
    assert to_box(xs, 0.72, 0.195, 1.03, 0.245).min() >= R + 0.01 - 1e-9
    at_wall = xs[np.abs(xs[:, 0] - 0.6) < 1e-3]
    assert len(at_wall) and np.all((0.15 + R - 1e-3 <= at_wall[:, 1]) & (at_wall[:, 1] <= 0.25 - R + 1e-3))
    assert to_box(route(plan(world)), 0.72, 0.195, 1.03, 0.245).min() == 0.0  # the plain route crosses that lane


def test_a_route_runs_along_a_lane_it_follows_and_not_along_one_it_crosses():
    """The default box's lane (x 0.17..1.03, y 0.195..0.245, the mover's path along x): a leg along y = 0.2 lies in it
    for 86 cm at 0°; one along x = 0.6 crosses it at 90°; one at 30° to the path from y = 0.22 is in it for its first
    5 cm; one at 60° starts in it too, but beyond the 45° that count as along."""
    from planner.lanes import runs_along

    world = corridor()
    assert runs_along(world, [(0.1, 0.2), (1.1, 0.2)]) == (True,)
    assert runs_along(world, [(0.6, 0.02), (0.6, 0.38)]) == (False,)
    assert runs_along(world, [(0.5, 0.22), (0.5 + 0.2 * math.cos(math.pi / 6), 0.22 + 0.2 * math.sin(math.pi / 6))]) \
        == (True,)
    assert runs_along(world, [(0.5, 0.22), (0.5 + 0.2 * math.cos(math.pi / 3), 0.22 + 0.2 * math.sin(math.pi / 3))]) \
        == (False,)
    assert runs_along(world, [(0.1, 0.1), (1.1, 0.1)]) == (False,)  # along, but 7.5 cm below the lane
