"""From a family's layout to a world: the same for every family (:func:`build`).

A family's ``layout(rng, level)`` lays its world out in a frame of its own choosing (:mod:`robots.generator.layout`);
:func:`build` then turns and mirrors it by one of the arena's eight symmetries (drawn from the same generator),
rounds every number to 0.1 mm, checks the document with :func:`robots.worldfile.parse_world` exactly as a
user's file is checked, and keeps it only if :func:`robots.generator.reach.reach` finds a route; otherwise it
starts again from the next sub-seed.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass

import numpy as np

from ekm.angles import wrap
from ekm.errors import InputError
from robots.generator.layout import T, Retry, as_shape
from robots.generator.shapes import route_passes
from robots.worldfile import parse_world

ATTEMPTS = 50  # sub-seeds tried before giving up (none of the families needs more than a few)


def build(family, seed: int, difficulty: float | None, name: str):
    """The world ``name`` of ``family`` (a :class:`robots.generator.Family`) from ``seed`` (see
    :func:`robots.generator.generate`)."""
    from robots.generator.reach import reach

    rng = np.random.default_rng(seed)
    drawn = rng.uniform()  # always drawn, so a given difficulty leaves the rest of the stream as it was
    level = round(drawn if difficulty is None else difficulty, 4)
    why: Counter[str] = Counter()  # why the layouts drawn were refused, and how often
    for attempt in range(ATTEMPTS):
        if attempt:
            rng = np.random.default_rng([seed, attempt])
        try:
            layout = family.layout(rng, level)
            sym = Symmetry.draw(rng, layout.doc["size"])
            doc = tidy({"name": name, **sym.doc(layout.doc)})
            if layout.blockers:
                doc = close_doors(doc, [tidy(sym.shape(c)) for c in layout.candidates], layout.blockers, rng)
        except Retry as refused:
            why[str(refused) or "the layouts drawn did not fit"] += 1
            continue
        world = parse_world(doc, name)
        found = reach(world)
        if not found.solvable:
            why["the generator's search found no route for the robot's disc"] += 1
            continue
        doc["difficulty"] = {"family": family.name, "seed": seed, "level": level, **found.measures(),
                             "traps": layout.traps, "movers": len(world.moving)}
        return parse_world(doc, name)
    (reason, times), = why.most_common(1)
    raise InputError(f"{name}: no world of this spelling from seed {seed}: {reason} ({times} of {ATTEMPTS} layouts "
                     "drawn); try another seed or family")


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
        if doc.get("events"):
            out["events"] = [{**e, "add": [self.shape(s) for s in e["add"]]} for e in doc["events"]]
        x, y, theta = doc["start"]
        out["start"] = self.point((x, y)) + [self.angle(theta)]
        out["goal"] = self.point(doc["goal"])
        out["wall_thickness"] = doc.get("wall_thickness", T)
        return out


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
        on_route = [c for c in candidates if c not in placed and route_passes(found.route, as_shape(c))]
        if not on_route:
            raise Retry
        placed.append(on_route[int(rng.integers(len(on_route)))])
    return {**{k: v for k, v in doc.items() if k not in ("start", "goal", "wall_thickness")},
            "unforeseen": placed, "start": doc["start"], "goal": doc["goal"], "wall_thickness": doc["wall_thickness"]}
