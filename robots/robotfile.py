"""Robot files: a robot as data (docs/design.md §2, §10), checked key by key like a world file, and the named robots.

A robot file is a JSON object in metres, seconds and radians holding the fields of
:class:`~robots.params.RobotParams`::

    {"name": "worn-wheel",
     "about": "the Khepera with its left wheel 10 % smaller",
     "radius": 0.025, "wheel_base": 0.053, "wheel_gain": [0.9, 1.0],
     "max_wheel_speed": 0.16, "speed_unit": 0.008, "motor_tau": 0.02,
     "actuator_noise": 0.1, "noise_period": 0.032,
     "target_period": 1.024, "avoid_period": 0.128, "dt": 0.016,
     "short_range": {"angles": [1.4835, ...], "range_m": 0.05, "resolution_m": 0.005, "noise": 0.1},
     "long_range": {"angles": [0.0, 0.5236, ...], "range_m": 0.175, "resolution_m": 0.005, "noise": 0.1}}

Only ``name`` is required; a key left out takes the Khepera's value (:data:`robots.params.KHEPERA`), so a
file may say only how its robot differs. ``ekm robots --show khepera`` prints every key, a template to edit.
Sensor ``angles`` are the directions of the IR sensors in the robot's frame (rad, 0 = ahead, + = left).

Every problem raises :class:`ekm.errors.InputError` with one line naming the file and the key, e.g.
``my-robot.json: wheel_base: must be > 0, got -0.05``.
"""

from __future__ import annotations

import functools
import json
import math
import re
from dataclasses import fields, replace
from importlib import resources
from pathlib import Path

from ekm.errors import InputError
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.registry import Registry
from robots.worldfile import _Checker as Checker
from robots.worldfile import decode, read_text

_SENSOR_KEYS = ("angles", "range_m", "resolution_m", "noise")
_NUMBERS = ("radius", "wheel_base", "max_wheel_speed", "speed_unit", "motor_tau", "actuator_noise", "noise_period",
            "target_period", "avoid_period", "dt")
_KEYS = ("name", "about", "radius", "wheel_base", "wheel_gain", "max_wheel_speed", "speed_unit", "motor_tau",
         "actuator_noise", "noise_period", "target_period", "avoid_period", "dt", "short_range", "long_range")
assert set(_KEYS) == {f.name for f in fields(RobotParams)}, "a robot file holds every field of RobotParams"
_NAME = re.compile(r"[a-z0-9][a-z0-9_.-]*")


def parse_robot(doc, source: str = "<robot>") -> RobotParams:
    """A :class:`RobotParams` from a decoded robot-file document, every key checked (see the module docstring)."""
    ck = Checker(source)
    ck.obj(doc, "", ("name",), _KEYS[1:])
    name = ck.string(doc["name"], "name")
    if not _NAME.fullmatch(name):
        ck.fail("name", f"a robot's name is lower-case letters, digits, '-', '_' and '.', got {json.dumps(name)}")
    values: dict = {"name": name}
    if "about" in doc:
        values["about"] = ck.string(doc["about"], "about")
    for key in _NUMBERS:
        if key in doc:
            values[key] = ck.number(doc[key], key, nonneg=key in ("speed_unit", "actuator_noise"),
                                    positive=key not in ("speed_unit", "actuator_noise"))
    if "wheel_gain" in doc:
        values["wheel_gain"] = ck.vector(doc["wheel_gain"], "wheel_gain", 2, "[left, right] (a wheel's speed over "
                                         "its motor's: 1 = as commanded)", positive=True)
    for key in ("short_range", "long_range"):
        if key in doc:
            values[key] = _sensors(ck, doc[key], key)
    robot = replace(KHEPERA, **values)
    _check_robot(ck, robot)
    return robot


def _sensors(ck: Checker, value, key: str) -> SensorSet:
    v = ck.obj(value, key, ("angles", "range_m"), ("resolution_m", "noise"))
    angles = ck.list(v["angles"], f"{key}.angles")
    if not angles:
        ck.fail(f"{key}.angles", "needs at least one sensor direction (rad)")
    phis = tuple(ck.number(a, f"{key}.angles[{i}]") for i, a in enumerate(angles))
    for i, phi in enumerate(phis):
        if not -math.pi <= phi <= math.pi:
            ck.fail(f"{key}.angles[{i}]", f"must be in [-pi, pi] (rad, 0 = ahead, + = left), got {phi}")
    default = getattr(KHEPERA, key)
    return SensorSet(angles=phis, range_m=ck.number(v["range_m"], f"{key}.range_m", positive=True),
                     resolution_m=ck.number(v.get("resolution_m", default.resolution_m), f"{key}.resolution_m",
                                            nonneg=True),
                     noise=ck.number(v.get("noise", default.noise), f"{key}.noise", nonneg=True))


