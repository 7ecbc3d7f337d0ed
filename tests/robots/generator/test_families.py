"""Generated worlds (robots.generator, its families and build): every family makes checked, solvable,
reproducible worlds with its features; the spellings of a generated world's name."""

import collections
import dataclasses
import functools
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from ekm.errors import InputError
from robots.generator import FAMILIES, Family, generate, parse_spelling
from robots.generator.shapes import route_passes, shape_gap, walls_apart
from robots.generator.reach import reach
from robots.geometry import Box, Circle, Polygon, Segment, bounds, distance
from robots.params import KHEPERA
from robots.worldfile import parse_world, world_document, world_json
from robots.worldnames import load_world

R = KHEPERA.radius
SEEDS = (0, 1, 2, 7)
CASES = [(f, s, None) for f in FAMILIES for s in SEEDS] + [(f, 11, d) for f in FAMILIES for d in (0.0, 1.0)]


@functools.lru_cache(maxsize=None)
def made(family, seed, difficulty=None):
    return generate(family, seed, difficulty)


def ids(case):
    family, seed, difficulty = case
    return f"{family}:{seed}" + ("" if difficulty is None else f":{difficulty:g}")


def test_the_families_in_order_each_with_a_one_line_description():
    assert list(FAMILIES) == ["corridor", "traps", "clutter", "maze", "movers", "blocked", "niches", "traffic",
                              "pillars", "shapes", "slanted", "large", "doors"]
    assert all(f.summary and "\n" not in f.summary for f in FAMILIES.all().values())


@pytest.mark.parametrize("case", CASES, ids=ids)
def test_a_generated_world_is_checked_solvable_and_labelled(case):
    family, seed, difficulty = case
    w = made(*case)
    assert w.name == ids(case) and w.source == w.name
    again = parse_world(world_document(w))
    assert again == w and again.difficulty == w.difficulty  # the file holds everything, the label too
    assert parse_world(json.loads(world_json(w))) == w
    d = w.difficulty
    assert (d.family, d.seed) == (family, seed) and 0.0 <= d.level <= 1.0
    if difficulty is not None:
        assert d.level == difficulty
    assert all(0.8 - 1e-9 <= side <= (6.3 if family == "large" else 2.5) + 1e-9 for side in w.size)
    assert w.clearance(np.asarray(w.start[:2])) >= R and w.clearance(np.asarray(w.goal), include_moving=False) >= R
    assert d.straight_m >= 0.5 and d.route_ratio >= 1.0
    found = reach(w)
    assert found.solvable
    assert found.measures() == {k: getattr(d, k) for k in found.measures()}  # the label is the search's
    assert d.movers == len(w.moving)


@pytest.mark.parametrize("family", FAMILIES)
def test_a_world_is_made_again_bit_for_bit_from_its_name(family):
    w = made(family, 2)
    assert load_world(w.name) == w and world_json(load_world(w.name)) == world_json(w)
    assert world_json(generate(family, 2)) == world_json(w)
    # A given difficulty leaves the rest of the seed's stream alone: the drawn level, given, lays out the same.
    given = generate(family, 2, w.difficulty.level)
    assert given.name == f"{family}:2:{w.difficulty.level:g}"
    assert dataclasses.replace(given, name=w.name) == w


