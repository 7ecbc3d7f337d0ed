"""Distances, contact normals and ray hits against a :class:`~robots.jaxworld.scene.Scene` — pure ``jax.numpy``.

One point (the robot's centre) or one ray at a time against every primitive; ``vmap`` does the rest. Padding
primitives are at distance ``inf`` and are never hit.
"""

from __future__ import annotations

import jax.numpy as jnp

from robots.jaxworld.scene import Scene

_TINY = 1e-12


def _closest_on_segments(p, a, b):
    """The closest points ``(..., 2)`` to ``p`` ``(2,)`` on the segments ``a``–``b`` ``(..., 2)``."""
    ab = b - a
    denom = jnp.sum(ab * ab, axis=-1)
    w = jnp.clip(jnp.sum((p - a) * ab, axis=-1) / jnp.where(denom > 0, denom, 1.0), 0.0, 1.0)
    return a + w[..., None] * ab


def _towards(p, q):
    """Distance ``|q - p|`` ``(...)`` and unit direction ``(..., 2)`` from ``p`` to the points ``q``."""
    delta = q - p
    dist = jnp.sqrt(jnp.maximum(jnp.sum(delta * delta, axis=-1), _TINY))
    return dist, delta / dist[..., None]


def gaps(p, scene: Scene):
    """Signed distance from the point ``p`` ``(2,)`` to the surface of every primitive, and the unit normal from
    ``p`` towards it.

    Returns ``gap`` ``(C + P,)`` — m from ``p`` to the capsule's surface (``|p - closest| - r``) or the polygon's
    (negative inside) — and ``normal`` ``(C + P, 2)``; padding reads ``inf``. The robot's disc of radius ``R``
    overlaps a primitive where ``gap < R``: the overlap is ``R - gap``, along ``normal``.
    """
    dist, n_cap = _towards(p, _closest_on_segments(p, scene.cap_a, scene.cap_b))
    gap_cap = jnp.where(scene.cap_on, dist - scene.cap_r, jnp.inf)

    v0 = scene.poly_v
    v1 = jnp.roll(v0, -1, axis=-2)
    e_dist, e_n = _towards(p, _closest_on_segments(p, v0, v1))  # (P, V), (P, V, 2)
    e_dist = jnp.where(scene.edge_on, e_dist, jnp.inf)
    nearest = jnp.argmin(e_dist, axis=-1)
    d_poly = jnp.min(e_dist, axis=-1)
    n_poly = jnp.take_along_axis(e_n, nearest[:, None, None], axis=-2)[:, 0]
    edge = v1 - v0
    cross = edge[..., 0] * (p[1] - v0[..., 1]) - edge[..., 1] * (p[0] - v0[..., 0])
    inside = jnp.all((cross >= 0) | ~scene.edge_on, axis=-1)
    real = jnp.any(scene.edge_on, axis=-1)
    gap_poly = jnp.where(real, jnp.where(inside, -d_poly, d_poly), jnp.inf)
    n_poly = jnp.where(inside[:, None], -n_poly, n_poly)
    return jnp.concatenate([gap_cap, gap_poly]), jnp.concatenate([n_cap, n_poly])


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _segment_gaps(p, q, a, b):
    """Distance between the segment ``p``–``q`` ``(2,)`` and the segments ``a``–``b`` ``(..., 2)``: 0 where they
    cross, else the least of the four end points' distances to the other segment."""
    ends = jnp.minimum(_towards(p, _closest_on_segments(p, a, b))[0], _towards(q, _closest_on_segments(q, a, b))[0])
    others = jnp.minimum(jnp.linalg.norm(a - _closest_on_segments(a, p, q), axis=-1),
                         jnp.linalg.norm(b - _closest_on_segments(b, p, q), axis=-1))
    d = jnp.minimum(ends, others)
    e, f = q - p, b - a
    s1, s2 = _cross(e, a - p), _cross(e, b - p)
    s3, s4 = _cross(f, p - a), _cross(f, q - a)
    crossing = (s1 * s2 < 0) & (s3 * s4 < 0)
    return jnp.where(crossing, 0.0, d)


def clearance(p, q, scene: Scene):
    """Least distance from the segment ``p``–``q`` ``(2,)`` to any primitive's surface (0 where it enters one;
    ``inf`` in an empty scene)."""
    cap = jnp.where(scene.cap_on, jnp.maximum(_segment_gaps(p, q, scene.cap_a, scene.cap_b) - scene.cap_r, 0.0),
                    jnp.inf)
    v0 = scene.poly_v
    edge = jnp.where(scene.edge_on, _segment_gaps(p, q, v0, jnp.roll(v0, -1, axis=-2)), jnp.inf)
    return jnp.minimum(jnp.min(cap), jnp.min(edge))


