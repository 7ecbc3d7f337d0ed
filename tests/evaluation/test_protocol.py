"""The ch. 6.1 test (evaluation.protocol): known answers (issue 12, item 5), the defaults, traced paths, and the
full protocol (slow).

:func:`evaluation.protocol.drive_test` on a noise-free analytic controller — straight ahead at a fixed whole
number of speed units until the target is ahead and nearer than ``R``, then zero — whose first-passage times,
path lengths, stops, final errors and caps are computed here independently, from the closed form of the
motion model (first-order lag, Euler sub-steps of 16 ms), to the sub-step.

The full protocol (slow: about a minute; run with ``python -m pytest -m slow``): 15×15 maps, 100,000 training
steps, 5 trials, 50 test targets, 10 % noise — ``ekm train``'s defaults. The thesis's figures for the
indirect map are E ≈ 3 mm, P(25 mm) > 0.9, T(25) ≈ 9 steps/m and D(25) < 9 %, and its direct map is worse on
each (8 mm, < 0.9, 17.5, 18 %).
"""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.config import EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import EPSILONS, TargetRecord, drive_test, evaluate, trace_paths
from robots.params import KHEPERA
from training.online import TrainConfig
from training.run import train


# ---------------------------------------------------------------------------------------------------
# drive_test() on a noise-free analytic controller, against the closed form of the motion model.
# ---------------------------------------------------------------------------------------------------

PARAMS = dataclasses.replace(KHEPERA, actuator_noise=0.0)
N = PARAMS.substeps(PARAMS.target_period)  # 64 sub-steps of 16 ms per 1.024 s control step
DT = PARAMS.dt
Q = math.exp(-DT / PARAMS.motor_tau)  # wheel lag over one sub-step: e^{-0.8}
V = 15 * PARAMS.speed_unit  # 0.12 m/s: a whole number of speed units, sent unchanged
R = 0.030  # the controller commands zero once the target is ahead and nearer than this
CAP = 5
START = (0.5, 0.5, 0.0)  # heading along +x; every target lies on the line y = 0.5
L1, L2, L3 = 0.2533, 0.2372, 0.002  # l_i: straight distances target to target (the first from the start)


def controller(u):
    """Both wheels at V; zero once the target is ahead (|α| < π/2) and nearer than R."""
    stop = (u[1] < R) & (jnp.abs(u[0]) < 0.5 * jnp.pi)
    return jnp.where(stop, 0.0, V) * jnp.ones(2)


def driven(m):
    """Distance from rest after m sub-steps at set-point V. The wheels run at V(1 - Q^j) through
    sub-step j = 0, 1, ... (first-order lag, held through each sub-step), and Euler integration sums
    them: V·dt·Σ_{j<m} (1 - Q^j) = V·dt·(m - (1 - Q^m)/(1 - Q))."""
    return V * DT * (m - (1.0 - Q**m) / (1.0 - Q))


def coasted(s, j):
    """Distance after s driven control steps (from rest) and then j sub-steps at set-point zero: the
    wheels spin down from w = V(1 - Q^{sN}) as w·Q^j."""
    w = V * (1.0 - Q ** (s * N))
    return driven(s * N) + w * DT * (1.0 - Q**j) / (1.0 - Q)


def by_hand(gap):
    """The closed-form run to one target ``gap`` metres ahead (signed: negative = behind) of a robot at rest.

    Returns (positions after every sub-step of the CAP control steps, control steps moved, capped)."""
    for s in range(CAP):
        x = driven(s * N)
        if 0.0 < gap - x < R:  # ahead and nearer than R at the start of step s: the command is zero from now on
            pos = [driven(m) for m in range(1, s * N + 1)] + [coasted(s, j) for j in range(1, N + 1)]
            return pos + [pos[-1]] * ((CAP - s - 1) * N), s, False
    return [driven(m) for m in range(1, CAP * N + 1)], CAP, True


