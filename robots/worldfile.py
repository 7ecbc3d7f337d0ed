"""World files: the JSON format of docs/design.md §2, checked key by key, and the named worlds.

A world is a JSON object in metres and radians, origin bottom-left, x right, y up::

    {"name": "three-rooms", "size": [1.2, 0.5],
     "walls": [[x0, y0, x1, y1], ...],             # on the planner's a-priori map
     "obstacles": [shape, ...],                    # known obstacles (on the map)
     "unforeseen": [shape, ...],                   # only in the world
     "moving": [{"shape": shape, "path": path}, ...],
     "events": [{"at_s": 30.0, "add": [shape, ...], "known": true}, ...],
     "start": [x, y, theta], "goal": [x, y] | {"path": path},
     "wall_thickness": 0.01,
     "difficulty": {...}}                           # optional: written by the generator

Shapes: ``{"type": "box", "center": [x, y], "size": [w, h], "angle": a}``, ``{"type": "circle",
"center": [x, y], "radius": r}``, ``{"type": "polygon", "points": [[x, y], ...]}``,
``{"type": "segment", "from": [x, y], "to": [x, y]}``. A moving shape is given around its own origin
(``center`` defaults to ``[0, 0]``); its path places it. Paths: ``{"type": "circle", "center": [x, y],
"radius": r, "period_s": T, "direction": "ccw" | "cw"}`` (optional ``phase`` in rad, where on the circle
it starts) and ``{"type": "line", "from": [x, y], "to": [x, y], "speed_mps": v, "bounce": true}`` (with
``bounce`` false the mover stops at ``to``). Events add shapes at ``at_s``; ``known`` (default true) says
whether the planner is told and may replan.

``difficulty`` describes a generated world (``robots.generator``; ``ekm worlds --generate``): ``family``
(string), ``seed`` (int >= 0) and ``level`` (in [0, 1]) say how it was made; ``narrowest_passage_m``,
``route_length_m``, ``straight_m`` (> 0), ``route_ratio`` (>= 1), ``turns``, ``traps`` and ``movers``
(int >= 0) are its measures (``robots.generator.reach`` defines them). Nothing else reads them: they label
the world for benchmarks and do not change it.

Every problem raises :class:`ekm.errors.InputError` with one line naming the file and the key, e.g.
``lab.json: obstacles[1].radius: must be > 0, got -0.02``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ekm.errors import InputError
from robots.geometry import (Box, Circle, Point, Polygon, Segment, Shape, bounds, distance, polygon_self_intersection,
                             signed_area, translate)
from robots.params import KHEPERA


@dataclass(frozen=True)
class CirclePath:
    """Uniform motion on a circle; ``direction`` 'ccw' or 'cw'; starts at angle ``phase`` (rad)."""

    center: Point
    radius: float
    period_s: float
    direction: str = "ccw"
    phase: float = 0.0

    def position(self, t: float) -> Point:
        sign = 1.0 if self.direction == "ccw" else -1.0
        a = self.phase + sign * 2.0 * math.pi * t / self.period_s
        return (self.center[0] + self.radius * math.cos(a), self.center[1] + self.radius * math.sin(a))

    def velocity(self, t: float) -> Point:
        sign = 1.0 if self.direction == "ccw" else -1.0
        w = sign * 2.0 * math.pi / self.period_s
        a = self.phase + w * t
        return (-self.radius * w * math.sin(a), self.radius * w * math.cos(a))

    def extent(self) -> tuple[float, float, float, float]:
        (x, y), r = self.center, self.radius
        return (x - r, y - r, x + r, y + r)


@dataclass(frozen=True)
class LinePath:
    """Motion from ``start`` to ``end`` at ``speed_mps``; back and forth if ``bounce``, else it stops at ``end``."""

    start: Point
    end: Point
    speed_mps: float
    bounce: bool = True

    def _s(self, t: float) -> tuple[float, float]:
        """Fraction along the line and direction of travel (+1 towards ``end``, -1 back, 0 stopped)."""
        length = math.dist(self.start, self.end)
        if length == 0.0:
            return 0.0, 0.0
        travelled = self.speed_mps * t / length
        if not self.bounce:
            return min(travelled, 1.0), (1.0 if travelled < 1.0 else 0.0)
        phase = travelled % 2.0
        return (phase, 1.0) if phase <= 1.0 else (2.0 - phase, -1.0)

    def position(self, t: float) -> Point:
        s, _ = self._s(t)
        return (self.start[0] + s * (self.end[0] - self.start[0]), self.start[1] + s * (self.end[1] - self.start[1]))

    def velocity(self, t: float) -> Point:
        _, sign = self._s(t)
        length = math.dist(self.start, self.end)
        if sign == 0.0:
            return (0.0, 0.0)
        k = sign * self.speed_mps / length
        return (k * (self.end[0] - self.start[0]), k * (self.end[1] - self.start[1]))

    def extent(self) -> tuple[float, float, float, float]:
        return (min(self.start[0], self.end[0]), min(self.start[1], self.end[1]),
                max(self.start[0], self.end[0]), max(self.start[1], self.end[1]))


Path_ = CirclePath | LinePath


@dataclass(frozen=True)
class Moving:
    """A moving obstacle: ``shape`` around its own origin, carried along ``path``."""

    shape: Shape
    path: Path_

    def at(self, t: float) -> Shape:
        """The obstacle's shape in world coordinates at time ``t``."""
        return translate(self.shape, self.path.position(t))


