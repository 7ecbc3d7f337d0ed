"""The ``movers`` family of generated worlds: its :func:`layout`, registered as :data:`FAMILY`."""

from __future__ import annotations

import math

import numpy as np

from robots.generator.family import Family
from robots.generator.layout import ARENA, R, T, Layout, Retry, wall, wall_with_door
from robots.geometry import segment_distance


def layout(rng, level: float) -> Layout:
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
            walls += wall_with_door(np.array([x, 0.0]), np.array([x, h]), yd, dw)
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
            walls += [wall((xa, 0), (xa, lo)), wall((xa, hi), (xa, h)), wall((xb, 0), (xb, lo)),
                      wall((xb, hi), (xb, h)), wall((xa, lo), (xb, lo)), wall((xa, hi), (xb, hi))]
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


FAMILY = Family("movers", layout, "rooms and corridors whose doorways and corridors 1 to 3 moving obstacles cross")
