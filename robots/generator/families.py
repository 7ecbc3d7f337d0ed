"""The families' builders: from a random generator and a difficulty level, a world-file document.

Each builder ``name(rng, level) -> Layout`` lays its world out in a frame of its own choosing;
:func:`build` then turns and mirrors it by one of the arena's eight symmetries (drawn from the same
generator), rounds every number to 0.1 mm, checks the document with :func:`robots.worldfile.parse_world`
exactly as a user's file is checked, and keeps it only if :func:`robots.generator.reach.reach` finds a
route; otherwise it starts again from the next sub-seed. Widths are physical gaps between surfaces: a wall
is a segment grown by half its thickness (round caps), so a door ``w`` wide between two wall segments has
their ends ``w + T`` apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ekm.angles import wrap
from robots.geometry import Box, Circle, distance, segment_distance
from robots.params import KHEPERA
from robots.worldfile import parse_world

R = KHEPERA.radius  # m: the robot's radius
T = 0.01  # m: wall thickness of every generated world
ARENA = (0.8, 2.5)  # m: the smallest and largest side of an arena
ATTEMPTS = 50  # sub-seeds tried before giving up (none of the families needs more than a few)


class Retry(Exception):
    """The layout drawn does not fit (too big, overlapping, no route): try the next sub-seed."""


@dataclass
class Layout:
    """A builder's world-file document (without ``name``), the traps it placed, and for ``blocked`` the
    boxes that would close each door (``candidates``) and how many of them to close (``blockers``)."""

    doc: dict
    traps: int = 0
    blockers: int = 0
    candidates: list = field(default_factory=list)


def build(family: str, seed: int, difficulty: float | None, name: str):
    """The world ``name`` of ``family`` from ``seed`` (see :func:`robots.generator.generate`)."""
    from robots.generator.reach import reach

    rng = np.random.default_rng(seed)
    drawn = rng.uniform()  # always drawn, so a given difficulty leaves the rest of the stream as it was
    level = round(drawn if difficulty is None else difficulty, 4)
    for attempt in range(ATTEMPTS):
        if attempt:
            rng = np.random.default_rng([seed, attempt])
        try:
            layout = BUILDERS[family](rng, level)
            sym = Symmetry.draw(rng, layout.doc["size"])
            doc = tidy({"name": name, **sym.doc(layout.doc)})
            if layout.blockers:
                doc = close_doors(doc, [tidy(sym.shape(c)) for c in layout.candidates], layout.blockers, rng)
        except Retry:
            continue
        world = parse_world(doc, name)
        found = reach(world)
        if not found.solvable:
            continue
        doc["difficulty"] = {"family": family, "seed": seed, "level": level, **found.measures(),
                             "traps": layout.traps, "movers": len(world.moving)}
        return parse_world(doc, name)
    raise RuntimeError(f"{name}: no solvable layout in {ATTEMPTS} attempts")


# ------------------------------------------------------------------------------------------- documents

def tidy(value):
    """``value`` with every float rounded to 0.1 mm (and no negative zero): tidy JSON, the same bits in
    any process."""
    if isinstance(value, dict):
        return {k: tidy(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [tidy(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return round(float(value), 4) + 0.0
    return value


def _wall(a, b) -> list:
    return [float(a[0]), float(a[1]), float(b[0]), float(b[1])]


def _box(center, size, angle: float = 0.0) -> dict:
    doc = {"type": "box", "center": list(center), "size": list(size)}
    return {**doc, "angle": float(angle)} if angle else doc


def _circle(center, radius: float) -> dict:
    return {"type": "circle", "center": list(center), "radius": float(radius)}


def _shape(doc: dict):
    """A box or circle document as a :mod:`robots.geometry` shape."""
    if doc["type"] == "circle":
        return Circle(tuple(doc["center"]), doc["radius"])
    return Box(tuple(doc["center"]), tuple(doc["size"]), doc.get("angle", 0.0))


def _unit(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


@dataclass(frozen=True)
class Symmetry:
    """One of the eight symmetries of a ``size`` arena: a mirror in x, then ``quarter`` quarter turns
    counter-clockwise (each swaps the arena's sides)."""

    size: tuple
    quarter: int
    mirror: bool

    @classmethod
    def draw(cls, rng, size) -> Symmetry:
        return cls(tuple(size), int(rng.integers(4)), bool(rng.integers(2)))

    def point(self, p) -> list:
        (x, y), (w, h) = p, self.size
        if self.mirror:
            x = w - x
        for _ in range(self.quarter):
            x, y, w, h = h - y, x, h, w
        return [x, y]

    def vector(self, v) -> list:
        x, y = v
        if self.mirror:
            x = -x
        for _ in range(self.quarter):
            x, y = -y, x
        return [x, y]

    def angle(self, a: float) -> float:
        """``a`` turned with the arena, in [−π, π): the one wrap mirrored (``−wrap(−a)``, the same bits as
        ``(a + π) mod 2π − π``), as generated worlds have always held their angles — a world is its spelling, and
        ``maze:7`` must stay the world every results file and table was made in."""
        a = (math.pi - a if self.mirror else a) + self.quarter * math.pi / 2
        return -wrap(-a)

    def shape(self, s: dict, relative: bool = False) -> dict:
        place = self.vector if relative else self.point
        out = dict(s)
        if "center" in s:
            out["center"] = place(s["center"])
        if "points" in s:
            out["points"] = [place(p) for p in s["points"]]
        if s["type"] == "segment":
            out["from"], out["to"] = place(s["from"]), place(s["to"])
        if s["type"] == "box":
            a = self.angle(s.get("angle", 0.0)) % math.pi  # a box is the same turned by pi
            out.pop("angle", None)
            if a > 1e-9 and abs(a - math.pi) > 1e-9:
                out["angle"] = a
        return out

    def path(self, p: dict) -> dict:
        if p["type"] == "line":
            return {**p, "from": self.point(p["from"]), "to": self.point(p["to"])}
        direction = p.get("direction", "ccw")
        if self.mirror:
            direction = "cw" if direction == "ccw" else "ccw"
        phase = self.angle(p.get("phase", 0.0))
        return {**p, "center": self.point(p["center"]), "phase": phase, "direction": direction}

    def doc(self, doc: dict) -> dict:
        w, h = doc["size"]
        out = {"size": [h, w] if self.quarter % 2 else [w, h]}
        if doc.get("walls"):
            out["walls"] = [self.point(wl[:2]) + self.point(wl[2:]) for wl in doc["walls"]]
        for key in ("obstacles", "unforeseen"):
            if doc.get(key):
                out[key] = [self.shape(s) for s in doc[key]]
        if doc.get("moving"):
            out["moving"] = [{"shape": self.shape(m["shape"], relative=True), "path": self.path(m["path"])}
                             for m in doc["moving"]]
        x, y, theta = doc["start"]
        out["start"] = self.point((x, y)) + [self.angle(theta)]
        out["goal"] = self.point(doc["goal"])
        out["wall_thickness"] = doc.get("wall_thickness", T)
        return out


# ------------------------------------------------------------------------------------------- geometry

def offset_polyline(points, d: float) -> np.ndarray:
    """The polyline ``points`` ``(k, 2)`` moved ``d`` to its left (mitred corners: the distance between the
    two lines is ``d`` along every leg)."""
    p = np.asarray(points, dtype=float)
    u = np.diff(p, axis=0)
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    inner = [p[k] + d * (n[k - 1] + n[k]) / (1.0 + n[k - 1] @ n[k]) for k in range(1, len(p) - 1)]
    return np.array([p[0] + d * n[0], *inner, p[-1] + d * n[-1]])


def thick_polyline(points, thickness: float) -> list:
    """The polygon ``thickness`` wide around the polyline ``points`` (square ends, mitred corners)."""
    left = offset_polyline(points, thickness / 2)
    right = offset_polyline(points, -thickness / 2)
    return [list(p) for p in [*left, *right[::-1]]]


def _segment_gap(a, b, c, d) -> float:
    """Distance between the segments ``a``-``b`` and ``c``-``d`` (0 when they cross)."""
    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
        return 0.0
    return float(min(segment_distance(a, c, d), segment_distance(b, c, d),
                     segment_distance(c, a, b), segment_distance(d, a, b)))


def walls_apart(walls, gap: float) -> bool:
    """Do wall segments ``[x0, y0, x1, y1]`` that share no end keep at least ``gap`` between their surfaces?"""
    segs = [(np.array(w[:2]), np.array(w[2:])) for w in walls]
    for i, (a, b) in enumerate(segs):
        for c, d in segs[i + 1:]:
            if min(np.hypot(*(p - q)) for p in (a, b) for q in (c, d)) < 1e-9:
                continue
            if _segment_gap(a, b, c, d) < T + gap:
                return False
    return True


def shape_gap(a, b) -> float:
    """The gap between two box or circle shapes (<= 0 when they touch or overlap)."""
    if isinstance(a, Circle) and isinstance(b, Circle):
        return math.dist(a.center, b.center) - a.radius - b.radius
    if isinstance(a, Circle) or isinstance(b, Circle):
        circle, box = (a, b) if isinstance(a, Circle) else (b, a)
        p, v = np.asarray(circle.center, dtype=float)[None], box.vertices()
        inside = bool(_convex_contains(p, v)[0])
        return (0.0 if inside else float(_to_edges(p, v)[0])) - circle.radius
    va, vb = a.vertices(), b.vertices()
    if _convex_contains(va, vb).any() or _convex_contains(vb, va).any() or _edges_cross(va, vb):
        return 0.0
    return float(min(_to_edges(va, vb).min(), _to_edges(vb, va).min()))


def _to_edges(p, v) -> np.ndarray:
    """Distance from each point ``p`` ``(n, 2)`` to the nearest edge of the closed polygon ``v`` ``(m, 2)``."""
    a, ab = v, np.roll(v, -1, axis=0) - v
    ap = p[:, None, :] - a[None]
    t = np.clip(np.einsum("nmk,mk->nm", ap, ab) / np.einsum("mk,mk->m", ab, ab), 0.0, 1.0)
    d = ap - t[..., None] * ab
    return np.sqrt(np.einsum("nmk,nmk->nm", d, d)).min(axis=1)


def _convex_contains(p, v) -> np.ndarray:
    """Which points ``p`` ``(n, 2)`` lie inside the convex polygon ``v`` ``(m, 2)`` (counter-clockwise)."""
    ab = np.roll(v, -1, axis=0) - v
    ap = p[:, None, :] - v[None]
    return np.all(ab[None, :, 0] * ap[..., 1] - ab[None, :, 1] * ap[..., 0] > 0, axis=1)


def _edges_cross(va, vb) -> bool:
    """Does an edge of the closed polygon ``va`` cross one of ``vb``?"""
    a, b = va[:, None], np.roll(va, -1, axis=0)[:, None]
    c, d = vb[None], np.roll(vb, -1, axis=0)[None]

    def side(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    return bool(np.any((side(a, b, c) * side(a, b, d) < 0) & (side(c, d, a) * side(c, d, b) < 0)))


def bounding_radius(s) -> float:
    return s.radius if isinstance(s, Circle) else 0.5 * math.hypot(*s.size)


# ------------------------------------------------------------------------------------------- corridor

def corridor(rng, level: float) -> Layout:
    """A corridor of known walls along a random polyline of 90 deg (or 45 and 90 deg) bends, from 1 turn
    (level 0) to 8 (level 1), staircases and zig-zags of short steps among them; 15 cm wide at level 0
    down to 8 cm at level 1; closed at both ends. It never touches itself: walls that share no end keep
    1 cm apart. The robot starts at one end facing along it; the goal is at the other end."""
    width = float(np.clip(0.15 - 0.07 * level + rng.uniform(-0.01, 0.01), 0.08, 0.15))
    turns = int(np.clip(round(1 + 7 * level + rng.uniform(-0.5, 0.5)), 1, 8))
    diagonal = bool(rng.uniform() < 0.5)
    off = 0.5 * (width + T)  # centre line to the walls' centre lines
    for _ in range(60):
        line = _corridor_line(rng, turns, diagonal, width)
        left, right = offset_polyline(line, off), offset_polyline(line, -off)
        walls = ([_wall(a, b) for a, b in zip(left, left[1:])] + [_wall(a, b) for a, b in zip(right, right[1:])]
                 + [_wall(left[0], right[0]), _wall(left[-1], right[-1])])
        if not walls_apart(walls, 0.01):
            continue
        ends = np.array(walls).reshape(-1, 2)
        lo, hi = ends.min(axis=0), ends.max(axis=0)
        margin = rng.uniform(0.04, 0.12, size=2)
        size = np.maximum(hi - lo + 2 * margin, ARENA[0])
        if np.any(size > ARENA[1]):
            continue
        shift = 0.5 * (size - (hi - lo)) - lo
        u0, u1 = _unit_between(line[0], line[1]), _unit_between(line[-2], line[-1])
        start, goal = line[0] + 0.06 * u0 + shift, line[-1] - 0.06 * u1 + shift
        if math.dist(start, goal) < 0.5:
            continue
        doc = {"size": list(size), "walls": [_wall(w[:2] + shift, w[2:] + shift) for w in np.array(walls)],
               "start": [*start, math.atan2(u0[1], u0[0])], "goal": list(goal), "wall_thickness": T}
        return Layout(doc)
    raise Retry


def _unit_between(a, b) -> np.ndarray:
    v = np.asarray(b, float) - np.asarray(a, float)
    return v / np.hypot(*v)


def _corridor_line(rng, turns: int, diagonal: bool, width: float) -> np.ndarray:
    """The corridor's centre line: a first leg, then bends, staircases and zig-zags until ``turns`` turns,
    then a last leg. Headings are multiples of 45 deg (of 90 deg unless ``diagonal``)."""
    short = (width + 2 * T + 0.04, width + 2 * T + 0.09)
    heading = int(rng.integers(8)) if diagonal else 2 * int(rng.integers(4))  # in 45 deg units
    points = [np.zeros(2)]

    def leg(length):
        points.append(points[-1] + length * _unit(heading * math.pi / 4))

    def toward_home() -> int:
        """+1 or -1: the turn that points back towards the middle of the line so far (keeps it compact)."""
        home = np.mean(points, axis=0) - points[-1]
        cross = math.cos(heading * math.pi / 4) * home[1] - math.sin(heading * math.pi / 4) * home[0]
        return 1 if cross >= 0 else -1

    leg(rng.uniform(0.25, 0.4))
    done = 0
    while done < turns:
        left = turns - done
        kind = rng.choice(["bend", "stairs", "uturn"], p=[0.5, 0.35, 0.15])
        sign = toward_home() if rng.uniform() < 0.6 else int(rng.choice([-1, 1]))
        step = int(rng.choice([1, 2])) if diagonal else 2
        if kind == "stairs" and left >= 2:
            m = min(left, int(rng.integers(2, 5)))
            for k in range(m):
                heading += sign * step * (-1) ** k
                leg(rng.uniform(*short) if k < m - 1 else rng.uniform(0.2, 0.4))
            done += m
        elif kind == "uturn" and left >= 2:
            heading += 2 * sign
            leg(rng.uniform(short[1], short[1] + 0.1))
            heading += 2 * sign
            leg(rng.uniform(0.25, 0.45))
            done += 2
        else:
            heading += sign * step
            leg(rng.uniform(0.2, 0.45))
            done += 1
    return np.array(points)


# ------------------------------------------------------------------------------------------- traps

def traps(rng, level: float) -> Layout:
    """One trap (level 0) to three (level 1), unforeseen, one after another on the line from the start to
    the goal, each open towards the robot as it comes: a U (one polygon, as ``concave-obstacle``), a V,
    or a U or V made of two or three boxes whose gaps (1-2.5 cm) the robot cannot pass. Deeper with the
    level; at least 13 cm to pass round every trap on both sides; an open arena otherwise."""
    n = int(np.clip(round(1 + 2 * level + rng.uniform(-0.5, 0.5)), 1, 3))
    t = 0.02  # the traps' arm thickness (m)
    shapes, extents = [], []
    for kind in rng.choice(["U", "V", "boxes"], size=n):
        mouth = rng.uniform(0.14, 0.22) + 0.04 * level
        depth = rng.uniform(0.14, 0.2) + 0.12 * level
        made = _trap(rng, str(kind), mouth, depth, t)  # mouth at x = 0, centred on y = 0, open towards -x
        box = np.array([_bounds(s) for s in made])
        shapes.append(made)
        extents.append((box[:, 0].min(), box[:, 1].min(), box[:, 2].max(), box[:, 3].max()))
    half = max(max(-e[1], e[3]) for e in extents)
    height = max(ARENA[0], 2 * half + 2 * (0.14 + rng.uniform(0.0, 0.15)))
    x_start = rng.uniform(0.12, 0.18)
    x = x_start + rng.uniform(0.2, 0.3)
    placed_x = []
    for e in extents:
        placed_x.append(x)
        x += e[2] + rng.uniform(0.18, 0.28)
    x_goal = x - rng.uniform(0.0, 0.06)
    width = x_goal + rng.uniform(0.12, 0.2)
    if width > ARENA[1]:
        raise Retry
    width = max(width, ARENA[0])

    def y_room(e):  # centre lines that leave >= 13 cm between the trap and the border's surface
        return (0.135 + T / 2 - e[1], height - 0.135 - T / 2 - e[3])

    lo0, hi0 = y_room(extents[0])
    lo1, hi1 = y_room(extents[-1])
    y_start, y_goal = rng.uniform(lo0, hi0), rng.uniform(lo1, hi1)
    unforeseen = []
    for made, e, px in zip(shapes, extents, placed_x):
        lo, hi = y_room(e)
        s = (px - x_start) / (x_goal - x_start)
        yc = float(np.clip(y_start + s * (y_goal - y_start) + rng.uniform(-0.02, 0.02), lo, hi))
        unforeseen += [_moved(sh, px, yc) for sh in made]
    doc = {"size": [width, height], "unforeseen": unforeseen, "start": [x_start, y_start, 0.0],
           "goal": [x_goal, y_goal], "wall_thickness": T}
    return Layout(doc, traps=n)


def _trap(rng, kind: str, mouth: float, depth: float, t: float) -> list:
    """One trap's shapes, its mouth (inner width ``mouth``) at x = 0 facing -x, ``depth`` deep inside."""
    h = mouth / 2 + t / 2  # the arms' centre lines
    if kind == "U":
        back = depth + t / 2
        return [{"type": "polygon", "points": thick_polyline([(0, h), (back, h), (back, -h), (0, -h)], t)}]
    if kind == "V":
        return [{"type": "polygon", "points": thick_polyline([(0, h), (depth, 0.0), (0, -h)], t)}]
    gap = rng.uniform(0.01, 0.025)  # between the boxes: too narrow for the robot
    if rng.uniform() < 0.5:  # a U of three boxes
        arm = depth - gap
        return [_box((arm / 2, h), (arm, t)), _box((arm / 2, -h), (arm, t)),
                _box((depth + t / 2, 0.0), (t, mouth + 2 * t))]
    # a V of two boxes that almost meet at the apex
    length = math.hypot(depth, h)
    u = np.array([depth, -h]) / length  # along the upper arm, towards the apex
    cut = (gap / 2 + t * depth / (2 * length)) * length / h  # leaves the gap between the arms' inner corners
    tip, end = np.array([0.0, h]), np.array([depth, 0.0]) - cut * u
    angle = math.atan2(u[1], u[0])
    mid = (tip + end) / 2
    arm = float(np.hypot(*(end - tip)))
    return [_box(mid, (arm, t), angle), _box((mid[0], -mid[1]), (arm, t), -angle)]


def _bounds(s: dict) -> tuple:
    if s["type"] == "polygon":
        p = np.array(s["points"])
        return (*p.min(axis=0), *p.max(axis=0))
    v = _shape(s).vertices()
    return (*v.min(axis=0), *v.max(axis=0))


def _moved(s: dict, dx: float, dy: float) -> dict:
    if s["type"] == "polygon":
        return {**s, "points": [[x + dx, y + dy] for x, y in s["points"]]}
    return {**s, "center": [s["center"][0] + dx, s["center"][1] + dy]}


# ------------------------------------------------------------------------------------------- clutter

def clutter(rng, level: float) -> Layout:
    """Unforeseen boxes (half of them turned, longer with the level) and circles strewn over an open arena
    larger with the level, covering 4 % of it at level 0 and 20-25 % at level 1 (as densely as the gaps
    allow: shapes are placed at random until the cover is reached or no more fit). Every gap between two
    shapes, or a shape and the border, is at least 15 cm at level 0 and 8 cm at level 1, or closed: at
    higher levels a few shapes overlap into clusters of up to three. Start at one side, goal at the other, both
    10 cm clear of everything."""
    w = rng.uniform(1.0, 1.4) + 0.6 * level
    h = rng.uniform(0.8, 1.1) + 0.4 * level
    min_gap = 0.08 + 0.07 * (1 - level)
    start = np.array([rng.uniform(0.1, 0.15), rng.uniform(0.15, h - 0.15)])
    goal = np.array([w - rng.uniform(0.1, 0.15), rng.uniform(0.15, h - 0.15)])
    target = (0.04 + 0.24 * level) * w * h
    shapes, docs, cluster, area = [], [], [], 0.0
    centres, radii = np.zeros((1500, 2)), np.zeros(1500)  # of the shapes placed, for a quick first test
    for _ in range(1500):
        if area >= target:
            break
        joined = None
        if shapes and rng.uniform() < 0.2 * level:  # overlap a shape already placed: a cluster
            joined = int(rng.integers(len(shapes)))
            if cluster.count(cluster[joined]) >= 3:
                continue
            centre = np.asarray(shapes[joined].center) + bounding_radius(shapes[joined]) * rng.uniform(0.5, 0.9) \
                * _unit(rng.uniform(-math.pi, math.pi))
        else:
            centre = np.array([rng.uniform(0, w), rng.uniform(0, h)])
        if rng.uniform() < 0.55:
            turned = rng.uniform() < 0.5
            doc = _box(centre, (rng.uniform(0.03, 0.12), rng.uniform(0.05, 0.18 + 0.17 * level)),
                       rng.uniform(0, math.pi) if turned else float(rng.choice([0.0, math.pi / 2])))
        else:
            doc = _circle(centre, rng.uniform(0.02, 0.07))
        s = _shape(doc)
        x0, y0, x1, y1 = _bounds(doc) if doc["type"] == "box" else (*(centre - s.radius), *(centre + s.radius))
        room = T / 2 + min_gap
        if x0 < room or y0 < room or x1 > w - room or y1 > h - room:
            continue
        if any(math.dist(centre, p) < bounding_radius(s) + 0.1 and shape_gap(s, Circle(tuple(p), 0.0)) < 0.1
               for p in (start, goal)):
            continue
        own = cluster[joined] if joined is not None else len(shapes)
        if joined is not None and shape_gap(s, shapes[joined]) > 0:
            continue
        if not _clear_of(s, shapes, centres[:len(shapes)], radii[:len(shapes)], cluster, own, min_gap):
            continue
        centres[len(shapes)], radii[len(shapes)] = s.center, bounding_radius(s)
        shapes.append(s)
        docs.append(doc)
        cluster.append(own)
        area += s.size[0] * s.size[1] if isinstance(s, Box) else math.pi * s.radius ** 2
    heading = math.atan2(*(goal - start)[::-1]) + rng.uniform(-0.5, 0.5)
    doc = {"size": [w, h], "unforeseen": docs, "start": [*start, heading], "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


def _clear_of(s, shapes, centres, radii, cluster, own: int, gap: float) -> bool:
    """Is ``s`` at least ``gap`` from every shape, or (of its own cluster ``own``) overlapping it? (``centres``
    and ``radii``: the shapes' bounding circles.)"""
    near = np.flatnonzero(np.hypot(*(centres - s.center).T) < radii + bounding_radius(s) + gap)
    gaps = ((shape_gap(s, shapes[k]), cluster[k] == own) for k in near)
    return all(g >= gap or (same and g <= 0.0) for g, same in gaps)


# ------------------------------------------------------------------------------------------- maze

def maze(rng, level: float) -> Layout:
    """A grid of rooms, 2x2 at level 0 to 4x4 at level 1, walled by known walls with doors 8-12 cm wide:
    a perfect maze (a random depth-first spanning tree of the rooms, so dead ends), plus up to two extra
    doors at low levels (loops), and half walls (stubs from a room's wall into it, more with the level).
    Start in one corner room, goal in the far one."""
    nx, ny = (int(np.clip(round(2 + 2 * level + rng.uniform(-0.5, 0.5)), 2, 4)) for _ in range(2))
    s = max(rng.uniform(0.3, 0.42), ARENA[0] / min(nx, ny))
    if max(nx, ny) * s > ARENA[1]:
        raise Retry
    edges = _spanning_tree(rng, nx, ny)
    others = [e for e in _all_edges(nx, ny) if e not in edges]
    extra = min(len(others), int(round((1 - level) * rng.uniform(0.0, 2.4))))
    for k in rng.permutation(len(others))[:extra]:
        edges.add(others[k])
    doors = {e: (rng.uniform(0.3, 0.7) * s, rng.uniform(0.08, 0.12)) for e in sorted(edges)}
    walls = []
    for e in _all_edges(nx, ny):
        a, b = _edge_line(e, s)
        walls += _wall_with_door(a, b, *doors[e]) if e in doors else [_wall(a, b)]
    start_room, goal_room = (0, 0), (nx - 1, ny - 1)
    for room in ((i, j) for i in range(nx) for j in range(ny)):
        if room in (start_room, goal_room) or rng.uniform() > 0.15 + 0.5 * level:
            continue
        stub = _stub(rng, room, s, doors, nx, ny)
        if stub is not None:
            walls.append(stub)
    start = (np.array(start_room) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    goal = (np.array(goal_room) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    if math.dist(start, goal) < 0.5:
        raise Retry
    doc = {"size": [nx * s, ny * s], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)],
           "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


def _all_edges(nx: int, ny: int) -> list:
    """Pairs of neighbouring rooms ``((i, j), (i2, j2))``, each once, in a fixed order."""
    return ([((i, j), (i + 1, j)) for j in range(ny) for i in range(nx - 1)]
            + [((i, j), (i, j + 1)) for j in range(ny - 1) for i in range(nx)])


def _spanning_tree(rng, nx: int, ny: int) -> set:
    """A random depth-first spanning tree of the rooms (the recursive backtracker: long paths, dead ends)."""
    seen, stack, tree = {(0, 0)}, [(0, 0)], set()
    while stack:
        i, j = stack[-1]
        nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di < nx and 0 <= j + dj < ny and (i + di, j + dj) not in seen]
        if not nbrs:
            stack.pop()
            continue
        nxt = nbrs[int(rng.integers(len(nbrs)))]
        tree.add(tuple(sorted([(i, j), nxt])))
        seen.add(nxt)
        stack.append(nxt)
    return tree


def _edge_line(edge, s: float) -> tuple:
    """The wall between two neighbouring rooms, from its lower (left) end to its upper (right) end."""
    (i, j), (i2, j2) = edge
    if i2 > i:  # side by side: a vertical wall
        return np.array([i2 * s, j * s]), np.array([i2 * s, (j + 1) * s])
    return np.array([i * s, j2 * s]), np.array([(i + 1) * s, j2 * s])


def _wall_with_door(a, b, at: float, width: float) -> list:
    """The wall ``a``-``b`` with a door ``width`` wide (between surfaces) centred ``at`` from ``a``."""
    u = _unit_between(a, b)
    half = 0.5 * (width + T)
    return [_wall(a, a + (at - half) * u), _wall(a + (at + half) * u, b)]


def _stub(rng, room, s: float, doors: dict, nx: int, ny: int):
    """A half wall into ``room`` from the middle part of one of its sides, kept 10 cm from that side's door;
    None if the side drawn has no room for it."""
    i, j = room
    side = int(rng.integers(4))  # 0: left, 1: right, 2: bottom, 3: top
    corner = np.array([i * s, j * s])
    along, inward = (np.array([0.0, 1.0]), np.array([1.0, 0.0]))
    if side >= 2:
        along, inward = inward, along
    base = corner + (s * inward if side in (1, 3) else 0.0)
    direction = -inward if side in (1, 3) else inward
    nbr = {0: (i - 1, j), 1: (i + 1, j), 2: (i, j - 1), 3: (i, j + 1)}[side]
    at = rng.uniform(0.35, 0.65) * s
    door = doors.get(tuple(sorted([room, nbr])))
    if door is not None and abs(at - door[0]) < door[1] / 2 + T + 0.1:
        return None
    start = base + at * along
    return _wall(start, start + rng.uniform(0.3, 0.5) * s * direction)


# ------------------------------------------------------------------------------------------- movers

def movers(rng, level: float) -> Layout:
    """Two to four rooms in a row, joined by doorways (10-16 cm) or short corridors of known walls, with one
    moving obstacle (level 0) to three (level 1): robot-sized circles or boxes (2-4 cm radius) on line paths
    with bounce at 2-6 cm/s, faster with the level. A doorway's mover shuttles along the wall just in front
    of the door, across its mouth, and leaves it open at one end of its path; a corridor's mover shuttles
    along one side of the corridor, which is wide enough to leave 8 cm beside it. Every doorway and
    corridor is on the route."""
    rooms = int(np.clip(round(2 + 1.5 * level + rng.uniform(-0.5, 0.5)), 2, 4))
    n = int(np.clip(round(1 + 2 * level + rng.uniform(-0.5, 0.5)), 1, 3))
    h = rng.uniform(0.8, 1.0)
    kinds = ["door" if rng.uniform() < 0.5 else "corridor" for _ in range(rooms - 1)]
    slots = [(p, side) for p, kind in enumerate(kinds) for side in ((-1, 1) if kind == "door" else (0,))]
    order = sorted(range(len(slots)), key=lambda k: (rng.uniform() + (slots[k][1] == 1), k))  # partitions first
    chosen = {slots[k] for k in order[:n]}
    widths = rng.uniform(0.3, 0.45, size=rooms)
    lengths = rng.uniform(0.15, 0.3, size=rooms - 1) * np.array([kind == "corridor" for kind in kinds])
    total = widths.sum() + lengths.sum()
    if total > ARENA[1]:
        raise Retry
    widths *= max(1.0, ARENA[0] / total)
    w = float(widths.sum() + lengths.sum())
    walls, moving, x = [], [], float(widths[0])
    for p, kind in enumerate(kinds):
        speed = rng.uniform(0.02, 0.03) + 0.03 * level
        if kind == "door":
            dw = rng.uniform(0.1, 0.16)
            yd = rng.uniform(0.12 + dw / 2, h - 0.12 - dw / 2)
            walls += _wall_with_door(np.array([x, 0.0]), np.array([x, h]), yd, dw)
            for side in (-1, 1):
                if (p, side) in chosen:
                    moving.append(_door_mover(rng, x, yd, dw, side, h, speed))
            x += float(widths[p + 1])
        else:
            shape, rb = _mover_shape(rng) if (p, 0) in chosen else (None, 0.0)
            wc = 2 * rb + 0.01 + rng.uniform(0.08, 0.11) if shape else rng.uniform(0.1, 0.16)
            yc = rng.uniform(0.12 + wc / 2, h - 0.12 - wc / 2)
            xa, xb = x, x + float(lengths[p])
            lo, hi = yc - wc / 2 - T / 2, yc + wc / 2 + T / 2
            walls += [_wall((xa, 0), (xa, lo)), _wall((xa, hi), (xa, h)), _wall((xb, 0), (xb, lo)),
                      _wall((xb, hi), (xb, h)), _wall((xa, lo), (xb, lo)), _wall((xa, hi), (xb, hi))]
            if shape:
                yp = yc + rng.choice([-1, 1]) * (wc / 2 - rb - 0.01)
                ends = [[xa - rng.uniform(0.0, 0.04), yp], [xb + rng.uniform(0.0, 0.04), yp]]
                moving.append(_mover(shape, ends[::int(rng.choice([-1, 1]))], speed))
            x = xb + float(widths[p + 1])
    start = _clear_point(rng, (0.08, 0.15), h, moving)
    goal = _clear_point(rng, (w - 0.15, w - 0.08), h, moving)
    doc = {"size": [w, h], "walls": walls, "moving": moving,
           "start": [*start, rng.uniform(-0.5, 0.5)], "goal": list(goal), "wall_thickness": T}
    return Layout(doc)


def _mover_shape(rng) -> tuple[dict, float]:
    """A robot-sized moving shape around its own origin and its bounding radius (2-4 cm)."""
    r = rng.uniform(0.02, 0.04)
    if rng.uniform() < 0.5:
        return {"type": "circle", "radius": r}, r
    beta = rng.uniform(math.pi / 6, math.pi / 3)
    size = [2 * r * math.cos(beta), 2 * r * math.sin(beta)]
    return {"type": "box", "size": size, "angle": rng.uniform(0, math.pi)}, r


def _mover(shape: dict, ends, speed: float) -> dict:
    return {"shape": shape, "path": {"type": "line", "from": list(ends[0]), "to": list(ends[1]),
                                     "speed_mps": speed, "bounce": True}}


def _door_mover(rng, x: float, yd: float, dw: float, side: int, h: float, speed: float) -> dict:
    """A mover shuttling along the wall at ``x`` on ``side`` (-1 left, +1 right), across the door at ``yd``
    (``dw`` wide), far enough past it at one end at least to leave the door open."""
    shape, rb = _mover_shape(rng)
    xp = x + side * (T / 2 + rb + rng.uniform(0.01, 0.05))
    reach_ = dw / 2 + rb + 2 * R + 0.03
    lo = max(rb + 0.015, yd - reach_ - rng.uniform(0.0, 0.12))
    hi = min(h - rb - 0.015, yd + reach_ + rng.uniform(0.0, 0.12))
    if max(yd - lo, hi - yd) < dw / 2 + rb + 0.05:
        raise Retry
    ends = [[xp, lo], [xp, hi]]
    return _mover(shape, ends[::int(rng.choice([-1, 1]))], speed)


def _clear_point(rng, xs: tuple, h: float, moving: list) -> np.ndarray:
    """A point with x in ``xs`` and 20 cm from the top and bottom, clear of every mover's sweep."""
    for _ in range(20):
        p = np.array([rng.uniform(*xs), rng.uniform(0.2, h - 0.2)])
        if all(segment_distance(p, m["path"]["from"], m["path"]["to"]) >= R + 0.04 + 0.03 for m in moving):
            return p
    raise Retry


# ------------------------------------------------------------------------------------------- blocked

def blocked(rng, level: float) -> Layout:
    """Known walls that leave two or more routes: a wall across the arena with two or three doors, or a
    ring of 2x2, 3x2 or 3x3 rooms (the middle one closed) with the goal across the ring. Unforeseen boxes
    close the door on the shortest route of the known map, one (or, at higher levels on the wall with
    three doors, two: the second on the shortest route that is left) -- found by
    :func:`robots.generator.reach.reach` on the known map (:func:`close_doors`) -- so the robot must find
    the route that is left."""
    if rng.uniform() < 0.5:
        n_block = 2 if rng.uniform() < 0.8 * level else 1
        return _door_wall(rng, level, n_block)
    return _ring(rng, level)


def _door_wall(rng, level: float, n_block: int) -> Layout:
    w = rng.uniform(1.0, 1.3) + 0.6 * level
    h = rng.uniform(0.8, 1.0) + 0.5 * level
    xw = w * rng.uniform(0.4, 0.6)
    k = n_block + 1 + int(rng.uniform() < 0.3)
    dws = rng.uniform(0.1, 0.16, size=k)
    spacing, lo, hi = 0.25, 0.15, h - 0.15  # door centres: 25 cm apart at least, 15 cm from the border
    if hi - lo < (k - 1) * spacing:
        raise Retry
    ys = lo + np.sort(rng.uniform(0.0, hi - lo - (k - 1) * spacing, size=k)) + spacing * np.arange(k)
    walls, candidates, y = [], [], 0.0
    for yd, dw in zip(ys, dws):
        walls.append(_wall((xw, y), (xw, yd - (dw + T) / 2)))
        candidates.append(_blocker(rng, (xw, yd), math.pi / 2, dw))
        y = yd + (dw + T) / 2
    walls.append(_wall((xw, y), (xw, h)))
    start = np.array([rng.uniform(0.1, xw - 0.2), rng.uniform(0.15, h - 0.15)])
    goal = np.array([rng.uniform(xw + 0.2, w - 0.1), rng.uniform(0.15, h - 0.15)])
    if math.dist(start, goal) < 0.5:
        raise Retry
    doc = {"size": [w, h], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)], "goal": list(goal),
           "wall_thickness": T}
    return Layout(doc, blockers=n_block, candidates=candidates)


def _ring(rng, level: float) -> Layout:
    nx, ny = (2, 2) if level < 0.35 else [(3, 2), (2, 3), (3, 3)][int(rng.integers(3))]
    s = max(rng.uniform(0.35, 0.5), ARENA[0] / min(nx, ny))
    ring = [(i, 0) for i in range(nx)] + [(nx - 1, j) for j in range(1, ny)] \
        + [(i, ny - 1) for i in range(nx - 2, -1, -1)] + [(0, j) for j in range(ny - 2, 0, -1)]
    linked = {tuple(sorted([a, b])) for a, b in zip(ring, ring[1:] + ring[:1])}
    walls, candidates = [], []
    for e in _all_edges(nx, ny):
        a, b = _edge_line(e, s)
        if e in linked:
            at, dw = rng.uniform(0.3, 0.7) * s, rng.uniform(0.1, 0.16)
            walls += _wall_with_door(a, b, at, dw)
            u = _unit_between(a, b)
            candidates.append(_blocker(rng, a + at * u, math.atan2(u[1], u[0]), dw))
        else:
            walls.append(_wall(a, b))
    start = (np.array(ring[0]) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    goal = (np.array(ring[len(ring) // 2]) + 0.5) * s + rng.uniform(-0.04, 0.04, 2)
    if math.dist(start, goal) < 0.5:
        raise Retry
    doc = {"size": [nx * s, ny * s], "walls": walls, "start": [*start, rng.uniform(-math.pi, math.pi)],
           "goal": list(goal), "wall_thickness": T}
    return Layout(doc, blockers=1, candidates=candidates)


def _blocker(rng, centre, angle: float, dw: float) -> dict:
    """A box that closes the door ``dw`` wide centred on ``centre`` in a wall along ``angle``: 1 cm over
    each of the door's wall ends, 3-5 cm thick."""
    return _box(centre, (dw + T + 0.02, rng.uniform(0.03, 0.05)), angle)


def close_doors(doc: dict, candidates: list, n: int, rng) -> dict:
    """``doc`` with ``n`` of the ``candidates`` (boxes, one per door) as unforeseen obstacles: each time the
    one on the shortest route of the known map with the boxes placed so far (drawn among them if the route
    passes several doors)."""
    from robots.generator.reach import reach

    placed = []
    for _ in range(n):
        world = parse_world({**doc, "obstacles": placed}, doc["name"])
        found = reach(world, known_only=True)
        if not found.solvable:
            raise Retry
        on_route = [c for c in candidates if c not in placed and route_passes(found.route, _shape(c))]
        if not on_route:
            raise Retry
        placed.append(on_route[int(rng.integers(len(on_route)))])
    return {**{k: v for k, v in doc.items() if k not in ("start", "goal", "wall_thickness")},
            "unforeseen": placed, "start": doc["start"], "goal": doc["goal"], "wall_thickness": doc["wall_thickness"]}


def route_passes(route, shape, within: float = 0.0) -> bool:
    """Does the polyline ``route`` ``(k, 2)`` come within ``within`` (m) of ``shape`` (or through it)?"""
    route = np.asarray(route, dtype=float)
    for a, b in zip(route, route[1:]):
        n = max(2, math.ceil(math.dist(a, b) / 0.005) + 1)
        samples = a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)
        if np.min(distance(samples, shape)) <= within:
            return True
    return False


BUILDERS = {"corridor": corridor, "traps": traps, "clutter": clutter, "maze": maze, "movers": movers,
            "blocked": blocked}
