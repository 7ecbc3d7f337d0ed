"""The soccer field (robots.soccer.field): mouth, goal lines and boxes, centre spot, halves, the closed wall
outline and the parameter checks, against numbers worked out by hand."""

from collections import Counter

import pytest

from ekm.errors import InputError
from robots.geometry import Segment
from robots.soccer.field import Field

F = Field()  # 1.2 m × 0.8 m, mouth 0.24 m, depth 0.06 m, walls 0.01 m thick


def test_default_mouth_lies_between_0_28_and_0_52():
    # (0.8 - 0.24) / 2 = 0.28, (0.8 + 0.24) / 2 = 0.52
    assert F.mouth == pytest.approx((0.28, 0.52))


def test_mouth_of_a_custom_field_is_centred_on_its_end():
    # (1.0 - 0.3) / 2 = 0.35, (1.0 + 0.3) / 2 = 0.65
    assert Field(length=2.0, width=1.0, goal_mouth=0.3).mouth == pytest.approx((0.35, 0.65))


def test_goal_lines_are_the_mouths_on_x_0_and_x_length():
    left, right = F.goal_line(0), F.goal_line(1)
    assert left.start == pytest.approx((0.0, 0.28)) and left.end == pytest.approx((0.0, 0.52))
    assert right.start == pytest.approx((1.2, 0.28)) and right.end == pytest.approx((1.2, 0.52))


def test_goal_boxes_lie_behind_the_lines_goal_depth_deep():
    # left: x in [0 - 0.06, 0]; right: x in [1.2, 1.2 + 0.06] = [1.2, 1.26]
    assert F.goal_box(0) == pytest.approx((-0.06, 0.28, 0.0, 0.52))
    assert F.goal_box(1) == pytest.approx((1.2, 0.28, 1.26, 0.52))


def test_centre_spot_is_the_middle_of_the_field():
    assert F.centre_spot == pytest.approx((0.6, 0.4))  # (1.2 / 2, 0.8 / 2)


def test_half_is_decided_by_the_half_way_line_at_x_0_6():
    assert F.half((0.59, 0.1)) == 0
    assert F.half((-0.03, 0.4)) == 0  # inside side 0's goal box
    assert F.half((0.61, 0.7)) == 1
    assert F.half((1.23, 0.4)) == 1  # inside side 1's goal box
    assert F.half((0.6, 0.4)) is None  # on the line: nobody's


def test_twelve_walls_form_a_closed_outline_with_the_goal_boxes_in_it():
    walls = F.walls()
    assert len(walls) == 12  # 2 side walls + 2 × (2 end-wall pieces + 2 box sides + 1 back)
    ends = Counter((round(x, 9), round(y, 9)) for s in walls for (x, y) in (s.start, s.end))
    assert set(ends.values()) == {2}  # every end point joins exactly two walls: no gap anywhere


def test_wall_centre_lines_put_their_inner_faces_on_the_lines_of_the_game():
    # each wall is 0.01 m thick, so its centre line lies h = 0.005 m outside the line it bounds
    walls = {frozenset({(round(w.start[0], 9), round(w.start[1], 9)), (round(w.end[0], 9), round(w.end[1], 9))})
             for w in F.walls()}

    def has(a, b):
        return frozenset({a, b}) in walls

    assert has((-0.005, -0.005), (1.205, -0.005))  # bottom side wall, inner face y = 0
    assert has((-0.005, 0.805), (1.205, 0.805))  # top side wall, inner face y = 0.8
    # left end wall: corner to the lower post (0.28 - 0.005 = 0.275), upper post (0.52 + 0.005 = 0.525) to corner
    assert has((-0.005, -0.005), (-0.005, 0.275)) and has((-0.005, 0.525), (-0.005, 0.805))
    # left goal box: sides from the end wall back to x = -0.06 - 0.005 = -0.065, and the back post to post
    assert has((-0.005, 0.275), (-0.065, 0.275)) and has((-0.005, 0.525), (-0.065, 0.525))
    assert has((-0.065, 0.275), (-0.065, 0.525))
    # right end: mirrored at x = 1.2 + 0.005 = 1.205, back at 1.2 + 0.06 + 0.005 = 1.265
    assert has((1.205, -0.005), (1.205, 0.275)) and has((1.205, 0.525), (1.205, 0.805))
    assert has((1.205, 0.275), (1.265, 0.275)) and has((1.205, 0.525), (1.265, 0.525))
    assert has((1.265, 0.275), (1.265, 0.525))


def test_clearance_is_the_distance_to_the_nearest_wall_surface():
    assert F.clearance(F.centre_spot) == pytest.approx(0.4)  # side walls at y = 0 and 0.8; ends 0.6 away
    assert F.clearance((-0.03, 0.4)) == pytest.approx(0.03)  # back of the left goal at x = -0.06
    # 4 mm into the bottom wall: 0.001 m from its centre line y = -0.005, minus its half thickness 0.005
    assert F.clearance((0.1, -0.004)) == pytest.approx(-0.004)


def test_contains_keeps_a_ball_clear_of_the_walls_and_lets_it_into_the_goal_box():
    r = 0.02
    assert F.contains(F.centre_spot, margin=r)
    assert not F.contains((0.01, 0.1), margin=r)  # 0.01 m from the end wall < 0.02 m
    assert F.contains((-0.03, 0.4), margin=r)  # in the left goal: 0.03 m from its back, 0.12 m from its sides
    assert not F.contains((-0.03, 0.2), margin=r)  # behind the end wall, beside the goal
    assert not F.contains((-0.05, 0.4), margin=r)  # 0.01 m from the back of the goal
    assert not F.contains((-0.2, 0.4), margin=0.0)  # far behind the goal: off the pitch, though clear of walls
    # beside the upper post, whose corner is rounded: the nearest wall is the joint's cap around
    # (-0.005, 0.525), of radius 0.005, at sqrt(0.02² + 0.02²) - 0.005 = 0.0233 m >= 0.02 m
    assert F.contains((0.015, 0.505), margin=r)
    assert not F.contains((0.012, 0.508), margin=r)  # sqrt(0.017² + 0.017²) - 0.005 = 0.0190 m < 0.02 m


@pytest.mark.parametrize("kwargs, name", [
    (dict(goal_mouth=0.9), "goal_mouth"),  # wider than the 0.8 m field
    (dict(goal_mouth=0.8), "goal_mouth"),  # as wide as the field: no end wall left
    (dict(length=-1.2), "length"),
    (dict(width=0.0), "width"),
    (dict(goal_mouth=-0.24), "goal_mouth"),
    (dict(goal_depth=-0.06), "goal_depth"),
    (dict(wall_thickness=-0.01), "wall_thickness"),
    (dict(length=float("nan")), "length"),
    (dict(width="0.8"), "width"),
])
def test_bad_field_parameters_are_refused_in_one_line_naming_them(kwargs, name):
    with pytest.raises(InputError) as err:
        Field(**kwargs)
    message = str(err.value)
    assert name in message and "\n" not in message


def test_wall_thickness_zero_is_allowed():
    assert Field(wall_thickness=0.0).walls()[0] == Segment((0.0, 0.0), (1.2, 0.0))


def test_a_side_other_than_0_or_1_is_refused():
    with pytest.raises(InputError, match="side"):
        F.goal_line(2)
