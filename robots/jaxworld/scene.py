"""A world as padded arrays: what the JAX engine collides with and casts its IR rays against.

Every shape of a :class:`~robots.worldfile.World` becomes one of two primitives, as pymunk holds it:

- a **capsule** — the points within ``r`` of the segment ``a``–``b``: a wall (the border and ``walls``, ``r`` =
  half the world's ``wall_thickness``, as ``pymunk.Segment``'s radius), a ``segment`` obstacle (``r`` = 0) or a
  ``circle`` (``a`` = ``b`` = its centre, ``r`` its radius);
- a **convex polygon** — a ``box``, or one convex piece of a ``polygon`` (the pieces of
  :func:`robots.world.convex_pieces`, Chipmunk's exact decomposition, as pymunk gets them), counter-clockwise.

Arrays are padded to fixed sizes — ``C`` capsules, ``P`` polygons of ``V`` vertices — with a mask, so that worlds of
different sizes and shapes share one batch (:func:`stack_scenes`) and one compiled program. Lengths in metres.

Moving obstacles and timed events are primitives too, tagged: a mover's shapes are kept around its own origin with
the index of the mover that carries them (``cap_mover``, ``poly_mover``), its path as padded arrays (``paths``:
a line, there and back or once, or a circle, as :class:`~robots.worldfile.LinePath` and
:class:`~robots.worldfile.CirclePath` hold them); an event's shapes carry the index of their event (``cap_event``,
``poly_event``) and its time (``event_at``) and whether the planner is told (``event_known``).
:mod:`robots.jaxworld.moving` places them at a time. A moving goal is the task's, not the scene's (its path as
:class:`Paths`, :func:`paths_of`).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import numpy as np

from robots.geometry import Box, Circle, Polygon, Segment, signed_area
from robots.worldfile import World


class Paths(NamedTuple):
    """Paths as arrays ``(M,)`` — the movers' (a :class:`Scene`'s ``paths``) or a moving goal's — which
    :func:`robots.jaxworld.moving.positions` reads: ``circle`` (else a line), ``a`` ``(M, 2)`` the line's start or
    the circle's centre, ``b`` ``(M, 2)`` the line's end, ``rate`` the line's speed (m/s) or the circle's signed turn
    rate (rad/s, + counter-clockwise), ``bounce`` (the line back and forth), ``radius``, ``phase`` (rad)."""

    circle: object
    a: object
    b: object
    rate: object
    bounce: object
    radius: object
    phase: object


class Scene(NamedTuple):
    """Padded primitives of one world (or, stacked, of a batch: a leading axis on every leaf).

    ``cap_a``, ``cap_b`` ``(C, 2)``: capsule end points; ``cap_r`` ``(C,)``: radii; ``cap_on`` ``(C,)``: real
    (not padding). ``poly_v`` ``(P, V, 2)``: polygon vertices, counter-clockwise; ``edge_on`` ``(P, V)``: edge
    ``j`` (vertex ``j`` to ``j + 1`` mod the polygon's count) is real. A polygon without real edges is padding.

    Movers and events (``M`` paths, ``E`` events, at least one of each, padding inert): ``cap_mover`` ``(C,)``,
    ``poly_mover`` ``(P,)`` int32 — the mover carrying the primitive (its coordinates then around the mover's
    origin), -1 for a still one; ``cap_event``, ``poly_event`` — the event that adds it, -1 for one there from the
    start. ``paths``: the movers' :class:`Paths` ``(M,)``. Events ``(E,)``: ``event_at`` (s; ``inf`` for padding),
    ``event_known``.
    """

    cap_a: object
    cap_b: object
    cap_r: object
    cap_on: object
    poly_v: object
    edge_on: object
    cap_mover: object
    poly_mover: object
    cap_event: object
    poly_event: object
    paths: Paths
    event_at: object
    event_known: object


def _pieces(shape, mover: int, event: int, caps: list, polys: list) -> None:
    """Append ``shape``'s primitives, tagged ``(mover, event)``, to ``caps`` ``[(a, b, r, mover, event)]`` and
    ``polys`` ``[(vertices (k, 2) ccw, mover, event)]``."""
    from robots.world import convex_pieces

    if isinstance(shape, Circle):
        caps.append((shape.center, shape.center, shape.radius, mover, event))
    elif isinstance(shape, Segment):
        caps.append((shape.start, shape.end, 0.0, mover, event))
    elif isinstance(shape, (Box, Polygon)):
        pieces = [shape.vertices()] if isinstance(shape, Box) else convex_pieces(shape.vertices())
        for v in pieces:
            v = np.asarray(v, float)
            polys.append((v if signed_area(v) > 0 else v[::-1], mover, event))
    else:
        raise TypeError(f"not a world shape: {shape!r}")


def primitives(world: World) -> tuple[list, list]:
    """The world's capsules ``[(a, b, r, mover, event)]`` and convex polygons ``[(vertices (k, 2) ccw, mover,
    event)]``, pymunk's shapes: the still ones (mover and event -1), each mover's around its origin, each event's."""
    half = 0.5 * world.wall_thickness
    caps = [(w.start, w.end, half, -1, -1) for w in world.border + world.walls]
    polys: list = []
    for shape in world.obstacles + world.unforeseen:
        _pieces(shape, -1, -1, caps, polys)
    for i, m in enumerate(world.moving):
        _pieces(m.shape, i, -1, caps, polys)
    for i, e in enumerate(world.events):
        for shape in e.add:
            _pieces(shape, -1, i, caps, polys)
    return caps, polys


