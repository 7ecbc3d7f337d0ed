"""Both mappings behind one interface (ekm.maps): dispatch on the configured mapping; untrained maps start from
the forward prior, drive straight and cannot steer."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from ekm import direct, indirect, maps
from ekm.config import EKMConfig


def test_maps_dispatch_on_the_configured_mapping():
    for mapping, cls in (("direct", direct.DirectEKM), ("indirect", indirect.IndirectEKM)):
        cfg = EKMConfig(mapping=mapping, neurons=4)
        assert isinstance(maps.init(cfg), cls)


PI = math.pi


def test_untrained_maps_start_from_the_forward_prior():
    cfg = EKMConfig(neurons=3, forward_init=0.5)
    m = indirect.init(cfg)
    np.testing.assert_allclose(np.asarray(m.M), np.broadcast_to(0.5 * np.float32([[0, 0.16], [0, 0.16]]), (9, 2, 2)))
    d = direct.init(cfg)
    # c_i = 0.5 M_fwd w̃_i (signed chart): both wheels 0.08 · d_i / d_scale ahead, minus that behind.
    dist = np.asarray(d.w)[:, 1] / cfg.d_scale
    behind = np.abs(np.asarray(d.w)[:, 0]) > PI / 2
    want = 0.08 * np.where(behind, -dist, dist)
    np.testing.assert_allclose(np.asarray(d.c), np.stack([want, want], axis=1), atol=1e-6)


@pytest.mark.parametrize("chart", ["signed", "polar"])
@pytest.mark.parametrize("mapping", ["direct", "indirect"])
def test_untrained_maps_drive_straight_and_cannot_steer(mapping, chart):
    """The forward reflex only breaks the forward/backward symmetry; it does not reach targets. In the
    signed chart it drives straight back to targets behind, in the polar chart always forwards."""
    cfg = EKMConfig(mapping=mapping, chart=chart)
    ekm = maps.init(cfg)
    for alpha in (-2.5, -1.0, 0.0, 0.7, 3.0):
        left, right = np.asarray(maps.control(ekm, jnp.asarray([alpha, 0.08]), cfg)[0], dtype=float)
        assert left == pytest.approx(right, abs=1e-4)  # no turning, whatever the direction
        forwards = chart == "polar" or abs(alpha) < np.pi / 2
        assert (left > 0.0) if forwards else (left < 0.0)
