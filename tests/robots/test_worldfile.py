"""World files (robots.worldfile): every kind of bad file is refused with one line naming the key; the
``difficulty`` key; world_document round trips; and world files generated and mutated by hypothesis, each
loaded or refused with the package's own one-line error."""

import copy
import json
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ekm.errors import InputError
from robots.worldfile import World, parse_world, world_document, world_json
from robots.worldnames import load_world
from tests.fuzzing import FUZZ, assert_loads_or_refuses

GOOD = {
    "name": "lab", "size": [1.2, 0.6],
    "walls": [[0.4, 0.0, 0.4, 0.24]],
    "obstacles": [{"type": "box", "center": [0.2, 0.1], "size": [0.05, 0.05]}],
    "unforeseen": [{"type": "circle", "center": [0.6, 0.25], "radius": 0.04}],
    "moving": [{"shape": {"type": "circle", "radius": 0.025},
                "path": {"type": "circle", "center": [0.6, 0.3], "radius": 0.08, "period_s": 20}}],
    "events": [{"at_s": 3.0, "add": [{"type": "segment", "from": [0.8, 0.0], "to": [0.8, 0.2]}]}],
    "start": [0.1, 0.3, 0.0], "goal": [1.1, 0.3],
}


def with_(**changes):
    doc = json.loads(json.dumps(GOOD))
    doc.update(changes)
    return doc


def write(tmp_path, doc_or_text, name="lab.json"):
    path = tmp_path / name
    path.write_text(doc_or_text if isinstance(doc_or_text, str) else json.dumps(doc_or_text))
    return path


def test_the_example_world_is_good_and_counted():
    world = parse_world(GOOD, "lab.json")
    assert world.counts() == {"name": "lab", "size": [1.2, 0.6], "walls": 1, "obstacles": 1, "unforeseen": 1,
                              "moving": 1, "moving_goal": False}


U_POINTS = [[0.45, 0.255], [0.77, 0.255], [0.77, 0.545], [0.45, 0.545],
            [0.45, 0.525], [0.75, 0.525], [0.75, 0.275], [0.45, 0.275]]

BAD = {
    "unknown key": (with_(colour="red"), "lab.json: colour: unknown key"),
    "unknown nested key": (with_(obstacles=[{"type": "circle", "center": [0.2, 0.1], "radius": 0.02, "r": 1}]),
                           "obstacles[0].r: unknown key"),
    "wrong type": (with_(size="big"), "size: must be [width, height] (m), got \"big\""),
    "bool as number": (with_(goal=[True, 0.3]), "goal[0]: must be a number"),
    "missing key": ({k: v for k, v in GOOD.items() if k != "start"}, "start: missing"),
    "unknown shape": (with_(unforeseen=[{"type": "star", "center": [0.6, 0.25]}]),
                      "unforeseen[0].type: must be one of box, circle, polygon, segment"),
    "negative radius": (with_(unforeseen=[{"type": "circle", "center": [0.6, 0.25], "radius": -0.04}]),
                        "unforeseen[0].radius: must be > 0"),
    "shape outside the arena": (with_(unforeseen=[{"type": "circle", "center": [1.19, 0.3], "radius": 0.05}]),
                                "unforeseen[0]: lies outside the 1.2 x 0.6 m arena"),
    "wall outside the arena": (with_(walls=[[0.4, 0.0, 0.4, 0.7]]), "walls[0]: lies outside"),
    "mover leaves the arena": (with_(moving=[{"shape": {"type": "circle", "radius": 0.025}, "path": {
        "type": "line", "from": [0.6, 0.3], "to": [1.3, 0.3], "speed_mps": 0.1}}]), "moving[0]: lies outside"),
    "start inside an obstacle": (with_(start=[0.2, 0.1, 0.0]), "start: the robot (radius 0.025 m) at [0.2, 0.1]"),
    "start touching a wall": (with_(start=[0.39, 0.1, 0.0]), "start: the robot"),
    "goal inside an obstacle": (with_(goal=[0.6, 0.25]), "goal: [0.6, 0.25] lies inside a wall or obstacle"),
    "non-simple polygon": (with_(unforeseen=[{"type": "polygon", "points": [[0.5, 0.1], [0.7, 0.3], [0.7, 0.1],
                                                                           [0.5, 0.3]]}]),
                           "unforeseen[0].points: not a simple polygon: edge 0 (points 0-1) meets edge 2"),
    "bad direction": (with_(goal={"path": {"type": "circle", "center": [0.9, 0.3], "radius": 0.1, "period_s": 5,
                                           "direction": "left"}}), "goal.path.direction: must be one of ccw, cw"),
}


@pytest.mark.parametrize("doc, message", BAD.values(), ids=BAD.keys())
def test_bad_worlds_are_refused_naming_the_key(tmp_path, doc, message):
    with pytest.raises(InputError) as err:
        load_world(write(tmp_path, doc))
    text = str(err.value)
    assert message in text
    assert text.startswith(str(tmp_path / "lab.json") + ": ")
    assert "\n" not in text


