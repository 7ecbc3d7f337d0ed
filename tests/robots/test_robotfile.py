"""Robot files: the named robots, a file read back equal, every fault one line naming the key, ``ekm robots``."""

import json
from dataclasses import replace

import pytest

from ekm.cli import main
from ekm.errors import InputError
from robots.params import KHEPERA
from robots.robotfile import load_robot, named_robots, parse_robot, robot_json


def test_the_named_robots_are_the_issue_s_and_the_khepera_is_the_package_s_own():
    assert set(named_robots()) >= {"khepera", "worn-wheel", "weak-motor", "wide-base", "slippery", "e-puck"}
    assert named_robots()[0] == "khepera"
    assert load_robot("khepera") == KHEPERA  # bit for bit: every result made with KHEPERA stands
    assert load_robot("worn-wheel").wheel_gain == (0.9, 1.0)
    assert load_robot("weak-motor").wheel_gain == (1.0, 0.8)
    assert load_robot("wide-base").wheel_base == pytest.approx(1.2 * 0.053)
    assert load_robot("slippery").actuator_noise == 0.2
    epuck = load_robot("e-puck")  # e-puck.org: 70 mm across, wheels 53 mm apart, 1000 steps/s = 12.8 cm/s
    assert (epuck.radius, epuck.wheel_base, epuck.max_wheel_speed) == (0.035, 0.053, 0.128)


def test_a_robot_file_reads_back_equal_and_a_partial_one_takes_the_khepera_s_values(tmp_path):
    robot = replace(KHEPERA, name="mine", wheel_gain=(0.95, 1.05), motor_tau=0.05)
    path = tmp_path / "mine.json"
    path.write_text(robot_json(robot))
    assert load_robot(str(path)) == robot
    assert parse_robot({"name": "lean", "radius": 0.02}) == replace(KHEPERA, name="lean", radius=0.02)
    assert load_robot(None) is KHEPERA and load_robot(robot) is robot


def test_the_fingerprint_follows_the_physics_not_the_name():
    assert replace(KHEPERA, name="other", about="x").fingerprint == KHEPERA.fingerprint
    assert load_robot("worn-wheel").fingerprint != KHEPERA.fingerprint


@pytest.mark.parametrize("doc, message", [
    ({"name": "r", "wheel_base": -0.05}, "r.json: wheel_base: must be > 0, got -0.05"),
    ({"name": "r", "wheel_gain": [0.9]}, "r.json: wheel_gain: must be [left, right]"),
    ({"name": "r", "wheel_gain": [0.9, 0]}, "r.json: wheel_gain[1]: must be > 0, got 0"),
    ({"name": "r", "wheels": 2}, "r.json: wheels: unknown key"),
    ({"radius": 0.02}, "r.json: name: missing"),
    ({"name": "R 2"}, "r.json: name: a robot's name is lower-case"),
    ({"name": "r", "actuator_noise": 1.5}, "r.json: actuator_noise: must be < 1"),
    ({"name": "r", "avoid_period": 0.1}, "r.json: avoid_period: must be a whole number of dt"),
    ({"name": "r", "target_period": 1.28 + 0.032}, "r.json: target_period: must be a whole number of avoid periods"),
    ({"name": "r", "long_range": {"angles": [], "range_m": 0.1}}, "r.json: long_range.angles: needs at least one"),
    ({"name": "r", "short_range": {"angles": [4.0], "range_m": 0.1}}, "r.json: short_range.angles[0]: must be in"),
    ({"name": "r", "radius": True}, "r.json: radius: must be a number, got true"),
])
def test_every_fault_is_one_line_naming_the_file_and_the_key(doc, message):
    with pytest.raises(InputError) as err:
        parse_robot(doc, "r.json")
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


def test_ekm_robots_lists_shows_and_checks(capsys, tmp_path):
    assert main(["robots"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("khepera") and "worn-wheel" in out and "wheel gain 0.9/1" in out
    assert main(["robots", "--show", "weak-motor"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["name"] == "weak-motor" and shown["wheel_gain"] == [1.0, 0.8]
    assert set(shown) >= {"radius", "wheel_base", "max_wheel_speed", "motor_tau", "actuator_noise", "short_range"}
    assert main(["robots", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)["robots"]
    assert [r["name"] for r in listed][:1] == ["khepera"] and all(len(r["fingerprint"]) == 12 for r in listed)


def test_a_robot_file_with_a_negative_wheel_base_is_refused_in_one_line_with_status_2(capsys, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"name": "bad", "wheel_base": -0.053}')
    assert main(["robots", "--check", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"error: {bad}: wheel_base: must be > 0, got -0.053"
    assert main(["run", "--world", "open-arena", "--architecture", "fields", "--robot", str(bad)]) == 2
    assert capsys.readouterr().err.strip() == f"error: {bad}: wheel_base: must be > 0, got -0.053"
    assert main(["run", "--world", "open-arena", "--architecture", "fields", "--robot", "no-such-robot"]) == 2
    assert "no such robot file or named robot" in capsys.readouterr().err