def expected_records():
    """Per target: error, capped, straight, hit, time, path, steps, bearing — and the margins by which each
    first passage clears ε (sub-step before it outside, its own sub-step inside)."""
    rows, margins, behind = [], [], 0.0  # behind: where the robot stands relative to the last target (+ = past it)
    for l_i in (L1, L2, -L3):  # the third target lies l_3 behind the second
        gap = l_i - behind
        pos, steps, capped = by_hand(gap)
        dist = [abs(gap - x) for x in pos]
        hit, time, path = [], [], []
        for eps in EPSILONS:
            if abs(gap) < eps:  # already there when presented
                hit.append(True), time.append(0.0), path.append(0.0)
                continue
            m = next((m for m, d in enumerate(dist, 1) if d < eps), None)
            hit.append(m is not None)
            time.append(m / N if m else 0.0)
            path.append(pos[m - 1] if m else 0.0)  # straight forward motion: path = displacement
            if m:
                margins += [eps - dist[m - 1], (dist[m - 2] if m > 1 else abs(gap)) - eps]
        rows.append((abs(gap - pos[-1]), capped, abs(l_i), hit, time, path, steps, 0.0 if gap > 0 else math.pi))
        behind = pos[-1] - gap
    return [np.asarray(col) for col in zip(*rows)], margins


@pytest.fixture(scope="module")
def driven_record():
    targets = jnp.asarray([[START[0] + L1, START[1]], [START[0] + L1 + L2, START[1]],
                           [START[0] + L1 + L2 - L3, START[1]]], jnp.float32)
    rec = drive_test(controller, targets, jnp.asarray(START), jax.random.PRNGKey(0), cap=CAP, params=PARAMS)
    return jax.tree.map(np.asarray, rec)


def test_the_hand_computed_run_is_the_case_it_is_meant_to_be():
    (error, capped, straight, hit, time, path, steps, bearing), margins = expected_records()
    # Target 1: stops 7.5 mm short (within 10 mm, never within 5 mm). Target 2: stops 2 mm short and coasts
    # 1 mm past it, so its command would no longer be zero (target behind). Target 3: 3 mm behind the robot,
    # already within every ε when presented; the controller drives away from it until the cap.
    assert hit.tolist() == [[False, True, True], [True, True, True], [True, True, True]]
    assert steps.tolist() == [2, 2, CAP] and capped.tolist() == [False, False, True]
    assert 0.005 < error[0] < 0.010 and 0.0 < error[1] < 0.002
    assert bearing.tolist() == [0.0, 0.0, math.pi]
    # Every first passage clears ε by > 0.1 mm on both sides: float32 cannot move it by a sub-step.
    assert min(margins) > 1e-4


def test_first_passage_times_are_to_the_sub_step(driven_record):
    (_, _, _, hit, time, _, _, _), _ = expected_records()
    np.testing.assert_array_equal(driven_record.hit, hit)
    np.testing.assert_allclose(driven_record.time, time, rtol=0, atol=1e-5)  # 1 sub-step = 1/64 = 0.0156
    assert time[1].tolist() == [127 / 64, 125 / 64, 117 / 64]  # target 2, ε = 5, 10, 25 mm


def test_path_lengths_until_first_passage_follow_the_closed_form(driven_record):
    (_, _, _, _, _, path, _, _), _ = expected_records()
    np.testing.assert_allclose(driven_record.path, path, rtol=0, atol=2e-6)  # a sub-step is up to 1.9 mm


def test_l_i_is_measured_from_the_previous_target_not_from_where_the_robot_stopped(driven_record):
    np.testing.assert_allclose(driven_record.straight, [L1, L2, L3], rtol=0, atol=1e-6)  # float32 targets near 1 m


def test_a_stop_holds_and_the_robot_spins_down_where_it_stopped(driven_record):
    """Target 2: the robot coasts past it; the controller then asks to drive on (target behind), but
    once it has commanded zero the robot is stopped (Eq. 6.1): it stays, its steps stop counting."""
    (error, capped, _, _, _, _, steps, _), _ = expected_records()
    np.testing.assert_array_equal(driven_record.steps, steps)
    np.testing.assert_array_equal(driven_record.capped, capped)
    np.testing.assert_allclose(driven_record.error, error, rtol=0, atol=2e-6)
    assert driven_record.error[1] < 0.002  # would be ~0.1 m and more had it driven on


def test_bearing_is_the_direction_of_the_target_when_presented(driven_record):
    np.testing.assert_allclose(driven_record.bearing, [0.0, 0.0, math.pi], atol=1e-6)


def test_summarize_of_the_analytic_run(driven_record):
    (error, _, straight, hit, time, path, _, _), _ = expected_records()
    out = summarize(TargetRecord(*(getattr(driven_record, f) for f in TargetRecord._fields)))
    assert out["E_mm"] == pytest.approx(1000.0 * error.mean(), abs=1e-3)
    assert out["P"] == pytest.approx({"5": 2 / 3, "10": 1.0, "25": 1.0})
    assert out["capped"] == 1 and out["trials"] == 1 and out["targets"] == 3
    # ε = 5 mm: targets 2 and 3 only (target 1 never came within 5 mm).
    assert out["T"]["5"] == pytest.approx((time[1, 0] / L2 + 0.0 / L3) / 2, rel=1e-5)
    assert out["D"]["5"] == pytest.approx((abs(path[1, 0] - L2) / L2 + abs(0.0 - L3) / L3) / 2, rel=1e-4)
    assert out["T"]["25"] == pytest.approx((time[0, 2] / L1 + time[1, 2] / L2 + 0.0 / L3) / 3, rel=1e-5)


