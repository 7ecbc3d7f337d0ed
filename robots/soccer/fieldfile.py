"""Soccer field files: the pitch, the ball, the kick-off poses and the rule as one JSON object, checked key by key.

A field file is written like a world file (:mod:`robots.worldfile`: metres and radians, origin at the bottom-left
corner of the playing surface, x along the field, y across) and read with the same checks::

    {"name": "lci-cup",
     "soccer": {"length": 1.2, "width": 0.8, "goal_mouth": 0.24, "goal_depth": 0.06},
     "wall_thickness": 0.01,
     "ball": {"radius": 0.02, "mass": 0.0027, "restitution": 0.7, "rolling_friction": 0.15},
     "kickoff": [[0.3, 0.4, 0.0], [0.9, 0.4, 3.141592653589793]],
     "rule": "centre"}

Only ``soccer`` is required (it is what makes the file a soccer field); every other key, and every key of
``soccer`` and ``ball``, has the default of :class:`robots.soccer.field.Field`, :class:`robots.soccer.ball.BallParams`,
:func:`robots.soccer.game.kickoff_poses` (x and y rounded to 12 decimals) and rule ``"centre"``
(:data:`robots.soccer.referee.RULES`). A missing ``name`` is the file's name without ``.json``.

``kickoff`` is side 0's pose first (side 0 defends x = 0). Each kick-off pose must put the whole robot (radius
``KHEPERA.radius``) on the playing surface ``[0, length] × [0, width]`` — clear of every wall and out of the goal
mouths —, the two robots must not overlap, and neither may overlap the ball on the centre spot. The ball must fit into a goal (radius <
``goal_depth``, diameter < ``goal_mouth``), the mouth must be narrower than the field, sizes must be > 0
(``wall_thickness`` >= 0), ``restitution`` in [0, 1], ``rolling_friction`` >= 0 and every number finite.

Every problem raises :class:`ekm.errors.InputError` with one line naming the file and the key, e.g.
``my-pitch.json: soccer.goal_mouth: must be narrower than the field's width 0.8 m, got 0.9``.

Named fields ship in the package ``robots.worlds.soccer`` (a folder of their own, so the named *worlds* of
:func:`robots.worldnames.named_worlds` do not list them): ``lci-cup``, the defaults.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from dataclasses import field as _f
from importlib import resources
from pathlib import Path

from ekm.errors import InputError
from robots.params import KHEPERA
from robots.soccer.ball import BallParams
from robots.soccer.field import Field
from robots.soccer.referee import RULES
from robots.worldfile import _Checker, _join, decode, read_text

__all__ = ["SoccerField", "field_document", "field_json", "load_field", "named_fields", "parse_field", "save_field"]

_TOP_REQUIRED = ("soccer",)
_TOP_OPTIONAL = ("name", "wall_thickness", "ball", "kickoff", "rule")
_SOCCER_KEYS = ("length", "width", "goal_mouth", "goal_depth")
_BALL_KEYS = ("radius", "mass", "restitution", "rolling_friction")
_POSE = "[x, y, θ] (m, m, rad: the heading, 0 = along +x)"
_NAMED = "robots.worlds.soccer"  # the package that holds the named fields


def default_kickoff(field: Field) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """:func:`robots.soccer.game.kickoff_poses` of ``field`` as plain tuples, x and y rounded to 12 decimals (so a
    field file holds 0.9, not 0.8999999999999999)."""
    from robots.soccer.game import kickoff_poses

    return tuple((round(float(p[0]), 12), round(float(p[1]), 12), float(p[2])) for p in kickoff_poses(field))


@dataclass(frozen=True)
class SoccerField:
    """A checked soccer field (module docstring): the pitch (``field``), the ``ball``, the two ``kickoff`` poses
    ``((x, y, θ) of side 0, (x, y, θ) of side 1)`` and the restart ``rule``. ``kickoff`` None means the default
    poses of ``field`` (:func:`default_kickoff`). ``source``: the file or named field it was read from ("" for one
    made in Python); it takes no part in ``==``. ``SoccerField()`` is the named field ``lci-cup``.

    Building one checks what a field file's reader checks (the ball fits a goal, the kick-off poses are clear of
    the walls, of each other and of the ball, the rule is known) and raises :class:`ekm.errors.InputError`
    naming the key, ``SoccerField: kickoff[0]: …``.
    """

    name: str = "lci-cup"
    field: Field = Field()
    ball: BallParams = BallParams()
    kickoff: tuple | None = None
    rule: str = "centre"
    source: str = _f(default="", compare=False)

    def __post_init__(self):
        def fail(key: str, msg: str):
            raise InputError(f"SoccerField: {key}: {msg}")

        if not isinstance(self.name, str) or not self.name:
            fail("name", f"must be a non-empty string, got {self.name!r}")
        if not isinstance(self.field, Field):
            fail("field", f"must be a robots.soccer.field.Field, got {type(self.field).__name__}")
        if not isinstance(self.ball, BallParams):
            fail("ball", f"must be a robots.soccer.ball.BallParams, got {type(self.ball).__name__}")
        kickoff = default_kickoff(self.field) if self.kickoff is None else _poses(self.kickoff, fail)
        object.__setattr__(self, "kickoff", kickoff)
        check(self.field, self.ball, kickoff, self.rule, fail)

    def to_dict(self) -> dict:
        """The field file's JSON object (:func:`field_document`)."""
        return field_document(self)