def test_the_same_world_in_another_process():
    code = ("from robots.generator import FAMILIES, generate; from robots.worldfile import world_json; "
            "print(''.join(world_json(generate(f, 7)) for f in FAMILIES), end='')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out == "".join(world_json(made(f, 7)) for f in FAMILIES)


def test_the_numbers_are_rounded_to_a_tenth_of_a_millimetre():
    def numbers(v):
        if isinstance(v, dict):
            return [x for value in v.values() for x in numbers(value)]
        if isinstance(v, list):
            return [x for value in v for x in numbers(value)]
        return [v] if isinstance(v, float) else []

    for family in FAMILIES:
        values = numbers(world_document(made(family, 1)))
        assert values and all(round(x, 4) == x for x in values)


def test_a_layout_drawn_again_is_drawn_from_the_next_sub_seed(monkeypatch):
    from robots.generator.layout import Retry

    maze, calls, plain = FAMILIES["maze"], [], made("maze", 5)

    def first_refused(rng, level):
        calls.append(level)
        if len(calls) % 2:
            raise Retry
        return maze.layout(rng, level)

    monkeypatch.setitem(FAMILIES.built_in(), "maze", Family("maze", first_refused, maze.summary))
    a, b = generate("maze", 5), generate("maze", 5)
    assert len(calls) == 4 and world_json(a) == world_json(b) and a != plain
    assert a.difficulty.level == plain.difficulty.level  # the level is the seed's, whatever the attempt


def test_a_world_without_a_route_is_never_returned(monkeypatch):
    from robots.generator import reach as reach_module
    from robots.generator.build import ATTEMPTS

    real, answers, plain = reach_module.reach, [], made("traps", 3)

    def first_unsolvable(world, **kw):
        answers.append(len(answers) > 0)
        return real(world, **kw) if answers[-1] else reach_module.Reach(False, 1.0)

    monkeypatch.setattr(reach_module, "reach", first_unsolvable)
    w = generate("traps", 3)
    assert answers == [False, True] and w != plain and real(w).solvable
    monkeypatch.setattr(reach_module, "reach", lambda world, **kw: reach_module.Reach(False, 1.0))
    with pytest.raises(InputError, match=f"traps:3: .*found no route for the robot's disc \\({ATTEMPTS} of {ATTEMPTS} "
                                         "layouts drawn"):
        generate("traps", 3)


def test_a_spelling_no_layout_fits_names_the_commonest_reason(monkeypatch):
    from robots.generator.build import ATTEMPTS
    from robots.generator.layout import Retry

    maze, calls = FAMILIES["maze"], []

    def refused(rng, level):  # two reasons, the second twice as often
        calls.append(level)
        raise Retry("too narrow" if len(calls) % 3 else "too wide")

    monkeypatch.setitem(FAMILIES.built_in(), "maze", Family("maze", refused, maze.summary))
    with pytest.raises(InputError) as caught:
        generate("maze", 5)
    assert len(calls) == ATTEMPTS == 50
    assert str(caught.value) == ("maze:5: no world of this spelling from seed 5: too narrow (34 of 50 layouts drawn); "
                                 "try another seed or family")


def test_seeds_span_the_difficulties():
    levels = [generate("movers", s).difficulty.level for s in range(12)]
    assert min(levels) < 0.25 and max(levels) > 0.75


# ------------------------------------------------------------------------------------------------- features

def wall_lines(w):
    return [(np.array(s.start), np.array(s.end)) for s in w.walls]


def corridor_widths(w) -> list:
    """For each wall, the width (between surfaces) to the nearest parallel wall facing it across a stretch the
    robot's route runs through: the corridor's width, measured from the walls."""
    samples = [a + t * (b - a) for a, b in zip(*(lambda r: (r[:-1], r[1:]))(reach(w).route))
               for t in np.linspace(0, 1, 50)]
    samples = np.array(samples)
    widths = []
    for a, b in wall_lines(w):
        length = np.hypot(*(b - a))
        u = (b - a) / length
        n = np.array([-u[1], u[0]])
        found = []
        for c, d in wall_lines(w):
            if abs(np.dot(d - c, n)) > 1e-3 * np.hypot(*(d - c)):
                continue  # not parallel
            off = np.dot(c - a, n)
            ends = sorted((np.dot(c - a, u), np.dot(d - a, u)))
            lo, hi = max(0.0, ends[0]), min(length, ends[1])
            if abs(off) < 1e-6 or hi - lo < 0.01:
                continue
            along, across = (samples - a) @ u, ((samples - a) @ n) * np.sign(off)
            if np.any((along > lo) & (along < hi) & (across > 0) & (across < abs(off))):
                found.append(abs(off) - w.wall_thickness)
        if found:
            widths.append(min(found))
    return widths


@pytest.mark.parametrize("seed, difficulty", [(s, None) for s in SEEDS] + [(11, 0.0), (11, 1.0)])
def test_corridor_is_one_closed_tube_8_to_15_cm_wide(seed, difficulty):
    w = made("corridor", seed, difficulty)
    assert w.walls and not (w.obstacles or w.unforeseen or w.moving)
    assert walls_apart([[*s.start, *s.end] for s in w.walls], 0.0099)  # it never touches itself
    widths = np.array(corridor_widths(w))
    width = widths.min()
    assert 0.08 - 1e-3 <= width <= 0.15 + 1e-3
    assert np.sum(widths < width + 2e-3) >= len(w.walls) - 2  # one width all along (the end caps aside)
    assert abs(w.difficulty.narrowest_passage_m - width) < 0.003
    heading = np.array([math.cos(w.start[2]), math.sin(w.start[2])])
    assert w.clearance(np.asarray(w.start[:2]) + 0.1 * heading) >= width / 2 - 2e-3  # it faces along it
    assert w.difficulty.turns >= 1


def test_corridors_never_touch_themselves():
    for seed in range(16):  # at level 1 most layouts drawn touch themselves and are drawn again
        w = generate("corridor", seed, 1.0)
        assert walls_apart([[*s.start, *s.end] for s in w.walls], 0.0099)
    assert made("corridor", 11, 0.0).difficulty.turns < made("corridor", 11, 1.0).difficulty.turns


def rays_hit(w, p, direction, length):
    pts = np.asarray(p) + np.linspace(0, length, 200)[:, None] * direction
    return any(np.any(distance(pts, s) == 0.0) for s in w.unforeseen)


@pytest.mark.parametrize("seed", SEEDS)
def test_traps_are_unforeseen_open_towards_the_robot_with_room_round(seed):
    w = made("traps", seed)
    assert w.unforeseen and not (w.walls or w.obstacles or w.moving) and 1 <= w.difficulty.traps <= 3
    assert reach(w, known_only=True).route_ratio == 1.0  # the planner's map is empty: it heads straight in
    start, goal = np.asarray(w.start[:2]), np.asarray(w.goal)
    u = (goal - start) / np.hypot(*(goal - start))
    assert abs(math.atan2(u[1], u[0]) - w.start[2]) < 0.2  # the robot faces the traps
    line = start + np.linspace(0, 1, 2000)[:, None] * (goal - start)
    blocked = np.any([distance(line, s) == 0.0 for s in w.unforeseen], axis=0)
    assert blocked.any()
    hit = line[np.argmax(blocked)]
    inside = hit - 0.03 * u  # just before the first contact: arms on both sides, the way back open
    n = np.array([-u[1], u[0]])
    assert rays_hit(w, inside, n, 0.2) and rays_hit(w, inside, -n, 0.2) and not rays_hit(w, inside, -u, 0.1)
    boxes = [s for s in w.unforeseen if isinstance(s, Box)]
    gaps = [shape_gap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:]]
    assert all(g < 2 * R for g in gaps if g < 0.1)  # a box-made trap's gaps are too narrow for the robot
    assert all(isinstance(s, (Box, Polygon)) for s in w.unforeseen)
    side = 1 if abs(u[0]) > abs(u[1]) else 0  # the arena's axis across the way to the goal
    for s in w.unforeseen:  # room to pass round on both sides: >= 12 cm to the border's surface
        lo, hi = bounds(s)[side], bounds(s)[side + 2]
        assert lo - w.wall_thickness / 2 >= 0.12 and w.size[side] - w.wall_thickness / 2 - hi >= 0.12