def test_keep_path_returns_every_sub_step_of_the_same_run(driven_record):
    targets = jnp.asarray([[START[0] + L1, START[1]], [START[0] + L1 + L2, START[1]],
                           [START[0] + L1 + L2 - L3, START[1]]], jnp.float32)
    rec, xy = drive_test(controller, targets, jnp.asarray(START), jax.random.PRNGKey(0), cap=CAP, params=PARAMS,
                         keep_path=True)
    assert xy.shape == (3, CAP, N, 2)
    for a, b in zip(rec, driven_record):
        np.testing.assert_array_equal(np.asarray(a), b)
    # The centre after every sub-step of target 1: the closed form, on the line y = 0.5.
    pos, _, _ = by_hand(L1)
    np.testing.assert_allclose(np.asarray(xy[0, ..., 0]).ravel(), START[0] + np.asarray(pos), rtol=0, atol=2e-6)
    np.testing.assert_array_equal(np.asarray(xy[..., 1]), np.float32(START[1]))


# ---------------------------------------------------------------------------------------------------
# The protocol's defaults: the thesis test is 50 targets, from the arena centre, at most 50 steps each.
# ---------------------------------------------------------------------------------------------------


def test_drive_test_caps_each_target_at_50_steps_by_default():
    rec = drive_test(lambda u: jnp.full(2, V), jnp.asarray([[START[0] + 8.0, START[1]]], jnp.float32),
                     jnp.asarray(START), jax.random.PRNGKey(0), params=PARAMS)
    assert rec.steps.tolist() == [50] and rec.capped.tolist() == [True]
    assert float(rec.error[0]) == pytest.approx(8.0 - driven(50 * N), abs=5e-5)  # 6.14 m driven


def test_evaluate_and_trace_paths_default_to_the_thesis_test():
    from ekm import maps
    from ekm.config import EKMConfig
    from evaluation.protocol import evaluate, run_test, test_targets, trace_paths

    cfg = EKMConfig(neurons=2)
    stack = jax.tree.map(lambda a: a[None], maps.init(cfg))  # one untrained trial: it cannot steer, so it is capped
    arena = (1.2, 0.8)  # not square: x and y must not be swapped
    rec = evaluate(stack, cfg, arena)
    assert rec.error.shape == (1, 50) and int(rec.steps.max()) == 50
    explicit = evaluate(stack, cfg, arena, targets=50, seed=0, cap=50)
    for a, b in zip(rec, explicit):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    pts, centre, xy, first = trace_paths(stack, cfg, arena)
    assert xy.shape == (50, 50 * N, 2)
    np.testing.assert_array_equal(np.asarray(centre), np.float32([0.6, 0.4, 0.0]))  # the arena centre, along x
    for a, b in zip(first, rec):
        np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float)[0], atol=1e-5)
    np.testing.assert_array_equal(np.asarray(pts), np.asarray(test_targets(50, arena, seed=0, margin=0.1)))
    np.testing.assert_array_equal(np.asarray(test_targets(50, arena)), np.asarray(pts))
    p = np.asarray(pts)
    assert (p >= 0.1).all() and (p[:, 0] <= 1.1).all() and (p[:, 1] <= 0.7).all()
    assert p[:, 0].max() > 0.9 and p[:, 1].min() < 0.2  # spread over the whole inner rectangle
    one = run_test(maps.init(cfg), pts[:3], centre, jax.random.PRNGKey(0), cfg=cfg)
    assert int(one.steps.max()) == 50 and one.error.shape == (3,)


# ------------------------------------------------------------------------------------------ against mutants

# More known answers, each written against a mutant that the known-answer tests above let through
# (docs/mutation.md).