def _ray_segment(s, u, a, b):
    """Distance ``t >= 0`` along the ray ``s + t u`` to the segments ``a``–``b`` ``(..., 2)``; ``inf`` if missed."""
    e = b - a
    f = a - s
    den = u[0] * e[..., 1] - u[1] * e[..., 0]
    ok = jnp.abs(den) > _TINY
    den = jnp.where(ok, den, 1.0)
    t = (f[..., 0] * e[..., 1] - f[..., 1] * e[..., 0]) / den
    w = (f[..., 0] * u[1] - f[..., 1] * u[0]) / den
    return jnp.where(ok & (t >= 0) & (w >= 0) & (w <= 1), t, jnp.inf)


def _ray_circle(s, u, c, r):
    """Distance ``t >= 0`` along the ray to the first crossing of the circles ``(c, r)``; ``inf`` if missed."""
    f = s - c
    b = jnp.sum(f * u, axis=-1)
    disc = b * b - (jnp.sum(f * f, axis=-1) - r * r)
    t = -b - jnp.sqrt(jnp.maximum(disc, 0.0))
    return jnp.where((disc >= 0) & (t >= 0), t, jnp.inf)


def ray_hit(s, u, length, scene: Scene):
    """Distance along the ray from ``s`` ``(2,)`` in unit direction ``u`` ``(2,)`` to the first primitive within
    ``length`` m; ``inf`` if none. A ray that starts inside a shape reads 0 (as pymunk's segment query does).

    Capsules as Chipmunk's ``cpSegmentShapeSegmentQuery`` sees them: where the ray's segment (``s`` to
    ``s + length u``) passes between the ends of the capsule's side that faces ``s`` (the segment shifted by ``r``
    towards ``s``), that side alone is tested; elsewhere the two end circles. (A ray grazing a wall's end along
    the wall can so miss the end cap, in pymunk and here alike.) A circle (``a = b``) is a circle.
    Convex polygons: Cyrus–Beck clipping, ``t_in = max`` over entering edges of ``n·(v - s) / n·u``, hit when
    ``t_in <= t_out`` (outward normals ``n`` of the counter-clockwise edges), the edge crossing Chipmunk finds.
    """
    a, b, r = scene.cap_a, scene.cap_b, scene.cap_r
    inside_cap = jnp.sum((_closest_on_segments(s, a, b) - s) ** 2, axis=-1) <= r * r
    ab = b - a
    ln2 = jnp.sum(ab * ab, axis=-1)
    circle = ln2 <= _TINY
    n = jnp.stack([-ab[..., 1], ab[..., 0]], axis=-1) / jnp.sqrt(jnp.maximum(ln2, _TINY))[..., None]
    d = jnp.sum((a - s) * n, axis=-1)  # signed distance of the capsule's line from s, along n
    flipped = jnp.where((d > 0)[..., None], -n, n)
    near_a, near_b = a + flipped * r[..., None] - s, b + flipped * r[..., None] - s
    delta = u * length
    strip = _cross(delta, near_a) * _cross(delta, near_b) <= 0
    d_off = d + jnp.where(d > 0, -r, r)
    ad, bd = -d_off, jnp.sum(delta * n, axis=-1) - d_off
    crosses = ad * bd < 0
    t_side = jnp.where(crosses, ad / jnp.where(crosses, ad - bd, 1.0) * length, jnp.inf)
    ends = jnp.minimum(_ray_circle(s, u, a, r), _ray_circle(s, u, b, r))
    t_cap = jnp.where(circle, _ray_circle(s, u, a, r), jnp.where(strip, t_side, jnp.where(r > 0, ends, jnp.inf)))
    t_cap = jnp.where(inside_cap, 0.0, t_cap)
    t_cap = jnp.where(scene.cap_on, t_cap, jnp.inf)

    v0 = scene.poly_v
    edge = jnp.roll(v0, -1, axis=-2) - v0
    n_out = jnp.stack([edge[..., 1], -edge[..., 0]], axis=-1)  # (P, V, 2), outward for ccw
    num = jnp.sum(n_out * (v0 - s), axis=-1)
    den = jnp.sum(n_out * u, axis=-1)
    on = scene.edge_on
    safe = jnp.where(den == 0, 1.0, den)
    t_in = jnp.max(jnp.where(on & (den < 0), num / safe, 0.0), axis=-1)
    t_out = jnp.min(jnp.where(on & (den > 0), num / safe, jnp.inf), axis=-1)
    parallel_out = jnp.any(on & (den == 0) & (num < 0), axis=-1)
    hit = jnp.any(on, axis=-1) & (t_in <= t_out) & ~parallel_out
    t_poly = jnp.where(hit, t_in, jnp.inf)

    t = jnp.minimum(jnp.min(t_cap), jnp.min(t_poly))
    return jnp.where(t <= length, t, jnp.inf)
