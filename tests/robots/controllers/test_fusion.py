"""Command fusion (robots.controllers.fusion, Eq. 4.11)."""

import jax.numpy as jnp
import numpy as np
import pytest

from ekm import indirect
from evaluation.scenario import ScenarioConfig, run_architecture
from robots.controllers import fusion
from robots.controllers.spec import parse_architecture
from tests.robots.controllers.observations import observation
from tests.robots.controllers.worlds import dead_end


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


def test_fusion_reaches_a_goal_beside_a_wall_only_when_it_avoids_nothing_beyond_the_goal():
    """The goal 1.5 cm (body to wall) from a wall: every forward sensor reads the wall there (5 cm range). Avoiding
    every reading (ch. 4.5), (1 − β) Z u_o holds the robot more than a centimetre off the goal for the whole run;
    avoiding none beyond the goal, it stops within the 5 mm of ch. 6.2.1, untouched."""
    config = ScenarioConfig(time_limit=30.0, recover=False)
    near = run_architecture(dead_end(0.015), parse_architecture("fusion"), seed=0, config=config)
    assert near.reached and near.collisions == 0 and near.final_distance_m < 0.005
    every = run_architecture(dead_end(0.015), parse_architecture("fusion:avoid=all"), seed=0, config=config)
    assert not every.arrived and every.collisions == 0 and every.final_distance_m > 0.01


@pytest.mark.parametrize("sensor, front, travel", [
    (7, (0.4, 0.2), (-0.4, 4.0)),  # 160°: the reversed vehicle's forward sensor at 20°
    (5, (0.2, 0.4), (4.0, -0.4)),  # -85°: at 95° from the way back, within back_cone's 100°
])
def test_fusion_turns_z_round_while_target_reaching_reverses(signed_map, sensor, front, travel):
    """Something 2 cm from a sensor of a robot the map drives backward: ch. 4.4's Z (``facing=front``) answers with
    its small positive weights × u; turned round (``travel``) with the reversed vehicle's -cross to the opposite
    motor and +same to its own, signs flipped (hand-worked in test_braitenberg): the rear sensor 160° on the left
    brakes and turns the robot left, the side sensor on the right brakes and turns it right. Driving forward, both
    are ch. 4.4's."""
    ekm, cfg = signed_map
    ir = np.full(8, np.inf)
    ir[sensor] = 0.02
    behind, ahead = (np.radians(170.0), 0.1), (0.3, 0.1)  # u_p = (α, d)
    parts = {}
    for target in (behind, ahead):
        c_p, _ = indirect.control(ekm, jnp.asarray(target), cfg)
        assert (np.sum(c_p) < 0) == (target is behind)  # the map reverses onto the target behind
        for facing in ("front", "travel"):
            ctl = fusion_controller(signed_map, facing=facing, avoid="all", beta=0.5)
            _, c = ctl.step(ctl.init(), observation(ir, target=target))
            parts[target, facing] = (np.asarray(c) - 0.5 * np.asarray(c_p)) / 0.5  # Z u_o
    np.testing.assert_allclose(parts[ahead, "front"], parts[ahead, "travel"], rtol=1e-5)
    u = parts[behind, "front"][0] / front[0]
    assert u > 0
    np.testing.assert_allclose(parts[behind, "front"], np.multiply(front, u), rtol=1e-4)
    np.testing.assert_allclose(parts[behind, "travel"], np.multiply(travel, u), rtol=1e-4)


def test_fusion_back_cone_is_in_degrees_and_bounded(signed_map):
    with pytest.raises(ValueError, match="back_cone"):
        fusion.FusionParams(back_cone=0.0)
    with pytest.raises(ValueError, match="back_cone"):
        fusion.FusionParams(back_cone=200.0)
    narrow = fusion_controller(signed_map, back_cone=60.0)  # the side sensors (95° off the way back) left out
    ir = np.full(8, np.inf)
    ir[5] = 0.02
    wide = fusion_controller(signed_map)
    target = (np.radians(170.0), 0.1)
    (_, c_narrow), (_, c_wide) = (ctl.step(ctl.init(), observation(ir, target=target)) for ctl in (narrow, wide))
    assert np.sum(c_wide) > np.sum(c_narrow)  # braked by the side sensor only within the wide cone