def test_a_target_exactly_eps_away_is_not_closer_than_eps():
    """"Closer than ε" is strict (P(ε), Eq. 6.2): a robot at rest with the target exactly 25 mm ahead (in
    float32, hypot(0.025, 0) == 0.025 exactly) has not reached it within 25 mm, but has within any larger ε.
    Kills ``hit0 = d0 <= eps``."""
    e25 = float(np.float32(EPSILONS[2]))
    rec = drive_test(lambda u: jnp.zeros(2), jnp.asarray([[e25, 0.0]], jnp.float32), jnp.zeros(3),
                     jax.random.PRNGKey(0), cap=2, params=PARAMS)
    assert rec.hit.tolist() == [[False, False, False]]
    assert rec.steps.tolist() == [0] and rec.capped.tolist() == [False]  # it stopped at once and never moved
    assert float(rec.error[0]) == e25


def test_trace_paths_has_one_row_per_target_when_targets_and_cap_differ():
    """xy is (targets, cap · n, 2); the default test has 50 targets and a cap of 50, which hides a reshape on
    the wrong axis. Kills ``xy.reshape(xy.shape[1], -1, 2)``."""
    from ekm import maps
    from ekm.config import EKMConfig
    from evaluation.protocol import evaluate, trace_paths

    cfg = EKMConfig(neurons=2)
    stack = jax.tree.map(lambda a: a[None], maps.init(cfg))
    n = KHEPERA.substeps(KHEPERA.target_period)
    pts, _, xy, first = trace_paths(stack, cfg, (1.0, 1.0), targets=3, cap=5)
    assert pts.shape == (3, 2) and xy.shape == (3, 5 * n, 2) and first.error.shape == (3,)
    rec = evaluate(stack, cfg, (1.0, 1.0), targets=3, cap=5)
    np.testing.assert_allclose(np.asarray(first.error), np.asarray(rec.error)[0], atol=1e-6)
    # The last sub-step of each target's row is where the robot stood when the next target was presented.
    np.testing.assert_allclose(np.linalg.norm(np.asarray(xy[:, -1]) - np.asarray(pts), axis=-1),
                               np.asarray(first.error), atol=1e-5)


# --------------------------------------------------------------------------------------------- traced paths

ARENA = (1.0, 1.0)


def test_traced_paths_are_the_first_trial_of_the_same_test():
    cfg, tcfg = EKMConfig(neurons=6), TrainConfig(steps=2000, trials=2, arena=ARENA)
    maps = train(cfg, tcfg, seed=1)
    rec = jax.tree.map(lambda a: np.asarray(a)[0], evaluate(maps, cfg, ARENA, targets=8))
    pts, start, xy, first = trace_paths(maps, cfg, ARENA, targets=8)
    for a, b in zip(first, rec):
        np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float), atol=1e-5)
    n = KHEPERA.substeps(KHEPERA.target_period)
    assert xy.shape == (8, 50 * n, 2)
    # Each path ends where the robot stood when E was measured, and starts next to the arena centre.
    np.testing.assert_allclose(np.linalg.norm(np.asarray(xy)[:, -1] - np.asarray(pts), axis=-1), rec.error, atol=1e-5)
    assert np.linalg.norm(np.asarray(xy)[0, 0] - np.asarray(start)[:2]) <= 1.1 * KHEPERA.max_wheel_speed * KHEPERA.dt


# --------------------------------------------------------------------------------- the full protocol (slow)

@pytest.fixture(scope="module")
def protocol():
    out = {}
    for mapping in ("indirect", "direct"):
        cfg, tcfg = EKMConfig(mapping=mapping), TrainConfig()
        out[mapping] = summarize(evaluate(train(cfg, tcfg, seed=0), cfg, tcfg.arena))
    return out


@pytest.mark.slow
def test_indirect_map_reaches_the_thesis_positioning_figures(protocol):
    s = protocol["indirect"]
    assert s["trials"] == 5 and s["targets"] == 50
    assert s["E_mm"] <= 3.0  # measured 1.33 mm
    assert s["P"]["25"] >= 0.9 and s["P"]["5"] >= 0.9  # 1.000 and 1.000
    assert s["T"]["25"] <= 9.0  # 7.94 steps/m
    assert s["D"]["25"] <= 0.09  # 0.049


@pytest.mark.slow
def test_direct_map_is_worse_on_each_figure(protocol):
    d, i = protocol["direct"], protocol["indirect"]
    assert d["E_mm"] > i["E_mm"]  # 5.77 against 1.33 mm
    assert d["P"]["5"] < i["P"]["5"]  # 0.988 against 1.000
    assert d["P"]["25"] <= i["P"]["25"]  # 0.992 against 1.000
    assert d["T"]["25"] > i["T"]["25"]  # 9.30 against 7.94 steps/m
    assert d["D"]["25"] > i["D"]["25"]  # 0.050 against 0.049
