"""Command fusion (robots.controllers.fusion, Eq. 4.11)."""

import jax.numpy as jnp
import numpy as np

from ekm import indirect
from robots.controllers import fusion
from tests.robots.controllers.observations import observation


def fusion_controller(signed_map, **params):
    ekm, cfg = signed_map
    return fusion.build(fusion.FusionParams(**params), ekm, cfg)


def test_fusion_without_obstacles_sends_beta_times_the_map_command(signed_map):
    ekm, cfg = signed_map
    ctl = fusion_controller(signed_map, beta=0.85)
    obs = observation(np.full(8, np.inf))
    _, c = ctl.step(ctl.init(), obs)
    c_p, _ = indirect.control(ekm, jnp.asarray(obs.target), cfg)
    np.testing.assert_allclose(np.asarray(c), 0.85 * np.asarray(c_p), rtol=1e-6)


def test_fusion_target_reaching_keeps_its_period_and_reacts_at_once_to_a_new_checkpoint(signed_map):
    ctl = fusion_controller(signed_map, refresh="clock", period=1.024)
    free = np.full(8, np.inf)
    state, c0 = ctl.step(ctl.init(), observation(free, target=(0.3, 0.25), t=0.0))
    state, c1 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=0.128))  # same checkpoint id: held
    np.testing.assert_array_equal(np.asarray(c0), np.asarray(c1))
    _, c2 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=0.256, target_id=1))  # new checkpoint
    assert not np.allclose(np.asarray(c2), np.asarray(c1))
    _, c3 = ctl.step(state, observation(free, target=(-1.0, 0.1), t=1.024))  # period up
    np.testing.assert_array_equal(np.asarray(c3), np.asarray(c2))


def test_fusion_with_refresh_sensed_recomputes_target_reaching_while_an_obstacle_is_sensed(signed_map):
    ir = np.full(8, np.inf)
    ir[0] = 0.04  # a wall on the left, not ahead
    for refresh, changes in (("clock", False), ("sensed", True)):
        ctl = fusion_controller(signed_map, refresh=refresh)
        state, _ = ctl.step(ctl.init(), observation(ir, target=(0.3, 0.25), t=0.0))
        state, _ = ctl.step(state, observation(ir, target=(-1.0, 0.1), t=0.128))
        held = np.asarray(state.c_p)
        c_new, _ = indirect.control(signed_map[0], jnp.asarray([-1.0, 0.1]), signed_map[1])
        assert np.allclose(held, np.asarray(c_new)) == changes
