"""Obstacle avoidance with a Braitenberg type-3C vehicle, c_o = Z u_o (thesis ch. 4.4, Eq. 4.10, Fig. 4.3).

u_o is the sensors' activation (:func:`robots.controllers.base.proximity`: 0 = nothing in range, 1 =
contact) and Z = [z_ij] a 2 × m matrix, row 0 the left motor, row 1 the right. Fig. 4.3 gives only the
signs: "the connections between the forward-facing sensors on one side of the robot's body with the
motor on the opposite side have large negative values, while the other connections have small positive
values". :func:`z_matrix` builds Z from the sensor directions, so one rule serves the 8 short-range and
the 12 long-range sensors:

- a *forward-facing* sensor (|φ| ≤ ``front``, 60° by default: the Khepera's ±10° and ±45° sensors; the
  0°, ±30°, ±60° ones of the long-range ring) drives the opposite motor with ``-cross`` and its own side's
  motor with ``+same``. A sensor straight ahead (φ = 0) belongs to both sides and splits both weights
  evenly, so an obstacle dead ahead only brakes — the symmetric case the thesis's trap figures show;
- every other sensor (the sides, the back) drives its own side's motor with ``+same`` and the opposite
  motor with ``+same/2``: an obstacle beside or behind the robot speeds it up and steers it gently away
  ("the robot detected a wall on its right and deviated slightly to the left", ch. 6.2.1). A sensor
  straight behind splits its weights evenly, like one straight ahead.

So an obstacle ahead-left makes the right motor run backward faster than the left runs forward and the
robot turns right, away from it (ch. 4.4). The gains are in m/s at full activation; command fusion
(:mod:`robots.controllers.fusion`) scales them by (1 − β).
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from ekm.angles import wrap
from robots.params import SensorSet

#: Sensors within this angle of straight ahead are forward-facing (Fig. 4.3).
FRONT = math.radians(60.0)


def z_matrix(sensors: SensorSet, cross: float, same: float, front: float = FRONT,
             backward: bool = False) -> np.ndarray:
    """Z ``(2, m)`` of Eq. 4.10 for ``sensors`` (see the module docstring): ``-cross`` from each forward-facing
    sensor to the opposite motor and ``+same`` to its own; small positive weights from the others.

    ``backward=True`` gives the vehicle that drives the other way round (an extension): the rule applied with
    the back as the front, so the sensors facing the way a reversing robot goes brake it and turn it away. It
    is the forward vehicle seen from behind: sensor angles φ - π, the motors' roles swapped (the robot's left
    is the reversed vehicle's right) and their signs flipped (its forward is the robot's backward)."""
    if not (cross >= 0 and same >= 0):
        raise ValueError(f"Braitenberg gains must be >= 0, got cross={cross}, same={same}")
    z = np.zeros((2, len(sensors.angles)), dtype=np.float32)
    for j, phi in enumerate(sensors.angles):
        phi = wrap(phi - math.pi if backward else phi)
        # How much of the sensor is on the left: 1 left, 0 right, 1/2 straight ahead or straight behind.
        left = 0.5 if min(abs(phi), math.pi - abs(phi)) < 1e-9 else (1.0 if phi > 0 else 0.0)
        own, opposite = (same, -cross) if abs(phi) <= front + 1e-9 else (same, 0.5 * same)
        z[0, j] = left * own + (1.0 - left) * opposite  # left motor
        z[1, j] = (1.0 - left) * own + left * opposite  # right motor
    return -z[::-1].copy() if backward else z


def avoid(z, u_o):
    """c_o = Z u_o (Eq. 4.10): wheel speeds ``(2,)`` (m/s) from sensor activations ``u_o`` ``(m,)``."""
    return jnp.asarray(z) @ u_o
