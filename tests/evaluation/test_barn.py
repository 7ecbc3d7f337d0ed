"""The BARN navigation score (issue 35): per run, success x OT / clip(AT, 2 OT, 8 OT), and per row its mean with a
95 % interval. Numbers worked out by hand."""

import math

import pytest

from evaluation.compare import _row
from evaluation.motion import barn
from evaluation.scenario import run_scenario
from planner.checkpoints import path_length
from robots.worldnames import load_world
from tests.evaluation.test_scenario import steering


def test_the_score_of_a_run_by_hand():
    assert barn(True, 30.0, 10.0) == pytest.approx(1 / 3)  # 10 / 30
    assert barn(True, 15.0, 10.0) == pytest.approx(0.5)  # faster than 2 OT counts as 2 OT: at most 0.5
    assert barn(True, 100.0, 10.0) == pytest.approx(0.125)  # slower than 8 OT counts as 8 OT
    assert barn(False, 30.0, 10.0) == 0.0


def test_a_run_scores_its_planned_route_at_top_speed_against_its_time():
    rec = run_scenario(load_world("open-arena"), steering(), seed=0)
    out = rec.outcome()
    optimal = path_length(rec.poses[0, :2], rec.plans[0].checkpoints) / 0.16  # the Khepera's c*
    assert out["reached"] and out["barn_score"] == pytest.approx(optimal / min(max(out["time_s"], 2 * optimal),
                                                                              8 * optimal), abs=1e-4)


def test_a_rows_mean_and_interval():
    """Scores 0.5, 0.25 and 0: mean 0.25, sample standard deviation 0.25, half-width 1.96 x 0.25 / sqrt(3) = 0.283,
    the lower end held at 0 (no score is negative)."""
    runs = [{"reached": s > 0, "time_s": 10.0, "path_m": 1.0, "collisions": 0, "trapped": False, "contact_s": 0.0,
             "barn_score": s} for s in (0.5, 0.25, 0.0)]
    score = _row(runs)["motion"]["barn_score"]
    half = 1.959964 * 0.25 / math.sqrt(3)
    assert score["mean"] == pytest.approx(0.25) and score["ci95"] == pytest.approx([0.0, 0.25 + half], abs=1e-5)
