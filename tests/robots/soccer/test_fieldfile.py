"""Soccer field files (robots.soccer.fieldfile): the shipped field is the defaults, a field survives a round trip,
and every check refuses a bad file in one line naming the file and the key."""

import json

import numpy as np
import pytest

from ekm.errors import InputError
from robots.soccer.ball import BallParams
from robots.soccer.field import Field
from robots.soccer.fieldfile import (SoccerField, field_document, load_field, named_fields, parse_field,
                                     save_field)
from robots.soccer.game import kickoff_poses
from robots.worldnames import load_world, named_worlds


def write(tmp_path, doc, name="pitch.json"):
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return path


def refusal(path) -> str:
    with pytest.raises(InputError) as err:
        load_field(path)
    message = str(err.value)
    assert "\n" not in message
    return message


def test_the_shipped_field_is_the_defaults():
    f = load_field("lci-cup")
    assert named_fields() == ["lci-cup"] and f == SoccerField()
    assert f.name == "lci-cup" and f.field == Field() and f.ball == BallParams() and f.rule == "centre"
    np.testing.assert_allclose(f.kickoff, kickoff_poses(Field()), rtol=0, atol=1e-12)
    assert f.kickoff == ((0.3, 0.4, 0.0), (0.9, 0.4, np.pi))  # x and y rounded: 0.9, not 0.8999999999999999


def test_the_shipped_field_is_no_navigation_world_and_a_world_reader_refuses_it(tmp_path):
    assert "lci-cup" not in named_worlds() and all("soccer" not in w for w in named_worlds())
    path = write(tmp_path, {"soccer": {}})
    with pytest.raises(InputError) as err:
        load_world(path)
    assert str(err.value) == f"{path}: is a soccer field, not a world: use ekm match --field {path}"


def test_only_soccer_is_required_and_the_name_defaults_to_the_file_s(tmp_path):
    f = load_field(write(tmp_path, {"soccer": {}}, "my-pitch.json"))
    assert f == SoccerField(name="my-pitch") and f.source == str(tmp_path / "my-pitch.json")


def test_a_field_survives_a_round_trip_through_its_file(tmp_path):
    mine = SoccerField(name="long", field=Field(length=2.0, width=1.0, goal_mouth=0.3, goal_depth=0.08,
                                                wall_thickness=0.02),
                       ball=BallParams(radius=0.03, mass=0.01, restitution=0.5, rolling_friction=0.0),
                       kickoff=((0.4, 0.3, 0.5), (1.6, 0.7, -2.0)), rule="sahota")
    path = save_field(mine, tmp_path / "long.json")
    assert load_field(path) == mine and parse_field(field_document(mine)) == mine
    assert json.loads(path.read_text()) == mine.to_dict()
    assert [p.name for p in tmp_path.iterdir()] == ["long.json"]  # no temporary file left behind
    default = load_field(save_field(SoccerField(), tmp_path / "copy.json"))
    assert default == SoccerField() and default.kickoff == SoccerField().kickoff


def test_save_field_refuses_a_path_it_cannot_write_and_leaves_nothing(tmp_path):
    with pytest.raises(InputError, match="no directory"):
        save_field(SoccerField(), tmp_path / "missing" / "f.json")
    with pytest.raises(InputError, match="is a directory"):
        save_field(SoccerField(), tmp_path)
    assert list(tmp_path.iterdir()) == []


MOUTH = {"soccer": {"goal_mouth": 0.8}}