def _check_robot(ck: Checker, robot: RobotParams) -> None:
    """What no single key shows: the clock's periods fit together, and the noise and speed unit make sense."""
    if robot.actuator_noise >= 1.0:
        ck.fail("actuator_noise", f"must be < 1 (a wheel slipping by 100 % could turn backwards), got "
                                  f"{robot.actuator_noise}")
    if robot.speed_unit >= robot.max_wheel_speed:
        ck.fail("speed_unit", f"must be below max_wheel_speed ({robot.max_wheel_speed} m/s), got {robot.speed_unit}")
    for key in ("noise_period", "avoid_period", "target_period"):
        try:
            robot.substeps(getattr(robot, key))
        except ValueError:
            ck.fail(key, f"must be a whole number of dt ({robot.dt} s) sub-steps, got {getattr(robot, key)}")
    for key in ("avoid_period", "target_period"):
        try:
            robot.noise_shape(getattr(robot, key))
        except ValueError:
            ck.fail(key, f"must be a whole number of noise periods ({robot.noise_period} s), got "
                         f"{getattr(robot, key)}")
    if robot.substeps(robot.target_period) % robot.substeps(robot.avoid_period):
        ck.fail("target_period", f"must be a whole number of avoid periods ({robot.avoid_period} s: the runner's "
                                 f"tick), got {robot.target_period}")


def robot_document(robot: RobotParams) -> dict:
    """``robot`` as a robot-file document, every key given (:func:`parse_robot` reads it back equal)."""
    d = robot.to_dict()
    d["wheel_gain"] = list(robot.wheel_gain)
    for key in ("short_range", "long_range"):
        d[key]["angles"] = list(d[key]["angles"])
    return {k: d[k] for k in _KEYS}


def robot_json(robot: RobotParams) -> str:
    """The robot file of ``robot``: one key a line, sensor sets on one line each."""
    doc = robot_document(robot)
    lines = [f"  {json.dumps(k)}: {json.dumps(v)}" for k, v in doc.items()]
    return "{\n" + ",\n".join(lines) + "\n}\n"


@functools.lru_cache(maxsize=16)
def robot_from_json(text: str | None) -> RobotParams:
    """The robot of a robot file's text (:func:`robot_json`; what a job carries to its worker), None for the
    Khepera — read once per process."""
    return KHEPERA if text is None else parse_robot(json.loads(text), "job robot")


def _shipped() -> list[RobotParams]:
    """The robots shipped with the package (``robots/models/*.json``), the Khepera first, then by name."""
    files = resources.files("robots.models").iterdir()
    names = sorted(f.name[:-5] for f in files if f.name.endswith(".json"))
    return [parse_robot(decode(resources.files("robots.models").joinpath(f"{n}.json").read_text(), f"{n}.json"),
                        f"{n}.json") for n in sorted(names, key=lambda n: n != KHEPERA.name)]


def _check_registered(robot: RobotParams) -> None:
    """A robot added in Python or by an installed package is checked key by key as a robot file is."""
    parse_robot(robot_document(robot), f"robot {robot.name}")


#: The named robots (:mod:`robots.registry`): the package's own, then those of installed packages (entry-point
#: group ``ekm.robots``, each naming a :class:`RobotParams`), then those added with ``ekm.register_robot``.
ROBOTS = Registry("robot", "robots", RobotParams, _shipped, _check_registered)


def named_robots() -> list[str]:
    """Names of the named robots (:data:`ROBOTS`), the Khepera first."""
    return ROBOTS.names()


def load_robot(robot) -> RobotParams:
    """A robot: a :class:`RobotParams` as it is, None for the Khepera, a named robot (``ekm robots``) or a robot
    file, every key checked."""
    if robot is None:
        return KHEPERA
    if isinstance(robot, RobotParams):
        return robot
    source = str(robot)
    path = Path(source)
    if path.suffix != ".json" and not path.exists() and source in ROBOTS:
        return ROBOTS[source]
    if path.is_file():
        text = read_text(path, source, "robot")
    else:
        from robots.spelling import did_you_mean

        raise InputError(f"{source}: no such robot file or named robot{did_you_mean(source, named_robots())} "
                         f"(named robots: {', '.join(named_robots())})")
    return parse_robot(decode(text, source), source)


def save_robot(robot: RobotParams, path) -> Path:
    """Write ``robot``'s file to ``path`` atomically; returns the path."""
    from ekm.files import atomic_write

    path = Path(path)
    with atomic_write(path) as tmp:
        Path(tmp).write_text(robot_json(robot))
    return path


def describe(robot: RobotParams) -> str:
    """A one-line summary of how ``robot`` moves and senses, for listings."""
    gain = "" if not robot.gained else f", wheel gain {robot.wheel_gain[0]:g}/{robot.wheel_gain[1]:g}"
    return (f"radius {1000 * robot.radius:g} mm, wheel base {1000 * robot.wheel_base:g} mm, "
            f"{robot.max_wheel_speed:g} m/s{gain}, slip {100 * robot.actuator_noise:g} %")
