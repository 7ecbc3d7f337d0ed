"""A world as padded arrays: what the JAX engine collides with and casts its IR rays against.

Every shape of a :class:`~robots.worldfile.World` becomes one of two primitives, as pymunk holds it:

- a **capsule** — the points within ``r`` of the segment ``a``–``b``: a wall (the border and ``walls``, ``r`` =
  half the world's ``wall_thickness``, as ``pymunk.Segment``'s radius), a ``segment`` obstacle (``r`` = 0) or a
  ``circle`` (``a`` = ``b`` = its centre, ``r`` its radius);
- a **convex polygon** — a ``box``, or one convex piece of a ``polygon`` (the pieces of
  :func:`robots.world.convex_pieces`, Chipmunk's exact decomposition, as pymunk gets them), counter-clockwise.

Arrays are padded to fixed sizes — ``C`` capsules, ``P`` polygons of ``V`` vertices — with a mask, so that worlds of
different sizes and shapes share one batch (:func:`stack_scenes`) and one compiled program. Lengths in metres.

Moving obstacles, timed events and moving goals are not represented: :func:`scene_of` refuses a world that has them
(:class:`ekm.errors.InputError`, one line); run such worlds on the pymunk engine.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ekm.errors import InputError
from robots.geometry import Box, Circle, Polygon, Segment, signed_area
from robots.worldfile import World


class Scene(NamedTuple):
    """Padded primitives of one world (or, stacked, of a batch: a leading axis on every leaf).

    ``cap_a``, ``cap_b`` ``(C, 2)``: capsule end points; ``cap_r`` ``(C,)``: radii; ``cap_on`` ``(C,)``: real
    (not padding). ``poly_v`` ``(P, V, 2)``: polygon vertices, counter-clockwise; ``edge_on`` ``(P, V)``: edge
    ``j`` (vertex ``j`` to ``j + 1`` mod the polygon's count) is real. A polygon without real edges is padding.
    """

    cap_a: object
    cap_b: object
    cap_r: object
    cap_on: object
    poly_v: object
    edge_on: object


def unsimulated(world: World) -> list[str]:
    """What ``world`` has that the JAX engine does not simulate: "moving obstacles", "timed events", "a moving
    goal" (empty: it runs)."""
    return [what for what, has in (("moving obstacles", world.moving), ("timed events", world.events),
                                   ("a moving goal", world.moving_goal)) if has]


def refuse_unsimulated(world: World) -> None:
    """Raise :class:`InputError` — one line naming the world and all it has that the engine does not simulate —
    unless :func:`unsimulated` is empty."""
    what = unsimulated(world)
    if what:
        listed = what[0] if len(what) == 1 else ", ".join(what[:-1]) + " and " + what[-1]
        raise InputError(f"engine jax: world {world.name!r} has {listed}, which the JAX engine does not simulate; "
                         f"use the pymunk engine")


def primitives(world: World) -> tuple[list, list]:
    """The world's capsules ``[(a, b, r)]`` and convex polygons ``[vertices (k, 2), ccw]``, pymunk's shapes."""
    from robots.world import convex_pieces

    refuse_unsimulated(world)
    half = 0.5 * world.wall_thickness
    caps = [(w.start, w.end, half) for w in world.border + world.walls]
    polys = []
    for shape in world.obstacles + world.unforeseen:
        if isinstance(shape, Circle):
            caps.append((shape.center, shape.center, shape.radius))
        elif isinstance(shape, Segment):
            caps.append((shape.start, shape.end, 0.0))
        elif isinstance(shape, Box):
            polys.append(shape.vertices())
        elif isinstance(shape, Polygon):
            polys.extend(convex_pieces(shape.vertices()))
        else:
            raise TypeError(f"not a world shape: {shape!r}")
    polys = [np.asarray(v, float) if signed_area(v) > 0 else np.asarray(v, float)[::-1] for v in polys]
    return caps, polys


def sizes(world: World) -> tuple[int, int, int]:
    """``(C, P, V)``: the world's capsules, convex polygons and most vertices of one polygon (at least 1 each)."""
    caps, polys = primitives(world)
    return max(1, len(caps)), max(1, len(polys)), max([3] + [len(v) for v in polys])


def scene_of(world: World, shape: tuple[int, int, int] | None = None) -> Scene:
    """The :class:`Scene` of ``world`` as float32 NumPy arrays, padded to ``shape`` = ``(C, P, V)`` (default: its
    own :func:`sizes`). A world larger than ``shape`` raises ValueError."""
    caps, polys = primitives(world)
    c, p, v = sizes(world) if shape is None else shape
    if len(caps) > c or len(polys) > p or any(len(q) > v for q in polys):
        raise ValueError(f"world {world.name!r} does not fit a scene of shape {(c, p, v)}: {sizes(world)}")
    cap_a, cap_b = np.zeros((c, 2), np.float32), np.zeros((c, 2), np.float32)
    cap_r, cap_on = np.zeros(c, np.float32), np.zeros(c, bool)
    for i, (a, b, r) in enumerate(caps):
        cap_a[i], cap_b[i], cap_r[i], cap_on[i] = a, b, r, True
    poly_v, edge_on = np.zeros((p, v, 2), np.float32), np.zeros((p, v), bool)
    for i, q in enumerate(polys):
        k = len(q)
        poly_v[i, :k], poly_v[i, k:] = q, q[0]  # padding vertices repeat the first: the closing edge stays real
        edge_on[i, :k] = True
    return Scene(cap_a, cap_b, cap_r, cap_on, poly_v, edge_on)


def stack_scenes(worlds) -> Scene:
    """The scenes of ``worlds`` padded to one shape and stacked: every leaf gains a leading axis ``(B, ...)``."""
    worlds = list(worlds)
    shape = tuple(int(s) for s in np.max([sizes(w) for w in worlds], axis=0))
    scenes = [scene_of(w, shape) for w in worlds]
    return Scene(*(np.stack(leaves) for leaves in zip(*scenes)))
