"""World files (robots.worldfile): every kind of bad file is refused with one line naming the key; and
the polygon check added for the physics (robots.geometry.polygon_self_intersection)."""

import json

import pytest

from ekm.errors import InputError
from robots.geometry import polygon_self_intersection
from robots.worldfile import load_world, parse_world

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
    "wrong type": (with_(size="big"), "size: must be a list of 2 numbers"),
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


@pytest.mark.parametrize("points, crossing", [
    ([(0, 0), (1, 0), (1, 1), (0, 1)], None),
    ([tuple(p) for p in U_POINTS], None),
    ([(0, 0), (1, 1), (1, 0), (0, 1)], (0, 2)),  # bow tie
    ([(0, 0), (2, 0), (1, 0), (1, 1)], (0, 1)),  # spike folding back along itself
    ([(0, 0), (1, 0), (1, 1), (1, 1), (0, 1)], (1, 3)),  # repeated point
    ([(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)], (0, 2)),  # a vertex touching another edge
], ids=["square", "U", "bow-tie", "spike", "repeated-point", "touching"])
def test_polygon_self_intersection(points, crossing):
    assert polygon_self_intersection(points) == crossing