def test_fusion_remembers_a_wall_end_its_sensors_have_lost_and_answers_it_with_the_nearest_sensors_weights(signed_map):
    """Tick 1: the 45 deg sensor reads 1.5 cm. Tick 2: the robot has turned 25 deg right on the spot and no sensor
    reads anything: the remembered point is at 70 deg, in the blind angle between the 45 and 85 deg sensors,
    nearest the 85 deg one (a side sensor: +same 0.4 to its own motor, +same/2 0.2 to the other). By hand: u = 1 -
    0.015 / 0.05 = 0.7, Z u = (0.28, 0.14), times 1 - beta = 0.15: (0.042, 0.021) m/s more than without the
    memory, which answers nothing."""
    ir = np.full(8, np.inf)
    ir[1] = 0.015
    sends = {}
    for remember in (True, False):
        ctl = fusion_controller(signed_map, remember=remember)
        state, _ = ctl.step(ctl.init(), observation(ir, pose=(0.5, 0.5, 0.0)))
        _, sends[remember] = ctl.step(state, observation(np.full(8, np.inf), t=0.128,
                                                         pose=(0.5, 0.5, np.radians(-25.0))))
    np.testing.assert_allclose(np.asarray(sends[True]) - np.asarray(sends[False]), [0.042, 0.021], atol=1e-4)


def test_fusion_reads_a_passages_two_walls_as_nothing_but_a_wall_on_one_side_and_whatever_is_ahead():
    # Khepera ring: 85, 45, 10, -10, -45, -85, -160, 160 degrees; radius 2.5 cm; lane 5 mm (the default is 0). A point
    # a sensor at 45 degrees reads at r lies (0.025 + r) sin 45 to the side: at r = 3.9 cm, 4.53 cm > 3 cm, aside; at
    # r = 1 cm, 2.47 cm, within 3 cm: in the way. The 10-degree pair: (0.025 + 0.05) sin 10 = 1.3 cm, always in the way.
    angles = jnp.asarray(fusion.KHEPERA.short_range.angles, jnp.float32)
    front = (fusion.FRONT, None)
    mirror = jnp.asarray([5, 4, 3, 2, 1, 0, 7, 6])  # the sensor at -phi, by hand
    assert fusion.mirrors(fusion.KHEPERA.short_range.angles) == (5, 4, 3, 2, 1, 0, 7, 6)
    inf = np.inf

    def seen(readings, reversing=0):
        out = fusion.in_the_way(jnp.asarray(readings, jnp.float32), angles, reversing, 0.025, 0.005, front, mirror)
        return np.isfinite(np.asarray(out))

    corridor = [0.02, 0.039, inf, inf, 0.039, 0.02, inf, inf]  # both walls of a 9 cm corridor, centred
    assert seen(corridor).tolist() == [True, False, False, False, False, True, False, False]  # the 45s read nothing
    one_wall = [0.02, 0.039, inf, inf, inf, inf, inf, inf]  # the left wall alone: the robot may be closing on it
    assert seen(one_wall).tolist() == [True, True, False, False, False, False, False, False]
    near_walls = [inf, 0.01, inf, inf, 0.039, inf, inf, inf]  # the left wall within 3 cm of the line: in the way
    assert seen(near_walls)[1] and seen(near_walls)[4]
    dead_ahead = [inf, 0.039, 0.05, 0.05, 0.039, inf, inf, inf]  # a passage's walls and the end of it ahead
    assert seen(dead_ahead).tolist() == [False, False, True, True, False, False, False, False]
    # with Z turned round while reversing (front[1] = 100 degrees of the way back), the rear pair (20 degrees off it)
    # reading both walls of the passage behind, (0.025 + 0.03) sin 20 = 1.9 cm to the side: in the way
    back = [inf, inf, inf, inf, inf, inf, 0.03, 0.03]
    turned = fusion.in_the_way(jnp.asarray(back, jnp.float32), angles, 1, 0.025, 0.005,
                               (fusion.FRONT, np.radians(100)), mirror)
    assert np.isfinite(np.asarray(turned)).tolist() == [False] * 6 + [True, True]


def test_fusion_steps_straight_out_of_a_movers_way(signed_map):
    """The fields' and Samba's test, the mover nearer: the robot at (0.5, 0.5) facing +x, its checkpoint to its left,
    nothing sensed; a mover of radius 2.5 cm 9 cm to its left comes at it at 0.1 m/s. Standing, the discs — the
    body grown by 1 cm, 3.5 + 2.5 = 6 cm — meet after 0.3 s < escape_s = 2.5 s. Straight ahead at v the nearest
    approach is 0.09 v / sqrt(v² + 0.01): 5.6 cm at 0.08 m/s (hit), 6.4 cm at 0.10 m/s (never): both wheels
    0.10 m/s (without the 1 cm, 0.08 would do). With escape_s = 0 the fused command stands."""
    mover = [0.5, 0.59, 0.0, -0.1, 0.025]
    obs = observation(np.full(8, np.inf), target=(np.pi / 2, 0.3), markers=[mover])
    ctl = fusion_controller(signed_map)
    np.testing.assert_allclose(np.asarray(ctl.step(ctl.init(), obs)[1]), [0.10, 0.10], atol=1e-6)
    off = fusion_controller(signed_map, escape_s=0.0)
    assert not np.allclose(np.asarray(off.step(off.init(), obs)[1]), [0.10, 0.10], atol=1e-3)
