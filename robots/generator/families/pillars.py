"""The ``pillars`` family of generated worlds: its :func:`layout` and :func:`overlay`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import T, Layout, circle


def layout(rng, level: float) -> Layout:
    """A forest of unforeseen pillars (circles of 1-2.5 cm radius) on a jittered hexagonal grid filling the
    arena between a start strip and a goal strip: the gaps between pillars are at least 10 cm at level 0 and
    6 cm at level 1 (the robot is 5 cm wide), drawn up to 3 cm above that. Start at one side, goal at the other."""
    w = rng.uniform(1.1, 1.4) + 0.5 * level
    h = rng.uniform(0.8, 1.0) + 0.3 * level
    start = np.array([rng.uniform(0.08, 0.12), rng.uniform(0.2, h - 0.2)])
    goal = np.array([w - rng.uniform(0.08, 0.12), rng.uniform(0.2, h - 0.2)])
    doc = {"size": [w, h], "start": [*start, rng.uniform(-0.5, 0.5)], "goal": list(goal), "wall_thickness": T}
    return Layout({**doc, "unforeseen": forest(rng, level, doc, (0.2, w - 0.2))})


def overlay(rng, level: float, made: Layout) -> Layout:
    """``made`` with pillars (as :func:`layout`'s, gaps 2 cm wider) wherever its free space has room for them,
    20 cm clear of the start and the goal."""
    doc = made.doc
    pillars = forest(rng, level, doc, (0.0, doc["size"][0]), extra_gap=0.02)
    return Layout({**doc, "unforeseen": list(doc.get("unforeseen", [])) + pillars}, made.traps, made.blockers,
                  made.candidates)


def forest(rng, level: float, doc: dict, xs: tuple, extra_gap: float = 0.0) -> list:
    """Pillars on a jittered hexagonal grid over ``xs`` (m) of the arena of ``doc``, each kept only if its gap to
    every other pillar and to the document's walls and shapes is at least the level's minimum (10 cm at level 0,
    6 cm at level 1, plus ``extra_gap``) and it is 20 cm from the start and the goal."""
    from robots.worldfile import parse_world

    min_gap = 0.1 - 0.04 * level + extra_gap
    pitch = 0.035 + min_gap + rng.uniform(0.0, 0.03)
    w, h = doc["size"]
    world = parse_world({"name": "layout", **doc}, "layout")
    ends = [np.asarray(doc["start"][:2], float), np.asarray(doc["goal"], float)]
    pillars, centres, radii = [], [], []
    for row, y in enumerate(np.arange(pitch / 2, h, pitch * math.sqrt(3) / 2)):
        for x in np.arange(xs[0] + (pitch / 2 if row % 2 else 0.0), xs[1], pitch):
            r = rng.uniform(0.01, 0.025)
            c = np.array([x, y]) + rng.uniform(-0.25, 0.25, 2) * (pitch - 2 * r - min_gap)
            if not (T / 2 + r + min_gap <= c[0] <= w - T / 2 - r - min_gap
                    and T / 2 + r + min_gap <= c[1] <= h - T / 2 - r - min_gap):
                continue
            if any(math.dist(c, e) < 0.2 for e in ends) or world.clearance(c, include_moving=False) < r + min_gap:
                continue
            if centres and np.min(np.hypot(*(np.array(centres) - c).T) - np.array(radii)) < r + min_gap:
                continue
            pillars.append(circle(c, r))
            centres.append(c)
            radii.append(r)
    return pillars


FAMILY = Family("pillars", layout, "a forest of unforeseen pillars with gaps down to 6 cm", overlay)