@pytest.mark.parametrize("literal, message", [("NaN", "must be finite, got nan"), ("1e999", "must be finite, got inf"),
                                              ("-Infinity", "must be finite, got -inf")])
def test_non_finite_numbers_are_refused(tmp_path, literal, message):
    text = json.dumps(GOOD).replace('"goal": [1.1, 0.3]', f'"goal": [1.1, {literal}]')
    with pytest.raises(InputError, match=f"goal\\[1\\]: {message}"):
        load_world(write(tmp_path, text))


def test_bad_json_is_refused_with_its_position(tmp_path):
    with pytest.raises(InputError, match=r"lab.json: not valid JSON \(Expecting .* at line 1 column \d+\)"):
        load_world(write(tmp_path, '{"name": "lab", "size": [1, 1],'))


def test_a_key_given_twice_is_refused(tmp_path):
    text = json.dumps(GOOD).replace('"goal": [1.1, 0.3]', '"goal": [1.1, 0.3], "goal": [0.2, 0.1]')
    with pytest.raises(InputError, match="lab.json: goal: given twice"):
        load_world(write(tmp_path, text))


def test_a_missing_file_is_refused_listing_the_named_worlds(tmp_path):
    with pytest.raises(InputError, match=r"nope.json: no such world file or named world \(named worlds: .*three-rooms"):
        load_world(tmp_path / "nope.json")


def test_a_concave_polygon_is_fine():
    world = parse_world(with_(unforeseen=[{"type": "polygon", "points": U_POINTS}], goal=[1.1, 0.1]))
    assert len(world.unforeseen[0].points) == 8


# ---------------------------------------------------------------------- the difficulty key, world documents

GOOD_DIFFICULTY = {"family": "maze", "seed": 3, "level": 0.5, "narrowest_passage_m": 0.09, "route_length_m": 1.2,
                   "straight_m": 0.8, "route_ratio": 1.5, "turns": 2, "traps": 0, "movers": 0}
BASE = {"name": "lab", "size": [1.0, 0.6], "start": [0.2, 0.3, 0.0], "goal": [0.8, 0.3]}


def test_a_difficulty_is_read_and_is_only_a_label():
    w = parse_world({**BASE, "difficulty": GOOD_DIFFICULTY})
    assert w.difficulty.to_dict() == GOOD_DIFFICULTY and w.counts()["family"] == "maze"
    plain = parse_world(BASE)
    assert w == plain and hash(w) == hash(plain) and "family" not in plain.counts()
    assert world_document(w)["difficulty"] == GOOD_DIFFICULTY


BAD_DIFFICULTY = {
    "unknown key": ({**GOOD_DIFFICULTY, "colour": 1}, "difficulty.colour: unknown key"),
    "missing key": ({k: v for k, v in GOOD_DIFFICULTY.items() if k != "turns"}, "difficulty.turns: missing"),
    "not an object": ([1, 2], "difficulty: must be an object, got list"),
    "seed a string": ({**GOOD_DIFFICULTY, "seed": "3"}, 'difficulty.seed: must be a whole number, got "3"'),
    "seed a fraction": ({**GOOD_DIFFICULTY, "seed": 3.5}, "difficulty.seed: must be a whole number, got 3.5"),
    "negative seed": ({**GOOD_DIFFICULTY, "seed": -1}, "difficulty.seed: must be >= 0, got -1"),
    "level above 1": ({**GOOD_DIFFICULTY, "level": 1.5}, "difficulty.level: must be in [0, 1], got 1.5"),
    "level a bool": ({**GOOD_DIFFICULTY, "level": True}, "difficulty.level: must be a number, got true"),
    "zero route": ({**GOOD_DIFFICULTY, "route_length_m": 0}, "difficulty.route_length_m: must be > 0, got 0"),
    "ratio below 1": ({**GOOD_DIFFICULTY, "route_ratio": 0.9}, "difficulty.route_ratio: must be >= 1, got 0.9"),
    "empty family": ({**GOOD_DIFFICULTY, "family": ""}, 'difficulty.family: must be a non-empty string, got ""'),
    "negative turns": ({**GOOD_DIFFICULTY, "turns": -2}, "difficulty.turns: must be >= 0, got -2"),
}


@pytest.mark.parametrize("difficulty, message", BAD_DIFFICULTY.values(), ids=BAD_DIFFICULTY.keys())
def test_a_bad_difficulty_is_refused_naming_the_key(difficulty, message):
    with pytest.raises(InputError) as err:
        parse_world({**BASE, "difficulty": difficulty}, "lab.json")
    assert str(err.value).startswith(f"lab.json: {message}") and "\n" not in str(err.value)


def test_world_document_round_trips_the_named_worlds():
    from robots.worldnames import named_worlds

    for name in named_worlds():
        w = load_world(name)
        assert parse_world(json.loads(world_json(w))) == w


# -------------------------------------------------------------------------------------------------- fuzzing

