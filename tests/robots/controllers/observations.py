"""Observations built by hand for the controller tests (not a test module)."""

import numpy as np

from robots.controllers.base import Observation


def observation(ir, target=(0.3, 0.25), t=0.0, target_id=0, pose=(0.5, 0.5, 0.0)):
    return Observation(t=np.float32(t), ir=np.asarray(ir, np.float32), target=np.asarray(target, np.float32),
                       target_id=np.int32(target_id), final=np.bool_(False), pose=np.asarray(pose, np.float32),
                       target_velocity=np.zeros(2, np.float32), markers=np.zeros((0, 5), np.float32))