@dataclass(frozen=True)
class Event:
    """At ``at_s`` seconds the shapes ``add`` appear; ``known``: the planner is told (and may replan)."""

    at_s: float
    add: tuple[Shape, ...]
    known: bool = True


@dataclass(frozen=True)
class Difficulty:
    """How a generated world was made and how hard it is (the world file's ``difficulty``; lengths in m).

    ``family``, ``seed`` and ``level`` (0 easy .. 1 hard) regenerate it; the rest are the measures of
    :func:`robots.generator.reach.reach`: the narrowest gap the best route passes, the length of the
    shortest route, the start-to-goal distance and their ratio, the route's turns, and the traps and
    moving obstacles the generator placed.
    """

    family: str
    seed: int
    level: float
    narrowest_passage_m: float
    route_length_m: float
    straight_m: float
    route_ratio: float
    turns: int
    traps: int
    movers: int

    def to_dict(self) -> dict:
        """The world file's ``difficulty`` object."""
        return {f: getattr(self, f) for f in DIFFICULTY_KEYS}


#: The keys of a world file's ``difficulty`` object, in the order they are written.
DIFFICULTY_KEYS = ("family", "seed", "level", "narrowest_passage_m", "route_length_m", "straight_m", "route_ratio",
                   "turns", "traps", "movers")


@dataclass(frozen=True)
class World:
    """A validated world (docs/design.md §2). Build it with :func:`load_world` or :func:`parse_world`."""

    name: str
    size: Point
    start: tuple[float, float, float]
    goal: Point | Path_
    walls: tuple[Segment, ...] = ()
    obstacles: tuple[Shape, ...] = ()
    unforeseen: tuple[Shape, ...] = ()
    moving: tuple[Moving, ...] = ()
    events: tuple[Event, ...] = ()
    wall_thickness: float = 0.01
    source: str = field(default="", compare=False)
    #: Set for generated worlds; a label, so it takes no part in ``==`` and hashing (the planner caches on worlds).
    difficulty: Difficulty | None = field(default=None, compare=False)

    @property
    def border(self) -> tuple[Segment, ...]:
        """The arena's border as four wall segments."""
        w, h = self.size
        corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        return tuple(Segment(corners[i], corners[(i + 1) % 4]) for i in range(4))

    @property
    def moving_goal(self) -> bool:
        return not isinstance(self.goal, tuple)

    def goal_at(self, t: float = 0.0) -> Point:
        """Goal position at time ``t`` (a fixed point, or where the moving target is)."""
        return self.goal.position(t) if self.moving_goal else self.goal

    def known_shapes(self, t: float = 0.0) -> tuple[Shape, ...]:
        """What the planner's a-priori map holds at ``t``: walls, known obstacles and known events so far."""
        added = tuple(s for e in self.events if e.known and e.at_s <= t for s in e.add)
        return self.walls + self.obstacles + added

    def static_shapes(self, t: float = 0.0) -> tuple[Shape, ...]:
        """Every non-moving shape in the world at ``t`` (known, unforeseen and added by events)."""
        added = tuple(s for e in self.events if e.at_s <= t for s in e.add)
        return self.walls + self.obstacles + self.unforeseen + added

    def clearance(self, points, t: float = 0.0, include_moving: bool = True, known_only: bool = False) -> np.ndarray:
        """Distance from ``points`` ``(..., 2)`` to the nearest wall (border included) or obstacle at ``t``.

        Walls count with half their thickness. ``known_only``: only what the planner's map holds
        (:meth:`known_shapes`; no unforeseen or moving obstacles).
        """
        p = np.asarray(points, dtype=float)
        half = 0.5 * self.wall_thickness
        walls = self.border + self.walls
        d = np.min([distance(p, s) - half for s in walls], axis=0)
        shapes = self.known_shapes(t) if known_only else self.static_shapes(t)
        others = [s for s in shapes if s not in self.walls]
        if include_moving and not known_only:
            others += [m.at(t) for m in self.moving]
        for s in others:
            d = np.minimum(d, distance(p, s))
        return np.maximum(d, 0.0)

    def counts(self) -> dict:
        """The ``ekm worlds --json`` summary of this world (docs/design.md §6)."""
        counts = {"name": self.name, "size": list(self.size), "walls": len(self.walls),
                  "obstacles": len(self.obstacles), "unforeseen": len(self.unforeseen),
                  "moving": len(self.moving), "moving_goal": self.moving_goal}
        if self.difficulty is not None:
            counts["family"] = self.difficulty.family
        return counts


