"""Movers on their paths and timed events, in JAX: a :class:`~robots.jaxworld.scene.Scene` placed at a time.

A scene keeps each mover's shapes around the mover's origin and each event's shapes tagged with their event
(:mod:`robots.jaxworld.scene`). :func:`placed` moves the first to where their paths put them at ``t`` and keeps the
second only once their event has fired — the scene the robot collides with and its IR sees then; the collision
and ray functions of :mod:`robots.jaxworld.collide` take it as they take a still one. Paths are those of
:mod:`robots.worldfile`: a line at ``speed`` from ``a`` to ``b`` (back and forth if ``bounce``, else it stops at
``b``), or a circle of ``radius`` round ``a`` at turn rate ``rate`` from angle ``phase``.

An event fires as :class:`robots.world.PymunkWorld` fires it: at the first sub-step starting at or after its time
with the robot's body clear of every shape it adds (a door that shuts on the robot waits until it has left the
doorway). Pure functions; times in s (float32, ``k dt``), lengths in m.
"""

from __future__ import annotations

import jax.numpy as jnp

from robots.jaxworld.scene import Paths, Scene

#: Slack (s) on an event's time: a time of ``k dt`` in float32 may land a rounding below the event's.
EVENT_SLACK = 1e-5

#: Where a padding marker stands (m): far beyond any sensor's range and any world, still, of radius 0.
FAR = 1.0e4


def _line(paths: Paths, t):
    """Fraction ``s`` along each line path and its direction of travel (+1 out, -1 back, 0 stopped), ``(M,)``."""
    length = jnp.linalg.norm(paths.b - paths.a, axis=-1)
    travelled = paths.rate * t / jnp.where(length > 0, length, 1.0)
    phase = jnp.mod(travelled, 2.0)
    s = jnp.where(paths.bounce, jnp.where(phase <= 1.0, phase, 2.0 - phase), jnp.minimum(travelled, 1.0))
    sign = jnp.where(paths.bounce, jnp.where(phase <= 1.0, 1.0, -1.0), jnp.where(travelled < 1.0, 1.0, 0.0))
    return jnp.where(length > 0, s, 0.0), jnp.where(length > 0, sign, 0.0), length


def positions(paths: Paths, t):
    """Each path's point ``(M, 2)`` at time ``t`` (:meth:`robots.worldfile.LinePath.position`,
    :meth:`~robots.worldfile.CirclePath.position`)."""
    s, _, _ = _line(paths, t)
    line = paths.a + s[:, None] * (paths.b - paths.a)
    angle = paths.phase + paths.rate * t
    circle = paths.a + paths.radius[:, None] * jnp.stack([jnp.cos(angle), jnp.sin(angle)], axis=-1)
    return jnp.where(paths.circle[:, None], circle, line)


def velocities(paths: Paths, t):
    """Each path's velocity ``(M, 2)`` (m/s) at time ``t`` (the paths' ``velocity``)."""
    _, sign, length = _line(paths, t)
    line = (sign * paths.rate / jnp.where(length > 0, length, 1.0))[:, None] * (paths.b - paths.a)
    angle = paths.phase + paths.rate * t
    w = paths.rate * paths.radius
    circle = jnp.stack([-w * jnp.sin(angle), w * jnp.cos(angle)], axis=-1)
    return jnp.where(paths.circle[:, None], circle, line)


def _at(index, values, default):
    """``values[index]`` where ``index >= 0``, else ``default`` (rows of ``values`` ``(M, ...)``)."""
    got = values[jnp.maximum(index, 0)]
    return jnp.where((index >= 0).reshape(index.shape + (1,) * (got.ndim - index.ndim)), got, default)


def live(scene: Scene, fired):
    """Whether each primitive is in the world ``(C + P,)``: still ones always, an event's once it ``fired``
    ``(E,)``."""
    return jnp.concatenate([_at(scene.cap_event, fired, True), _at(scene.poly_event, fired, True)])


def moved(scene: Scene, t) -> Scene:
    """``scene`` with every mover's primitives where its path has taken it at ``t`` (events' all kept)."""
    pos = positions(scene.paths, t)
    cap = _at(scene.cap_mover, pos, 0.0)
    poly = _at(scene.poly_mover, pos, 0.0)
    return scene._replace(cap_a=scene.cap_a + cap, cap_b=scene.cap_b + cap, poly_v=scene.poly_v + poly[:, None, :])


def placed(scene: Scene, t, fired) -> Scene:
    """The world as it is at ``t`` with the events ``fired`` ``(E,)``: movers moved (:func:`moved`), the shapes of
    events not yet fired left out."""
    scene = moved(scene, t)
    c = scene.cap_on.shape[-1]
    on = live(scene, fired)
    return scene._replace(cap_on=scene.cap_on & on[:c], edge_on=scene.edge_on & on[c:, None])


def primitive_velocities(scene: Scene, t0, t1):
    """Each primitive's velocity ``(C + P, 2)`` over ``[t0, t1]``: its mover's displacement over the interval
    divided by it, as a kinematic body is given its velocity in pymunk (0 for a still one)."""
    v = (positions(scene.paths, t1) - positions(scene.paths, t0)) / (t1 - t0)
    return jnp.concatenate([_at(scene.cap_mover, v, 0.0), _at(scene.poly_mover, v, 0.0)])


def is_still(scene: Scene):
    """Whether each primitive stands still ``(C + P,)`` (no mover carries it)."""
    return jnp.concatenate([scene.cap_mover < 0, scene.poly_mover < 0])


def has_movers(scene: Scene):
    """Whether ``scene`` has a real mover (a primitive one carries)."""
    return jnp.any(scene.cap_mover >= 0) | jnp.any(scene.poly_mover >= 0)


def due(scene: Scene, t, fired, gap, radius: float):
    """``fired`` ``(E,)`` after the events due at ``t`` whose every shape is at least ``radius`` from the robot's
    centre: ``gap`` ``(C + P,)`` the centre's distance to every primitive's surface, events' included."""
    event = jnp.concatenate([scene.cap_event, scene.poly_event])
    real = jnp.concatenate([scene.cap_on, jnp.any(scene.edge_on, axis=-1)])
    ids = jnp.arange(scene.event_at.shape[-1])
    near = jnp.min(jnp.where((event[None, :] == ids[:, None]) & real[None, :], gap[None, :], jnp.inf), axis=1)
    return fired | ((scene.event_at <= t + EVENT_SLACK) & (near >= radius))


def markers(scene: Scene, t, radii):
    """The declared movers as the controller's object markers ``(M, 5)`` — (x, y, vx, vy, radius), world frame,
    as :func:`evaluation.scenario._markers` makes them, ``radii`` ``(M,)`` their discs' — where a radius is < 0
    (padding, a world with fewer movers than its batch's) a still marker at :data:`FAR` of radius 0."""
    pos, vel = positions(scene.paths, t), velocities(scene.paths, t)
    real = radii >= 0
    rows = jnp.concatenate([pos, vel, jnp.maximum(radii, 0.0)[:, None]], axis=1)
    pad = jnp.concatenate([jnp.full(pos.shape, FAR), jnp.zeros((pos.shape[0], 3))], axis=1)
    return jnp.where(real[:, None], rows, pad).astype(jnp.float32)