# Every input either loads into a valid world or raises InputError — no other exception, and no warning
# that would reach a user's terminal (tests/fuzzing.py).

BASE_WORLD = json.loads(json.dumps({
    "name": "fuzz", "size": [1.2, 0.6], "wall_thickness": 0.01,
    "walls": [[0.4, 0.0, 0.4, 0.24], [0.4, 0.36, 0.4, 0.6]],
    "obstacles": [{"type": "box", "center": [0.2, 0.1], "size": [0.05, 0.05], "angle": 0.3},
                  {"type": "polygon", "points": [[0.6, 0.1], [0.7, 0.1], [0.65, 0.2]]}],
    "unforeseen": [{"type": "circle", "center": [0.9, 0.3], "radius": 0.04},
                   {"type": "segment", "from": [1.0, 0.5], "to": [1.1, 0.5]}],
    "moving": [{"shape": {"type": "circle", "radius": 0.025},
                "path": {"type": "circle", "center": [0.6, 0.4], "radius": 0.08, "period_s": 12, "direction": "cw"}},
               {"shape": {"type": "box", "size": [0.03, 0.03]},
                "path": {"type": "line", "from": [0.5, 0.05], "to": [0.7, 0.05], "speed_mps": 0.05, "bounce": False}}],
    "events": [{"at_s": 5.0, "add": [{"type": "box", "center": [0.8, 0.16], "size": [0.02, 0.12]}], "known": True}],
    "start": [0.1, 0.3, 0.0],
    "goal": [1.1, 0.42],
}))

NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30),
                    st.sampled_from([0, -0.0, 1e-300, -1e-300, 1e300, 5e-324, 0.025, -0.025, 1.2, 0.6]))
JSON_VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), NUMBERS, st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=6), inner, max_size=4)),
    max_leaves=12)


def paths_in(doc, prefix=()):
    """Every (path, value) inside a JSON document."""
    yield prefix, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from paths_in(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths_in(v, prefix + (i,))


ALL_PATHS = [p for p, _ in paths_in(BASE_WORLD) if p]


@st.composite
def mutated_worlds(draw):
    """The base world with a few of its values replaced, keys deleted or added, lists emptied or extended."""
    doc = copy.deepcopy(BASE_WORLD)
    for _ in range(draw(st.integers(1, 4))):
        path = draw(st.sampled_from(ALL_PATHS))
        parent = doc
        try:
            for k in path[:-1]:
                parent = parent[k]
            key = path[-1]
            action = draw(st.sampled_from(["replace", "replace", "number", "delete", "extra", "empty"]))
            if action == "replace":
                parent[key] = draw(JSON_VALUES)
            elif action == "number":
                parent[key] = draw(NUMBERS)
            elif action == "delete":
                del parent[key]
            elif action == "extra" and isinstance(parent, dict):
                parent[draw(st.text(min_size=1, max_size=6))] = draw(JSON_VALUES)
            elif action == "empty":
                parent[key] = [] if isinstance(parent[key], list) else {}
        except (KeyError, IndexError, TypeError):
            pass  # an earlier mutation removed the path: nothing to do
    return doc


def polygons():
    """Random polygons: self-intersecting, degenerate, repeated points, huge, tiny, outside the arena."""
    point = st.tuples(st.floats(-1.0, 2.0, allow_nan=False), st.floats(-1.0, 2.0, allow_nan=False))
    return st.lists(point, min_size=0, max_size=9).map(lambda pts: {"type": "polygon", "points": [list(p) for p in pts]})


def check_world(world):
    assert isinstance(world, World)
    numbers = [*world.size, *world.start]
    assert all(math.isfinite(v) for v in numbers) and world.size[0] > 0 and world.size[1] > 0
    assert world.clearance(np.asarray(world.start[:2]), 0.0) >= 0.025 - 1e-9  # the robot fits at its start


@FUZZ
@given(mutated_worlds())
def test_mutated_world_files_load_or_are_refused_with_one_line(doc):
    world = assert_loads_or_refuses(lambda: parse_world(doc, "fuzz.json"))
    if world is not None:
        check_world(world)


@FUZZ
@given(st.lists(polygons(), min_size=1, max_size=3), st.tuples(st.floats(0.0, 3.0), st.floats(0.0, 3.0)))
def test_random_polygons_and_arenas_load_or_are_refused(shapes, size):
    doc = {"name": "poly", "size": list(size), "unforeseen": shapes, "start": [0.1, 0.1, 0.0], "goal": [0.2, 0.2]}
    world = assert_loads_or_refuses(lambda: parse_world(doc, "poly.json"))
    if world is not None:
        check_world(world)


@FUZZ
@given(st.binary(max_size=200) | st.text(max_size=200).map(str.encode))
def test_arbitrary_bytes_as_a_world_file_are_refused_with_one_line(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("w") / "world.json"
    path.write_bytes(data)
    assert_loads_or_refuses(lambda: load_world(path))
