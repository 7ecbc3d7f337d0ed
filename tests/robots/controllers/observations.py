"""Observations built by hand for the controller tests (not a test module)."""

import numpy as np

from robots.controllers.base import Observation
from robots.params import LONG_RANGE


def observation(ir, target=(0.3, 0.25), t=0.0, target_id=0, pose=(0.5, 0.5, 0.0), final=False, markers=None):
    return Observation(t=np.float32(t), ir=np.asarray(ir, np.float32), target=np.asarray(target, np.float32),
                       target_id=np.int32(target_id), final=np.bool_(final), pose=np.asarray(pose, np.float32),
                       target_velocity=np.zeros(2, np.float32),
                       markers=np.zeros((0, 5), np.float32) if markers is None else np.asarray(markers, np.float32))


def long_ring(**readings):
    """Long-ring readings (m from the body surface), nothing seen but the sensors given by index: ``s0=0.02``
    is 2 cm straight ahead, ``s1`` 30° to the left, ``s11`` 30° to the right."""
    ir = np.full(len(LONG_RANGE.angles), np.inf)
    for name, value in readings.items():
        ir[int(name[1:])] = value
    return ir
