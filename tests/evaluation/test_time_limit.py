"""The time limit that follows the route (issue 35): ten times the planned route's time at the robot's top speed,
never under the old fixed 120 s; ``--time-limit`` overrides it. Numbers worked out by hand."""

import numpy as np
import pytest

from evaluation.scenario import ScenarioConfig, run_scenario, time_limit_for
from robots.controllers.base import Controller
from robots.params import KHEPERA
from robots.worldfile import parse_world


def standing():
    return Controller(name="stand", spec="stand", sensors=KHEPERA.short_range, init=lambda: 0,
                      step=lambda state, obs: (state, np.zeros(2)))


def test_the_default_limit_is_ten_times_the_route_at_top_speed_and_at_least_120_s():
    config = ScenarioConfig()
    assert time_limit_for(config, 2.6, 0.16) == pytest.approx(162.5)  # 10 x 2.6 m / 0.16 m/s
    assert time_limit_for(config, 6.0, 0.16) == pytest.approx(375.0)
    assert time_limit_for(config, 6.0, 0.12) == pytest.approx(500.0)  # a slower robot gets longer
    assert time_limit_for(config, 1.15, 0.16) == 120.0  # three rooms: 71.9 s, the floor holds
    assert time_limit_for(ScenarioConfig(time_limit=40.0), 6.0, 0.16) == 40.0  # --time-limit overrides


def test_a_run_along_a_straight_2_6_m_route_is_given_162_5_s():
    """A 3 x 0.5 m empty arena, start (0.2, 0.25), goal (2.8, 0.25): the planner's route is the straight 2.6 m, so
    the limit is 10 x 2.6 / 0.16 = 162.5 s; a robot that never moves (and no trap monitor to stop it) runs out at
    the first tick past it, ceil(162.5 / 0.128) = 1270 ticks = 162.56 s."""
    world = parse_world({"name": "hall", "size": [3.0, 0.5], "start": [0.2, 0.25, 0.0], "goal": [2.8, 0.25]})
    rec = run_scenario(world, standing(), config=ScenarioConfig(trap_after=1e6, recover=False))
    assert rec.time_limit_s == pytest.approx(162.5)
    assert rec.ended == "time limit" and rec.time_s == pytest.approx(1270 * 0.128)
    short = run_scenario(world, standing(), config=ScenarioConfig(time_limit=5.0, trap_after=1e6))
    assert short.time_limit_s == 5.0 and short.time_s == pytest.approx(40 * 0.128)