def _poses(value, fail) -> tuple:
    """Two finite ``(x, y, θ)`` poses as tuples of floats, or ``fail``."""
    try:
        poses = [tuple(float(v) for v in p) for p in value]
    except (TypeError, ValueError):
        fail("kickoff", f"must be two poses {_POSE}, got {value!r}")
    if len(poses) != 2:
        fail("kickoff", f"must be two poses (side 0's first), got {len(poses)}")
    for i, p in enumerate(poses):
        if len(p) != 3:
            fail(f"kickoff[{i}]", f"must be {_POSE}, got {list(p)}")
        if not all(math.isfinite(v) for v in p):
            fail(f"kickoff[{i}]", f"must be finite, got {list(p)}")
    return tuple(poses)


def check(field: Field, ball: BallParams, kickoff, rule, fail, robot=KHEPERA) -> None:
    """The checks that relate one key to another (module docstring), each reported by ``fail(key, message)``."""
    if rule not in RULES:
        fail("rule", f"must be one of {', '.join(RULES)}, got {json.dumps(rule)}")
    if ball.radius >= field.goal_depth or 2.0 * ball.radius >= field.goal_mouth:
        fail("ball.radius", f"a ball of radius {ball.radius} m does not fit a goal {field.goal_mouth} m wide and "
                            f"{field.goal_depth} m deep (needs radius < goal_depth and diameter < goal_mouth)")
    r = robot.radius
    spot = field.centre_spot
    for i, (x, y, _) in enumerate(kickoff):
        if not (r <= x <= field.length - r and r <= y <= field.width - r):
            fail(f"kickoff[{i}]", f"the robot (radius {r} m) at [{x:g}, {y:g}] is not wholly on the playing surface "
                                  f"[0, {field.length:g}] x [0, {field.width:g}]: its centre must be at least {r} m "
                                  f"from every edge (the walls, and the goal mouths)")
        apart = math.dist((x, y), spot)
        if apart < r + ball.radius:
            fail(f"kickoff[{i}]", f"the robot at [{x:g}, {y:g}] overlaps the ball on the centre spot "
                                  f"[{spot[0]:g}, {spot[1]:g}] (centres {apart:.3f} m apart, need >= "
                                  f"{r + ball.radius:g} m)")
    (x0, y0, _), (x1, y1, _) = kickoff
    apart = math.dist((x0, y0), (x1, y1))
    if apart < 2.0 * r:
        fail("kickoff[1]", f"the robot at [{x1:g}, {y1:g}] overlaps side 0's at [{x0:g}, {y0:g}] (centres "
                           f"{apart:.3f} m apart, need >= {2.0 * r:g} m)")


# ---------------------------------------------------------------------------------------------- reading