def sizes(world: World) -> tuple[int, int, int, int, int]:
    """``(C, P, V, M, E)``: the world's capsules, convex polygons, most vertices of one polygon, movers and events
    (at least 1 each, 3 vertices)."""
    caps, polys = primitives(world)
    return (max(1, len(caps)), max(1, len(polys)), max([3] + [len(v) for v, _, _ in polys]),
            max(1, len(world.moving)), max(1, len(world.events)))


def paths_of(paths, m: int) -> Paths:
    """``paths`` (:class:`~robots.worldfile.LinePath`, :class:`~robots.worldfile.CirclePath`) as :class:`Paths`
    arrays, padded to ``m`` (padding stands at the origin)."""
    from robots.worldfile import CirclePath

    circle, a, b = np.zeros(m, bool), np.zeros((m, 2), np.float32), np.zeros((m, 2), np.float32)
    rate, bounce = np.zeros(m, np.float32), np.zeros(m, bool)
    radius, phase = np.zeros(m, np.float32), np.zeros(m, np.float32)
    for i, path in enumerate(paths):
        if isinstance(path, CirclePath):
            circle[i], a[i], radius[i], phase[i] = True, path.center, path.radius, path.phase
            rate[i] = (1.0 if path.direction == "ccw" else -1.0) * 2.0 * np.pi / path.period_s
        else:
            a[i], b[i], rate[i], bounce[i] = path.start, path.end, path.speed_mps, path.bounce
    return Paths(circle, a, b, rate, bounce, radius, phase)


def scene_of(world: World, shape: tuple | None = None) -> Scene:
    """The :class:`Scene` of ``world`` as float32 NumPy arrays, padded to ``shape`` = ``(C, P, V, M, E)`` (default:
    its own :func:`sizes`; a shape of three, ``(C, P, V)``, keeps one mover and one event slot). A world larger
    than ``shape`` raises ValueError."""
    caps, polys = primitives(world)
    c, p, v, m, e = (sizes(world) if shape is None else tuple(shape) + (1, 1)[len(shape) - 3:])
    if (len(caps) > c or len(polys) > p or any(len(q) > v for q, _, _ in polys) or len(world.moving) > m
            or len(world.events) > e):
        raise ValueError(f"world {world.name!r} does not fit a scene of shape {(c, p, v, m, e)}: {sizes(world)}")
    cap_a, cap_b = np.zeros((c, 2), np.float32), np.zeros((c, 2), np.float32)
    cap_r, cap_on = np.zeros(c, np.float32), np.zeros(c, bool)
    cap_mover, cap_event = np.full(c, -1, np.int32), np.full(c, -1, np.int32)
    for i, (a, b, r, mover, event) in enumerate(caps):
        cap_a[i], cap_b[i], cap_r[i], cap_on[i], cap_mover[i], cap_event[i] = a, b, r, True, mover, event
    poly_v, edge_on = np.zeros((p, v, 2), np.float32), np.zeros((p, v), bool)
    poly_mover, poly_event = np.full(p, -1, np.int32), np.full(p, -1, np.int32)
    for i, (q, mover, event) in enumerate(polys):
        k = len(q)
        poly_v[i, :k], poly_v[i, k:] = q, q[0]  # padding vertices repeat the first: the closing edge stays real
        edge_on[i, :k], poly_mover[i], poly_event[i] = True, mover, event
    event_at, event_known = np.full(e, np.inf, np.float32), np.zeros(e, bool)
    for i, ev in enumerate(world.events):
        event_at[i], event_known[i] = ev.at_s, ev.known
    return Scene(cap_a, cap_b, cap_r, cap_on, poly_v, edge_on, cap_mover, poly_mover, cap_event, poly_event,
                 paths_of([mv.path for mv in world.moving], m), event_at, event_known)


def stack(trees):
    """Scenes (or :class:`Paths`) of one shape stacked: every leaf gains a leading axis ``(B, ...)``."""
    return jax.tree.map(lambda *leaves: np.stack(leaves), *trees)


def stack_scenes(worlds) -> Scene:
    """The scenes of ``worlds`` padded to one shape and stacked: every leaf gains a leading axis ``(B, ...)``."""
    worlds = list(worlds)
    shape = tuple(int(s) for s in np.max([sizes(w) for w in worlds], axis=0))
    return stack([scene_of(w, shape) for w in worlds])


def shape_of(scene: Scene) -> tuple[int, int, int, int, int]:
    """``(C, P, V, M, E)`` of one (unstacked) scene: the shape :func:`scene_of` pads to."""
    return (scene.cap_a.shape[-2], scene.poly_v.shape[-3], scene.poly_v.shape[-2], scene.paths.a.shape[-2],
            scene.event_at.shape[-1])


def has_dynamics(world: World) -> bool:
    """Whether ``world`` has movers or timed events (a batch of such worlds steps them)."""
    return bool(world.moving or world.events)