# ---------------------------------------------------------------------------------------------- parsing

class _Checker:
    """Reads one JSON document, raising InputError('<source>: <key path>: <problem>') on the first fault."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, msg: str):
        raise InputError(f"{self.source}: {key}: {msg}" if key else f"{self.source}: {msg}")

    def obj(self, value, key: str, required: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict:
        if not isinstance(value, dict):
            self.fail(key, f"must be an object, got {type(value).__name__}")
        for k in value:
            if k not in required and k not in optional:
                allowed = ", ".join(required + optional)
                self.fail(_join(key, k), f"unknown key (allowed: {allowed})")
        for k in required:
            if k not in value:
                self.fail(_join(key, k), "missing")
        return value

    def number(self, value, key: str, *, positive: bool = False, nonneg: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(key, f"must be a number, got {json.dumps(value)}")
        if not math.isfinite(value):
            self.fail(key, f"must be finite, got {value}")
        if positive and value <= 0:
            self.fail(key, f"must be > 0, got {value}")
        if nonneg and value < 0:
            self.fail(key, f"must be >= 0, got {value}")
        return float(value)

    def vector(self, value, key: str, n: int, form: str | None = None, **kw) -> tuple[float, ...]:
        """``n`` numbers; ``form`` says what they are (``"[x, y, θ] (m, m, rad)"``; default ``[x, y]`` in m)."""
        if not isinstance(value, list) or len(value) != n:
            form = form or ("[x, y] (m)" if n == 2 else f"a list of {n} numbers")
            self.fail(key, f"must be {form}, got {json.dumps(value)}")
        return tuple(self.number(v, f"{key}[{i}]", **kw) for i, v in enumerate(value))

    def integer(self, value, key: str) -> int:
        """A whole number >= 0 (JSON ``3``, not ``3.0``)."""
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(key, f"must be a whole number, got {json.dumps(value)}")
        if value < 0:
            self.fail(key, f"must be >= 0, got {value}")
        return value

    def list(self, value, key: str) -> list:
        if not isinstance(value, list):
            self.fail(key, f"must be a list, got {type(value).__name__}")
        return value

    def string(self, value, key: str, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str) or not value:
            self.fail(key, f"must be a non-empty string, got {json.dumps(value)}")
        if choices and value not in choices:
            self.fail(key, f"must be one of {', '.join(choices)}, got {json.dumps(value)}")
        return value

    def boolean(self, value, key: str) -> bool:
        if not isinstance(value, bool):
            self.fail(key, f"must be true or false, got {json.dumps(value)}")
        return value

    def typed(self, value, key: str, types: tuple[str, ...]) -> None:
        """A missing ``type`` names the types there are."""
        if isinstance(value, dict) and "type" not in value:
            self.fail(_join(key, "type"), f"missing (one of {', '.join(types)})")

    def shape(self, value, key: str, relative: bool = False) -> Shape:
        """A shape; ``relative`` shapes (carried by a path) may omit their centre."""
        self.typed(value, key, ("box", "circle", "polygon", "segment"))
        kind = self.string(self.obj(value, key, ("type",), _SHAPE_KEYS)["type"], _join(key, "type"),
                           ("box", "circle", "polygon", "segment"))
        center_req = () if relative else ("center",)
        if kind == "box":
            v = self.obj(value, key, ("type", "size") + center_req, ("center", "angle"))
            return Box(self.vector(v.get("center", [0, 0]), _join(key, "center"), 2),
                       self.vector(v["size"], _join(key, "size"), 2, "[width, height] (m)", positive=True),
                       self.number(v.get("angle", 0.0), _join(key, "angle")))
        if kind == "circle":
            v = self.obj(value, key, ("type", "radius") + center_req, ("center",))
            return Circle(self.vector(v.get("center", [0, 0]), _join(key, "center"), 2),
                          self.number(v["radius"], _join(key, "radius"), positive=True))
        if kind == "polygon":
            v = self.obj(value, key, ("type", "points"))
            pts = self.list(v["points"], _join(key, "points"))
            if len(pts) < 3:
                self.fail(_join(key, "points"), f"a polygon needs at least 3 points, got {len(pts)}")
            poly = tuple(self.vector(p, f"{_join(key, 'points')}[{i}]", 2) for i, p in enumerate(pts))
            crossing = polygon_self_intersection(poly)
            if crossing is not None:
                i, j = crossing
                self.fail(_join(key, "points"), f"not a simple polygon: edge {i} (points {i}-{(i + 1) % len(poly)}) "
                                                f"meets edge {j} (points {j}-{(j + 1) % len(poly)})")
            if abs(signed_area(poly)) < 1e-12:
                self.fail(_join(key, "points"), "polygon has zero area")
            return Polygon(poly)
        v = self.obj(value, key, ("type", "from", "to"))
        seg = Segment(self.vector(v["from"], _join(key, "from"), 2), self.vector(v["to"], _join(key, "to"), 2))
        if seg.start == seg.end:
            self.fail(key, "segment has zero length")
        return seg

    def path(self, value, key: str) -> Path_:
        self.typed(value, key, ("circle", "line"))
        kind = self.string(self.obj(value, key, ("type",), _PATH_KEYS)["type"], _join(key, "type"),
                           ("circle", "line"))
        if kind == "circle":
            v = self.obj(value, key, ("type", "center", "radius", "period_s"), ("direction", "phase"))
            return CirclePath(self.vector(v["center"], _join(key, "center"), 2),
                              self.number(v["radius"], _join(key, "radius"), positive=True),
                              self.number(v["period_s"], _join(key, "period_s"), positive=True),
                              self.string(v.get("direction", "ccw"), _join(key, "direction"), ("ccw", "cw")),
                              self.number(v.get("phase", 0.0), _join(key, "phase")))
        v = self.obj(value, key, ("type", "from", "to", "speed_mps"), ("bounce",))
        return LinePath(self.vector(v["from"], _join(key, "from"), 2),
                        self.vector(v["to"], _join(key, "to"), 2),
                        self.number(v["speed_mps"], _join(key, "speed_mps"), positive=True),
                        self.boolean(v.get("bounce", True), _join(key, "bounce")))

    def difficulty(self, value, key: str) -> Difficulty:
        v = self.obj(value, key, DIFFICULTY_KEYS)
        family = self.string(v["family"], _join(key, "family"))
        seed = self.integer(v["seed"], _join(key, "seed"))
        level = self.number(v["level"], _join(key, "level"))
        if not 0.0 <= level <= 1.0:
            self.fail(_join(key, "level"), f"must be in [0, 1], got {v['level']}")
        lengths = [self.number(v[k], _join(key, k), positive=True)
                   for k in ("narrowest_passage_m", "route_length_m", "straight_m")]
        ratio = self.number(v["route_ratio"], _join(key, "route_ratio"))
        if ratio < 1.0:
            self.fail(_join(key, "route_ratio"), f"must be >= 1, got {v['route_ratio']}")
        counts = [self.integer(v[k], _join(key, k)) for k in ("turns", "traps", "movers")]
        return Difficulty(family, seed, level, *lengths, ratio, *counts)


_SHAPE_KEYS = ("center", "size", "angle", "radius", "points", "from", "to")
_PATH_KEYS = ("center", "radius", "period_s", "direction", "phase", "from", "to", "speed_mps", "bounce")
_WORLD_REQUIRED = ("name", "size", "start", "goal")
_WORLD_OPTIONAL = ("walls", "obstacles", "unforeseen", "moving", "events", "wall_thickness", "difficulty")


def _join(key: str, sub: str) -> str:
    """The path of ``sub`` in ``key``; a key that is not printable (a newline in it) is quoted as JSON, so that
    the message stays one line."""
    sub = sub if sub.isprintable() else json.dumps(sub)
    return f"{key}.{sub}" if key else sub


def parse_world(doc, source: str = "<world>") -> World:
    """Build a :class:`World` from a decoded JSON document, checking every key (see module docstring)."""
    ck = _Checker(source)
    if isinstance(doc, dict) and "soccer" in doc:  # robots.soccer.fieldfile
        ck.fail("", f"is a soccer field, not a world: use ekm match --field {source}")
    ck.obj(doc, "", _WORLD_REQUIRED, _WORLD_OPTIONAL)
    name = ck.string(doc["name"], "name")
    size = ck.vector(doc["size"], "size", 2, "[width, height] (m)", positive=True)
    thickness = ck.number(doc.get("wall_thickness", 0.01), "wall_thickness", nonneg=True)
    walls = []
    for i, w in enumerate(ck.list(doc.get("walls", []), "walls")):
        x0, y0, x1, y1 = ck.vector(w, f"walls[{i}]", 4, "[x0, y0, x1, y1] (m): a segment from (x0, y0) to (x1, y1), "
                                                       "not a box; give a box as an obstacle")
        if (x0, y0) == (x1, y1):
            ck.fail(f"walls[{i}]", "wall has zero length")
        walls.append(Segment((x0, y0), (x1, y1)))
    obstacles = [ck.shape(s, f"obstacles[{i}]") for i, s in enumerate(ck.list(doc.get("obstacles", []), "obstacles"))]
    unforeseen = [ck.shape(s, f"unforeseen[{i}]") for i, s in enumerate(ck.list(doc.get("unforeseen", []), "unforeseen"))]
    moving = []
    for i, m in enumerate(ck.list(doc.get("moving", []), "moving")):
        key = f"moving[{i}]"
        ck.obj(m, key, ("shape", "path"))
        moving.append(Moving(ck.shape(m["shape"], f"{key}.shape", relative=True), ck.path(m["path"], f"{key}.path")))
    events = []
    for i, e in enumerate(ck.list(doc.get("events", []), "events")):
        key = f"events[{i}]"
        ck.obj(e, key, ("at_s", "add"), ("known",))
        add = tuple(ck.shape(s, f"{key}.add[{j}]") for j, s in enumerate(ck.list(e["add"], f"{key}.add")))
        events.append(Event(ck.number(e["at_s"], f"{key}.at_s", nonneg=True), add,
                            ck.boolean(e.get("known", True), f"{key}.known")))
    start = ck.vector(doc["start"], "start", 3, "[x, y, θ] (m, m, rad: the heading, 0 = along +x)")
    if isinstance(doc["goal"], dict):
        ck.obj(doc["goal"], "goal", ("path",))
        goal = ck.path(doc["goal"]["path"], "goal.path")
    else:
        goal = ck.vector(doc["goal"], "goal", 2, "[x, y] (m) or {\"path\": …} (a moving goal)")
    difficulty = ck.difficulty(doc["difficulty"], "difficulty") if "difficulty" in doc else None

    # Everything must lie inside the arena.
    w, h = size

    def inside(box, key):
        x0, y0, x1, y1 = box
        tol = 1e-9
        if x0 < -tol or y0 < -tol or x1 > w + tol or y1 > h + tol:
            ck.fail(key, f"lies outside the {w} x {h} m arena (spans x {x0:.3g}..{x1:.3g}, y {y0:.3g}..{y1:.3g})")

    for i, s in enumerate(walls):
        inside(bounds(s), f"walls[{i}]")
    for group, shapes in (("obstacles", obstacles), ("unforeseen", unforeseen)):
        for i, s in enumerate(shapes):
            inside(bounds(s), f"{group}[{i}]")
    for i, m in enumerate(moving):
        px0, py0, px1, py1 = m.path.extent()
        sx0, sy0, sx1, sy1 = bounds(m.shape)
        inside((px0 + sx0, py0 + sy0, px1 + sx1, py1 + sy1), f"moving[{i}]")
    for i, e in enumerate(events):
        for j, s in enumerate(e.add):
            inside(bounds(s), f"events[{i}].add[{j}]")
    inside((start[0], start[1], start[0], start[1]), "start")
    goal_extent = goal.extent() if isinstance(goal, (CirclePath, LinePath)) else (goal[0], goal[1], goal[0], goal[1])
    inside(goal_extent, "goal")

    world = World(name=name, size=size, start=start, goal=goal, walls=tuple(walls), obstacles=tuple(obstacles),
                  unforeseen=tuple(unforeseen), moving=tuple(moving), events=tuple(events),
                  wall_thickness=thickness, source=source, difficulty=difficulty)
    # The robot must fit at its start; a fixed goal must not lie inside an obstacle or a wall.
    clear = float(world.clearance(np.asarray(start[:2]), 0.0))
    if clear < KHEPERA.radius:
        ck.fail("start", f"the robot (radius {KHEPERA.radius} m) at {list(start[:2])} overlaps a wall or obstacle "
                         f"(clearance {clear:.3f} m)")
    if not world.moving_goal and float(world.clearance(np.asarray(goal), 0.0, include_moving=False)) <= 0.0:
        ck.fail("goal", f"{list(goal)} lies inside a wall or obstacle")
    return world


def read_text(path: Path, source: str, what: str) -> str:
    """The text of the ``what`` file (world, field) at ``path``; one that cannot be read is one
    :class:`InputError` line naming ``source``."""
    try:
        return path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{source}: cannot read {what} file ({exc.__class__.__name__}: {exc})") from None


def decode(text: str, source: str):
    """The JSON document of ``text``; not JSON, or an object with a key given twice, is one :class:`InputError`
    line naming ``source`` (JSON itself would silently keep the last of two keys)."""
    try:
        return json.loads(text, object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise InputError(f"{source}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except _DuplicateKey as exc:
        raise InputError(f"{source}: {exc.args[0]}: given twice (JSON would silently keep the last)") from None


class _DuplicateKey(ValueError):
    pass


def _unique_keys(pairs) -> dict:
    """``json.loads`` hook: an object with a repeated key is an error, not a silent overwrite."""
    doc = {}
    for key, value in pairs:
        if key in doc:
            raise _DuplicateKey(key)
        doc[key] = value
    return doc


# ---------------------------------------------------------------------------------------------- writing

def world_document(world: World) -> dict:
    """``world`` as a world-file document (the JSON object of the module docstring).

    The inverse of :func:`parse_world`: ``parse_world(world_document(w)) == w``, the difficulty included.
    Optional keys that are empty are left out; numbers are written as they are held.
    """
    doc = {"name": world.name, "size": list(world.size)}
    if world.walls:
        doc["walls"] = [[*s.start, *s.end] for s in world.walls]
    if world.obstacles:
        doc["obstacles"] = [shape_document(s) for s in world.obstacles]
    if world.unforeseen:
        doc["unforeseen"] = [shape_document(s) for s in world.unforeseen]
    if world.moving:
        doc["moving"] = [{"shape": shape_document(m.shape), "path": _path_document(m.path)} for m in world.moving]
    if world.events:
        doc["events"] = [{"at_s": e.at_s, "add": [shape_document(s) for s in e.add], "known": e.known}
                         for e in world.events]
    doc["start"] = list(world.start)
    doc["goal"] = {"path": _path_document(world.goal)} if world.moving_goal else list(world.goal)
    doc["wall_thickness"] = world.wall_thickness
    if world.difficulty is not None:
        doc["difficulty"] = world.difficulty.to_dict()
    return doc


def shape_document(shape: Shape) -> dict:
    """One shape as the world file writes it."""
    if isinstance(shape, Box):
        doc = {"type": "box", "center": list(shape.center), "size": list(shape.size)}
        return {**doc, "angle": shape.angle} if shape.angle else doc
    if isinstance(shape, Circle):
        return {"type": "circle", "center": list(shape.center), "radius": shape.radius}
    if isinstance(shape, Polygon):
        return {"type": "polygon", "points": [list(p) for p in shape.points]}
    return {"type": "segment", "from": list(shape.start), "to": list(shape.end)}


def _path_document(path: Path_) -> dict:
    if isinstance(path, CirclePath):
        return {"type": "circle", "center": list(path.center), "radius": path.radius, "period_s": path.period_s,
                "direction": path.direction, "phase": path.phase}
    return {"type": "line", "from": list(path.start), "to": list(path.end), "speed_mps": path.speed_mps,
            "bounce": path.bounce}


def world_json(world: World) -> str:
    """:func:`world_document` as JSON text, one wall, shape or mover a line (as the shipped worlds are laid out)."""
    lines = []
    for key, value in world_document(world).items():
        if isinstance(value, list) and value and isinstance(value[0], (list, dict)) and key != "size":
            items = ",\n".join(f"    {json.dumps(v)}" for v in value)
            lines.append(f'  "{key}": [\n{items}\n  ]')
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def save_world(world: World, path) -> Path:
    """Write ``world`` to the world file ``path`` (:func:`world_json`), atomically; returns the path."""
    from ekm.files import atomic_write

    path = Path(path)
    with atomic_write(path) as tmp:
        tmp.write_text(world_json(world))
    return path