def test_traps_of_every_kind_with_room_round_them():
    kinds, box_gaps = set(), []
    for seed in range(16):
        w = generate("traps", seed)
        u = np.subtract(w.goal, w.start[:2])
        side = 1 if abs(u[0]) > abs(u[1]) else 0
        for s in w.unforeseen:
            lo, hi = bounds(s)[side], bounds(s)[side + 2]
            assert lo - w.wall_thickness / 2 >= 0.12 and w.size[side] - w.wall_thickness / 2 - hi >= 0.12
            kinds.add({8: "U", 6: "V"}[len(s.points)] if isinstance(s, Polygon) else "boxes")
        boxes = [s for s in w.unforeseen if isinstance(s, Box)]
        box_gaps += [g for i, a in enumerate(boxes) for b in boxes[i + 1:] if (g := shape_gap(a, b)) < 0.1]
    assert kinds == {"U", "V", "boxes"} and box_gaps and max(box_gaps) < 2 * R


@pytest.mark.parametrize("seed", SEEDS + (11,))
def test_clutter_is_unforeseen_and_its_gaps_8_cm_or_closed(seed):
    w = made("clutter", seed) if seed != 11 else made("clutter", 11, 1.0)
    assert w.unforeseen and not (w.walls or w.obstacles or w.moving)
    assert all(isinstance(s, (Box, Circle)) for s in w.unforeseen)
    gaps = [shape_gap(a, b) for i, a in enumerate(w.unforeseen) for b in w.unforeseen[i + 1:]]
    assert all(g <= 1e-9 or g >= 0.08 - 1e-3 for g in gaps)
    edge = min(float(w.clearance(np.asarray(p), known_only=True))
               for s in w.unforeseen for p in (s.vertices() if isinstance(s, Box) else [s.center]))
    assert edge >= 0.08 - 1e-3 - max((s.radius for s in w.unforeseen if isinstance(s, Circle)), default=0)
    assert w.difficulty.narrowest_passage_m >= 0.08 - 2e-3


