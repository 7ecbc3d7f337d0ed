"""How a run moved (evaluation.motion), on hand-written trajectories whose measures are worked out by hand."""

import math

import numpy as np
import pytest

from evaluation.motion import at_ticks, mean_ci, measures
from planner.checkpoints import path_length

PERIOD = 0.128


def goal_at(point):
    return lambda t: point


def straight(n_ticks: int, speed: float, heading: float = 0.0, start=(0.0, 0.0)):
    """Poses every tick along a straight line at ``speed`` m/s."""
    t = PERIOD * np.arange(n_ticks + 1)
    x = start[0] + speed * t * math.cos(heading)
    y = start[1] + speed * t * math.sin(heading)
    return t, np.stack([x, y, np.full_like(t, heading)], axis=1)


def test_a_straight_steady_run_is_smooth_unhesitating_and_as_long_as_its_route():
    t, poses = straight(10, 0.1)  # 1.28 s at 0.1 m/s: 0.128 m
    m = measures([(0.1, 0.1)] * 10, t, poses, PERIOD, goal_at((1.0, 0.0)), route_m=0.128, arrived=False)
    assert m["command_change_mps"] == 0.0 and m["angular_accel_rms"] == 0.0 and m["stopped_s"] == 0.0
    assert m["turn_reversals_per_m"] == 0.0 and m["path_ratio"] == pytest.approx(1.0) and m["stop_distance_m"] is None


def test_command_changes_are_averaged_over_ticks_and_wheels():
    # tick 1 → 2: both wheels +0.1 (mean 0.1); tick 2 → 3: the right wheel −0.1 (mean 0.05): 0.075
    t, poses = straight(3, 0.0)
    m = measures([(0.0, 0.0), (0.1, 0.1), (0.1, 0.0)], t, poses, PERIOD, goal_at((1.0, 0.0)), 1.0, False)
    assert m["command_change_mps"] == pytest.approx(0.075)


def test_a_robot_standing_away_from_the_goal_hesitates_and_one_at_the_goal_does_not():
    t, poses = straight(8, 0.0, start=(0.5, 0.5))  # eight ticks standing still: 1.024 s
    assert measures([], t, poses, PERIOD, goal_at((0.9, 0.5)), 0.4, False)["stopped_s"] == pytest.approx(8 * PERIOD)
    at_goal = measures([], t, poses, PERIOD, goal_at((0.502, 0.5)), 0.4, True)
    assert at_goal["stopped_s"] == 0.0 and at_goal["stop_distance_m"] == pytest.approx(0.002)


def test_turning_left_then_right_then_left_is_two_reversals_and_a_steady_turn_accelerates_nothing():
    # heading rates +1, +1, +1, −1, −1, +1 rad/s for one tick each, driving 0.1 m a tick: 0.6 m of path;
    # three ticks keep their direction, two reverse it
    rates = [1.0, 1.0, 1.0, -1.0, -1.0, 1.0]
    heading = np.concatenate([[0.0], np.cumsum(rates) * PERIOD])
    xy = np.stack([0.1 * np.arange(7), np.zeros(7)], axis=1)
    poses = np.column_stack([xy, heading])
    m = measures([], PERIOD * np.arange(7), poses, PERIOD, goal_at((2.0, 0.0)), 0.6, False)
    assert m["turn_reversals_per_m"] == pytest.approx(2 / 0.6, abs=1e-3)
    # Δω per tick: 0, 0, −2, 0, +2 rad/s → α = 0, 0, −2/0.128, 0, 2/0.128: RMS = sqrt(2 · (2/0.128)² / 5)
    assert m["angular_accel_rms"] == pytest.approx(math.sqrt(2 * (2 / PERIOD) ** 2 / 5), rel=1e-3)
    steady = np.column_stack([xy, 0.5 * PERIOD * np.arange(7)])
    assert measures([], PERIOD * np.arange(7), steady, PERIOD, goal_at((2.0, 0.0)), 0.6, False)[
        "angular_accel_rms"] == pytest.approx(0.0, abs=1e-9)


def test_the_path_ratio_is_the_path_over_the_planned_route():
    assert path_length((0.0, 0.0), [(0.3, 0.4), (0.3, 1.4)]) == pytest.approx(1.5)
    t, poses = straight(10, 0.1)  # 0.128 m of path
    assert measures([], t, poses, PERIOD, goal_at((1.0, 0.0)), 0.064, False)["path_ratio"] == pytest.approx(2.0)


def test_poses_are_taken_at_the_ticks_not_the_sub_steps():
    times = np.arange(0, 17) * 0.016  # 16 sub-steps of 16 ms: two ticks
    poses = np.column_stack([times, np.zeros(17), np.zeros(17)])
    assert at_ticks(times, poses, PERIOD)[:, 0] == pytest.approx([0.0, 0.128, 0.256])


def test_mean_ci_is_the_mean_with_1_96_standard_errors():
    m, (lo, hi) = mean_ci([1.0, 2.0, 3.0, None])
    assert m == 2.0 and hi - m == pytest.approx(1.959964 * 1.0 / math.sqrt(3))
    assert mean_ci([None]) == (None, None) and mean_ci([4.0]) == (4.0, [4.0, 4.0])
    # nine zeros and a 3: mean 0.3, sd 0.9487, half-width 0.588 — no value is negative: the lower bound is 0
    m, (lo, hi) = mean_ci([0.0] * 9 + [3.0])
    assert m == pytest.approx(0.3) and lo == 0.0 and hi == pytest.approx(0.3 + 1.959964 * 0.948683 / math.sqrt(10))
    assert mean_ci([-3.0] + [0.0] * 9)[1][0] == pytest.approx(-0.3 - 1.959964 * 0.948683 / math.sqrt(10))