def parse_field(doc, source: str = "<field>", name: str | None = None) -> SoccerField:
    """Build a :class:`SoccerField` from a decoded JSON document, checking every key (module docstring);
    ``name``: the name to give a document without one (default: ``source``)."""
    ck = _Checker(source)
    ck.obj(doc, "", _TOP_REQUIRED, _TOP_OPTIONAL)
    name = ck.string(doc["name"], "name") if "name" in doc else (name or source)
    soccer = ck.obj(doc["soccer"], "soccer", (), _SOCCER_KEYS)
    default_field, default_ball = Field(), BallParams()
    sizes = {k: ck.number(soccer.get(k, getattr(default_field, k)), _join("soccer", k), positive=True)
             for k in _SOCCER_KEYS}
    thickness = ck.number(doc.get("wall_thickness", default_field.wall_thickness), "wall_thickness", nonneg=True)
    if sizes["goal_mouth"] >= sizes["width"]:
        ck.fail("soccer.goal_mouth", f"must be narrower than the field's width {sizes['width']:g} m, "
                                     f"got {sizes['goal_mouth']:g}")
    field = Field(**sizes, wall_thickness=thickness)
    given = ck.obj(doc.get("ball", {}), "ball", (), _BALL_KEYS)
    values = {k: given.get(k, getattr(default_ball, k)) for k in _BALL_KEYS}
    ball_values = {"radius": ck.number(values["radius"], "ball.radius", positive=True),
                   "mass": ck.number(values["mass"], "ball.mass", positive=True),
                   "restitution": ck.number(values["restitution"], "ball.restitution", nonneg=True),
                   "rolling_friction": ck.number(values["rolling_friction"], "ball.rolling_friction", nonneg=True)}
    if ball_values["restitution"] > 1.0:
        ck.fail("ball.restitution", f"must be in [0, 1] (outgoing over incoming speed at a wall), "
                                    f"got {values['restitution']}")
    ball = BallParams(**ball_values)
    if "kickoff" in doc:
        poses = ck.list(doc["kickoff"], "kickoff")
        if len(poses) != 2:
            ck.fail("kickoff", f"must be two poses [[x, y, θ], [x, y, θ]] (side 0's first), got {len(poses)}")
        kickoff = tuple(ck.vector(p, f"kickoff[{i}]", 3, _POSE) for i, p in enumerate(poses))
    else:
        kickoff = default_kickoff(field)
    rule = ck.string(doc.get("rule", "centre"), "rule", RULES)
    check(field, ball, kickoff, rule, ck.fail)
    return SoccerField(name=name, field=field, ball=ball, kickoff=kickoff, rule=rule, source=source)


def named_fields() -> list[str]:
    """Names of the fields shipped with the package, sorted."""
    return sorted(f.name[:-5] for f in resources.files(_NAMED).iterdir() if f.name.endswith(".json"))


def load_field(name_or_path) -> SoccerField:
    """Load a named field (:func:`named_fields`: ``lci-cup``) or a field file, checking every key; a
    :class:`SoccerField` is returned as it is. Every problem — no such file, not JSON, a key given twice, any
    check of the module docstring — raises :class:`ekm.errors.InputError` in one line naming the file."""
    if isinstance(name_or_path, SoccerField):
        return name_or_path
    text_source = str(name_or_path)
    path = Path(name_or_path)
    if path.suffix != ".json" and not path.exists() and text_source in named_fields():
        text = resources.files(_NAMED).joinpath(f"{text_source}.json").read_text()
    else:
        if not path.is_file():
            raise InputError(f"{text_source}: no such field file or named field (named fields: "
                             f"{', '.join(named_fields())})")
        text = read_text(path, text_source, "field")
    doc = decode(text, text_source)
    stem = path.name[:-5] if path.name.endswith(".json") else path.name
    return parse_field(doc, text_source, name=stem)


# ---------------------------------------------------------------------------------------------- writing

def field_document(soccer_field: SoccerField) -> dict:
    """``soccer_field`` as a field file's JSON object, every key written; the inverse of :func:`parse_field`
    (``parse_field(field_document(f)) == f``)."""
    f, b = soccer_field.field, soccer_field.ball
    return {"name": soccer_field.name,
            "soccer": {k: getattr(f, k) for k in _SOCCER_KEYS},
            "wall_thickness": f.wall_thickness,
            "ball": {k: getattr(b, k) for k in _BALL_KEYS},
            "kickoff": [list(p) for p in soccer_field.kickoff],
            "rule": soccer_field.rule}


def field_json(soccer_field: SoccerField) -> str:
    """:func:`field_document` as JSON text, one key a line (as the shipped field is laid out)."""
    lines = [f"  {json.dumps(k)}: {json.dumps(v)}" for k, v in field_document(soccer_field).items()]
    return "{\n" + ",\n".join(lines) + "\n}\n"


def save_field(soccer_field: SoccerField, path) -> Path:
    """Write ``soccer_field`` to the field file ``path`` (:func:`field_json`), atomically; returns the path. A
    path that cannot be written raises :class:`ekm.errors.InputError` and leaves nothing behind."""
    from ekm.files import atomic_write

    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a directory, expected a .json field file")
    if not path.parent.is_dir():
        raise InputError(f"{path}: cannot write the field file (no directory {path.parent})")
    try:
        with atomic_write(path) as tmp:
            tmp.write_text(field_json(soccer_field))
    except OSError as exc:
        raise InputError(f"{path}: cannot write the field file ({exc.strerror or exc})") from None
    return path