def test_clutter_turns_some_boxes_and_grows_with_the_difficulty():
    boxes = [s for seed in SEEDS for s in made("clutter", seed).unforeseen if isinstance(s, Box)]
    assert any(0.0 < s.angle % (math.pi / 2) for s in boxes)
    assert len(made("clutter", 11, 1.0).unforeseen) > 2 * len(made("clutter", 11, 0.0).unforeseen)

    def covered(w):  # the shapes' areas (overlaps counted twice) over the arena's
        area = sum(s.size[0] * s.size[1] if isinstance(s, Box) else math.pi * s.radius ** 2 for s in w.unforeseen)
        return area / (w.size[0] * w.size[1])

    assert 0.03 < covered(made("clutter", 11, 0.0)) < 0.06 and 0.17 < covered(made("clutter", 11, 1.0)) < 0.3


def doors(w, centres=False):
    """Gaps (between surfaces) in lines of collinear wall segments (a maze's doors), or their centres."""
    lines = {}
    for a, b in wall_lines(w):
        axis = 0 if abs(a[0] - b[0]) < 1e-9 else 1 if abs(a[1] - b[1]) < 1e-9 else None
        if axis is None:
            continue
        key = (axis, round(a[axis], 6))
        lo, hi = sorted((a[1 - axis], b[1 - axis]))
        lines.setdefault(key, []).append((lo, hi))
    gaps = []
    for (axis, at), spans in lines.items():
        spans.sort()
        reach_ = spans[0][1]
        for lo, hi in spans[1:]:
            if lo > reach_ + 1e-9:
                middle = [(lo + reach_) / 2] * 2
                middle[axis] = at
                gaps.append(middle if centres else lo - reach_ - w.wall_thickness)
            reach_ = max(reach_, hi)
    return gaps


def door_centres(w):
    return doors(w, centres=True)


@pytest.mark.parametrize("seed", SEEDS + (11,))
def test_maze_doors_are_8_to_12_cm(seed):
    w = made("maze", seed) if seed != 11 else made("maze", 11, 1.0)
    assert w.walls and not (w.obstacles or w.unforeseen or w.moving)
    gaps = doors(w)
    assert len(gaps) >= 3 and all(0.08 - 1e-3 <= g <= 0.12 + 1e-3 for g in gaps), gaps
    assert 0.08 - 2e-3 <= w.difficulty.narrowest_passage_m <= 0.12 + 2e-3