@pytest.mark.parametrize("doc, message", [
    # unknown keys and missing ones
    ({"soccer": {}, "colour": "green"}, "colour: unknown key (allowed: soccer, name, wall_thickness, ball, kickoff, rule)"),
    ({"soccer": {"corners": 4}}, "soccer.corners: unknown key (allowed: length, width, goal_mouth, goal_depth)"),
    ({"soccer": {}, "ball": {"spin": 1}}, "ball.spin: unknown key (allowed: radius, mass, restitution, rolling_friction)"),
    ({"name": "no-soccer"}, "soccer: missing"),
    # types
    ([], "must be an object, got list"),
    ({"soccer": [1.2, 0.8]}, "soccer: must be an object, got list"),
    ({"soccer": {"length": "1.2"}}, 'soccer.length: must be a number, got "1.2"'),
    ({"soccer": {"width": True}}, "soccer.width: must be a number, got true"),
    ({"soccer": {}, "name": 7}, "name: must be a non-empty string, got 7"),
    ({"soccer": {}, "kickoff": {"0": [0.3, 0.4, 0]}}, "kickoff: must be a list, got dict"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4], [0.9, 0.4, 3.14]]}, "kickoff[0]: must be [x, y, θ] (m, m, rad"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4, 0.0]]}, "kickoff: must be two poses [[x, y, θ], [x, y, θ]] (side 0's first), got 1"),
    ({"soccer": {}, "rule": 1}, "rule: must be a non-empty string, got 1"),
    # positive sizes
    ({"soccer": {"length": -1.2}}, "soccer.length: must be > 0, got -1.2"),
    ({"soccer": {"goal_depth": 0}}, "soccer.goal_depth: must be > 0, got 0"),
    ({"soccer": {}, "wall_thickness": -0.01}, "wall_thickness: must be >= 0, got -0.01"),
    ({"soccer": {}, "ball": {"radius": 0}}, "ball.radius: must be > 0, got 0"),
    ({"soccer": {}, "ball": {"mass": -1}}, "ball.mass: must be > 0, got -1"),
    ({"soccer": {}, "ball": {"rolling_friction": -0.1}}, "ball.rolling_friction: must be >= 0, got -0.1"),
    ({"soccer": {}, "ball": {"restitution": 1.5}}, "ball.restitution: must be in [0, 1] (outgoing over incoming speed at a wall), got 1.5"),
    # the mouth, the ball in the goal
    (MOUTH, "soccer.goal_mouth: must be narrower than the field's width 0.8 m, got 0.8"),
    ({"soccer": {}, "ball": {"radius": 0.06}}, "ball.radius: a ball of radius 0.06 m does not fit a goal 0.24 m wide and 0.06 m deep"),
    ({"soccer": {"goal_mouth": 0.1}, "ball": {"radius": 0.05}}, "ball.radius: a ball of radius 0.05 m does not fit a goal 0.1 m wide"),
    # the kick-off poses
    ({"soccer": {}, "kickoff": [[0.01, 0.4, 0.0], [0.9, 0.4, 3.14]]},
     "kickoff[0]: the robot (radius 0.025 m) at [0.01, 0.4] is not wholly on the playing surface [0, 1.2] x [0, 0.8]"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4, 0.0], [0.9, 0.79, 3.14]]},
     "kickoff[1]: the robot (radius 0.025 m) at [0.9, 0.79] is not wholly on the playing surface"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4, 0.0], [1.3, 0.4, 3.14]]},
     "kickoff[1]: the robot (radius 0.025 m) at [1.3, 0.4] is not wholly on the playing surface"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4, 0.0], [0.34, 0.4, 3.14]]},
     "kickoff[1]: the robot at [0.34, 0.4] overlaps side 0's at [0.3, 0.4] (centres 0.040 m apart, need >= 0.05 m)"),
    ({"soccer": {}, "kickoff": [[0.3, 0.4, 0.0], [0.6, 0.44, 3.14]]},
     "kickoff[1]: the robot at [0.6, 0.44] overlaps the ball on the centre spot [0.6, 0.4] (centres 0.040 m apart, "
     "need >= 0.045 m)"),
    # the rule
    ({"soccer": {}, "rule": "golden-goal"}, 'rule: must be one of centre, sahota, got "golden-goal"'),
])
def test_every_check_names_the_file_and_the_key(tmp_path, doc, message):
    path = write(tmp_path, doc)
    assert refusal(path).startswith(f"{path}: {message}")


@pytest.mark.parametrize("text, message", [
    ('{"soccer": {"width": Infinity}}', "soccer.width: must be finite, got inf"),
    ('{"soccer": {}, "kickoff": [[0.3, 0.4, NaN], [0.9, 0.4, 3.14]]}', "kickoff[0][2]: must be finite, got nan"),
    ('{"soccer": {}, "ball": {"mass": -Infinity}}', "ball.mass: must be finite, got -inf"),
    ('{"soccer": {"length": 1.2,}}', "not valid JSON (Expecting property name enclosed in double quotes at line 1 "
                                     "column 27)"),
    ('{"soccer": {}, "rule": "centre", "rule": "sahota"}', "rule: given twice (JSON would silently keep the last)"),
])
def test_numbers_must_be_finite_and_the_file_valid_json(tmp_path, text, message):
    path = write(tmp_path, text)
    assert refusal(path) == f"{path}: {message}"


def test_a_missing_file_or_unknown_name_is_one_line(tmp_path):
    assert refusal(tmp_path / "nowhere.json") == (f"{tmp_path / 'nowhere.json'}: no such field file or named field "
                                                  f"(named fields: lci-cup)")
    assert refusal("lci-cop").startswith("lci-cop: no such field file or named field")


def test_a_field_made_in_python_is_checked_as_a_file_is():
    with pytest.raises(InputError, match=r"^SoccerField: kickoff\[0\]: the robot at \[0.6, 0.4\] overlaps the ball"):
        SoccerField(kickoff=((0.6, 0.4, 0.0), (0.9, 0.4, 0.0)))
    with pytest.raises(InputError, match=r"^SoccerField: rule: must be one of centre, sahota"):
        SoccerField(rule="offside")
    with pytest.raises(InputError, match=r"^SoccerField: kickoff: must be two poses"):
        SoccerField(kickoff=((0.3, 0.4, 0.0),))
    with pytest.raises(InputError, match=r"^SoccerField: ball.radius: a ball of radius 0.1 m does not fit"):
        SoccerField(ball=BallParams(radius=0.1))
