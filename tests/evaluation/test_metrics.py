"""Known answers for the ch. 6.1 metrics (evaluation.metrics, Eq. 6.1-6.3; issue 12, item 5).

:func:`evaluation.metrics.summarize` on hand-built :class:`TargetRecord`\\ s, every number worked out by hand
below: E in mm over all targets, P(ε) over all targets, T(ε) = mean of t_i(ε)/l_i and D(ε) = mean of
|d_i(ε) - l_i|/l_i over the *reached* targets only, the count of capped targets.
"""

import numpy as np
import pytest

from evaluation.metrics import summarize
from evaluation.protocol import EPSILONS, TargetRecord


# ---------------------------------------------------------------------------------------------------
# summarize() on hand-built records: 2 trials x 3 targets, ε = 5, 10, 25 mm.
# Entries of time/path where hit is False hold junk (99, 7): they must not enter T or D.
# ---------------------------------------------------------------------------------------------------

F, T_ = False, True
JUNK_T, JUNK_D = 99.0, 7.0


def hand_record():
    error = [[0.001, 0.003, 0.020], [0.002, 0.004, 0.006]]  # m; sum 0.036 over 6 targets
    capped = [[F, F, T_], [F, T_, F]]  # 2 capped
    straight = [[0.5, 0.25, 0.4], [0.2, 0.5, 0.1]]  # l_i, m
    hit = [[[T_, T_, T_], [F, T_, T_], [F, F, F]],
           [[F, F, T_], [F, F, F], [F, F, T_]]]
    J, K = JUNK_T, JUNK_D
    time = [[[4.0, 3.5, 3.0], [J, 2.5, 2.0], [J, J, J]],  # steps until first closer than ε
            [[J, J, 1.5], [J, J, J], [J, J, 0.9]]]
    path = [[[0.55, 0.52, 0.48], [K, 0.26, 0.24], [K, K, K]],  # m travelled until first closer than ε
            [[K, K, 0.19], [K, K, K], [K, K, 0.09]]]
    steps = [[5, 4, 50], [3, 50, 2]]
    bearing = [[0.0, 0.1, -0.2], [3.0, 0.0, 1.0]]
    return TargetRecord(*(np.asarray(a) for a in (error, capped, straight, hit, time, path, steps, bearing)))


def test_e_is_the_mean_final_error_over_every_target_in_mm():
    assert summarize(hand_record())["E_mm"] == pytest.approx(1000.0 * 0.036 / 6)  # 6.0 mm


def test_p_is_the_fraction_of_all_targets_reached_within_eps():
    out = summarize(hand_record())
    assert out["P"] == pytest.approx({"5": 1 / 6, "10": 2 / 6, "25": 4 / 6})
    assert out["capped"] == 2 and out["trials"] == 2 and out["targets"] == 3


def test_t_divides_each_time_by_its_l_i_and_averages_over_reached_targets_only():
    out = summarize(hand_record())
    assert out["T"]["5"] == pytest.approx(4.0 / 0.5)  # 8.0: only trial 0, target 0
    assert out["T"]["10"] == pytest.approx((3.5 / 0.5 + 2.5 / 0.25) / 2)  # (7 + 10) / 2 = 8.5
    assert out["T"]["25"] == pytest.approx((3.0 / 0.5 + 2.0 / 0.25 + 1.5 / 0.2 + 0.9 / 0.1) / 4)  # 7.625
    # Not the mean time (1.85 at 25 mm), nor a mean over all targets counting the misses.
    assert out["T"]["25"] != pytest.approx((3.0 + 2.0 + 1.5 + 0.9) / 4)


def test_d_takes_the_absolute_deviation_relative_to_l_i_over_reached_targets_only():
    out = summarize(hand_record())
    assert out["D"]["5"] == pytest.approx(0.05 / 0.5)  # |0.55 - 0.5| / 0.5 = 0.1
    assert out["D"]["10"] == pytest.approx((0.02 / 0.5 + 0.01 / 0.25) / 2)  # 0.04
    # At 25 mm every reached target was reached after less than l_i: d - l < 0, and |d - l| counts.
    assert out["D"]["25"] == pytest.approx((0.02 / 0.5 + 0.01 / 0.25 + 0.01 / 0.2 + 0.01 / 0.1) / 4)  # 0.0575
    assert out["D"]["25"] > 0


def test_an_eps_that_no_target_reaches_has_no_t_or_d_and_p_zero():
    rec = hand_record()
    hit = np.asarray(rec.hit).copy()
    hit[..., 0] = False
    out = summarize(rec._replace(hit=hit))
    assert out["P"]["5"] == 0.0 and out["T"]["5"] is None and out["D"]["5"] is None
    assert out["T"]["10"] == pytest.approx(8.5)  # the other tolerances are unchanged


def test_a_single_trial_record_counts_one_trial():
    one = TargetRecord(*(np.asarray(a)[0] for a in hand_record()))
    out = summarize(one)
    assert out["trials"] == 1 and out["targets"] == 3 and out["capped"] == 1
    assert out["E_mm"] == pytest.approx(1000.0 * 0.024 / 3)
    assert out["P"] == pytest.approx({"5": 1 / 3, "10": 2 / 3, "25": 2 / 3})
    assert out["T"]["25"] == pytest.approx((3.0 / 0.5 + 2.0 / 0.25) / 2)
    assert out["D"]["25"] == pytest.approx((0.02 / 0.5 + 0.01 / 0.25) / 2)


def test_the_tolerances_are_the_thesis_5_10_and_25_mm():
    assert EPSILONS == (0.005, 0.010, 0.025)
    assert list(summarize(hand_record())["P"]) == ["5", "10", "25"]