def half_walls(w):
    """Wall segments no other wall segment is collinear with: a maze's stubs into its rooms."""
    def line(s):
        vertical = s.start[0] == s.end[0]
        return vertical, s.start[0] if vertical else s.start[1]

    lines = collections.Counter(line(s) for s in w.walls)
    return [s for s in w.walls if lines[line(s)] == 1]


def test_maze_grows_from_2x2_to_4x4_rooms_with_half_walls():
    easy, hard = made("maze", 11, 0.0), made("maze", 11, 1.0)
    assert len(doors(easy)) in (3, 4) and len(doors(hard)) == 15  # spanning trees, loops only when easy
    room = hard.size[0] / 4
    stubs = half_walls(hard)
    assert len(stubs) >= 3 and hard.size[0] == hard.size[1]
    for s in stubs:
        assert 0.3 * room - 1e-3 <= math.dist(s.start, s.end) <= 0.5 * room + 1e-3
    assert hard.difficulty.route_ratio > easy.difficulty.route_ratio


@pytest.mark.parametrize("seed", SEEDS + (11,))
def test_movers_cross_the_route_and_never_close_it_for_good(seed):
    w = made("movers", seed) if seed != 11 else made("movers", 11, 1.0)
    assert w.walls and 1 <= len(w.moving) <= 3
    route = reach(w).route
    for m in w.moving:
        size = m.shape.radius if isinstance(m.shape, Circle) else 0.5 * math.hypot(*m.shape.size)
        assert 0.02 - 1e-4 <= size <= 0.04 + 1e-4
        p = m.path
        assert p.bounce and 0.02 - 1e-4 <= p.speed_mps <= 0.06 + 1e-4
        assert route_passes(route, Segment(p.start, p.end), within=size + 0.09)  # it sweeps the route's way
        at_door = min(float(distance(np.asarray(c), Segment(p.start, p.end))) for c in door_centres(w)) \
            <= w.wall_thickness / 2 + size + 0.05 + 1e-3  # shuttling just in front of a doorway
        mid = np.add(p.start, p.end) / 2
        in_corridor = w.clearance(mid, include_moving=False) <= size + 0.01 + 1e-3  # along a corridor's wall
        assert at_door or in_corridor
        alone = dataclasses.replace(w, moving=(m,))
        ends = (0.0, math.dist(p.start, p.end) / p.speed_mps)  # at "from", at "to"
        assert any(reach(alone, movers_at=t).solvable for t in ends)  # open at one end of its sweep at least


@pytest.mark.parametrize("seed", SEEDS + (11,))
def test_blocked_closes_the_known_shortest_route_and_leaves_another(seed):
    w = made("blocked", seed) if seed != 11 else made("blocked", 11, 1.0)
    assert w.walls and 1 <= len(w.unforeseen) <= 2 and all(isinstance(s, Box) for s in w.unforeseen)
    known = reach(w, known_only=True)
    assert known.solvable and any(route_passes(known.route, s) for s in w.unforeseen)
    assert reach(w).solvable and reach(w).route_length_m > known.route_length_m


def test_blocked_sometimes_closes_two_doors():
    assert any(len(made("blocked", s, 1.0).unforeseen) == 2 for s in range(8))


# ------------------------------------------------------------------------------------------------ spellings

def test_spellings():
    assert parse_spelling("maze:7") == ("maze", 7, None)
    assert parse_spelling("maze:7:0.6") == ("maze", 7, 0.6)
    assert parse_spelling("three-rooms") is None and parse_spelling("lab.json") is None
    assert parse_spelling("nofamily:7") is None
    for bad, message in (("maze:x", "seed must be a whole number"), ("maze:-1", "seed must be a whole number"),
                         ("maze:7:1.5", "difficulty must be a number in [0, 1]"), ("maze:7:", "difficulty")):
        with pytest.raises(InputError, match=message.replace("[", r"\[")):
            parse_spelling(bad)
    with pytest.raises(InputError, match="maze:7:nan: the difficulty"):
        load_world("maze:7:nan")
