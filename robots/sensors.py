"""IR range sensors: where the rays go and what a reading is — pure functions, NumPy or JAX.

A sensor sits on the body's rim and looks outwards along its direction (``SensorSet.angles``, robot frame,
0 = ahead, + = left). Its reading is the distance from the body surface to the first obstacle along the
ray, as the thesis's long-range sensors report it (ch. 6.2.2: 17.5 cm range from a 2.5 cm body "enabling
the detection of obstacles at 20 cm or nearer from the robot center"):

1. 10 % multiplicative noise, ``d (1 + σ ξ)`` with ``ξ ~ N(0, 1)`` (thesis ch. 6.1, Webots);
2. quantised to the resolution ``τ`` = 0.5 cm (round to nearest; ch. 6.2.2: "to simulate noise, the
   sensors have a resolution of τ = 0.5 cm");
3. clipped to ``[0, range]``.

**Nothing within range reads ``inf``** (not ``range``): "no obstacle" stays distinguishable from "an
obstacle at the edge of the range", and ``inf`` drops out of ``min``-style obstacle fields naturally.
The ray casting itself lives with the world (:meth:`robots.world.PymunkWorld.ranges`); this module is
what both the world and any synthetic-sensor code share.
"""

from __future__ import annotations

import numpy as np

from robots.params import KHEPERA, SensorSet


def sensor_rays(pose, sensors: SensorSet, radius: float = KHEPERA.radius, xp=np):
    """Start (on the rim) and end (``range_m`` further out) of every sensor ray.

    Parameters
    ----------
    pose : array ``(..., 3)``
        Robot pose (x, y, θ).
    sensors : SensorSet
        Sensor directions and range.
    radius : float
        Body radius: the rays start on the body surface.

    Returns
    -------
    start, end : arrays ``(..., m, 2)`` for the ``m`` sensors.
    """
    pose = xp.asarray(pose)
    phi = pose[..., 2:3] + xp.asarray(sensors.angles)  # (..., m) world directions
    direction = xp.stack([xp.cos(phi), xp.sin(phi)], axis=-1)
    centre = pose[..., None, :2]
    return centre + radius * direction, centre + (radius + sensors.range_m) * direction


def ir_readings(distances, noise, sensors: SensorSet, xp=np):
    """Sensor readings for true surface ``distances`` ``(..., m)`` with standard-normal ``noise`` ``(..., m)``.

    ``reading = clip(τ · round(d (1 + σ ξ) / τ), 0, range)``; ``inf`` where ``d`` is ``inf`` or beyond
    the range (nothing seen). Pass ``noise = 0`` for noise-free (still quantised) readings.
    """
    d = xp.asarray(distances)
    seen = d <= sensors.range_m
    finite_d = xp.where(seen, d, 0.0)  # keep inf out of the arithmetic (and out of JAX gradients)
    noisy = finite_d * (1.0 + sensors.noise * xp.asarray(noise))
    if sensors.resolution_m > 0:
        noisy = xp.round(noisy / sensors.resolution_m) * sensors.resolution_m
    return xp.where(seen, xp.clip(noisy, 0.0, sensors.range_m), xp.inf)
