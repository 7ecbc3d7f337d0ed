"""The definitions of Riekki's action maps (1999, §3.2): the weight curve, MSA with Eq. 3.1, OSA, Avoid maps,
MAV and filtering — on whole maps, as :mod:`robots.controllers.actionmaps` computes them."""

import math

import jax
import numpy as np
import pytest

from ekm.angles import wrap
from robots.controllers import actionmaps as am

GRID = am.VelocityGrid()  # 72 directions x 8 speeds up to 0.16 m/s


class J:
    """The maps jitted once (op by op, each of their few hundred primitives would compile on its own)."""

    collision_times = jax.jit(am.collision_times, static_argnames=("grid",))
    ray_distances = jax.jit(am.ray_distances, static_argnames=("grid",))
    satisfying_times = jax.jit(am.satisfying_times, static_argnames=("grid",))
    msa = jax.jit(am.msa, static_argnames=("grid", "p", "passes"))
    osa = jax.jit(am.osa, static_argnames=("grid",))
    osa_times = jax.jit(am.osa_times, static_argnames=("grid",))
    optimum = jax.jit(am.optimum, static_argnames=("speed",))
    relax = jax.jit(am.relax, static_argnames=("p", "passes"))


def polar(alpha, d):
    return np.array([d * math.cos(alpha), d * math.sin(alpha)], np.float32)


def random_maps(seed, m=3):
    rng = np.random.default_rng(seed)
    maps = rng.uniform(-1, 1, (m,) + GRID.shape).astype(np.float32)
    maps[rng.random(maps.shape) < 0.3] = 0.0
    return maps


# ---------------------------------------------------------------------------------------------- grid, curve

def test_the_grid_spans_the_circle_and_the_speeds_up_to_c_star():
    a, s = GRID.angles(), GRID.speed_values()
    assert a.shape == (72,) and s.shape == (8,) and a[0] == 0.0
    assert np.all((a > -math.pi) & (a <= math.pi + 1e-6))
    np.testing.assert_allclose(np.diff(np.sort(a)), 2 * math.pi / 72, atol=1e-5)
    np.testing.assert_allclose(s, 0.02 * np.arange(1, 9), atol=1e-7)
    assert GRID.velocities().shape == (72, 8, 2)


def test_the_weight_curve_is_full_for_one_period_then_falls_without_ties_over_the_robots_times():
    assert float(am.weight(0.0)) == 1.0 and float(am.weight(am.FULL_S)) == 1.0 and float(am.weight(np.inf)) == 0.0
    t = np.arange(0.2, 300.0, 0.1, dtype=np.float32)  # 3-30 s is this robot's range; far beyond it too
    w = np.asarray(am.weight(t))
    assert np.all(np.diff(w) < 0) and w[-1] > 0  # strictly falling: no two times share a weight
    # exponential: a ratio of weights is a difference of times (the arbiter's hysteresis relies on it)
    assert float(am.weight(13.0) / am.weight(3.0)) == pytest.approx(math.exp(-10.0 / am.TAU_S), rel=1e-5)
    # Riekki's soccer curve is near zero after 3 s; rescaled, an arena crossing (~30 s) still weighs 0.05
    assert 0.03 < float(am.weight(30.0)) < 0.06


# ---------------------------------------------------------------------------------------------- MAV

def test_mav_keeps_per_action_the_weight_of_greatest_magnitude_with_its_sign():
    maps = random_maps(0)
    out = np.asarray(am.mav(*maps))
    k = np.argmax(np.abs(maps), axis=0)
    expected = np.take_along_axis(maps, k[None], axis=0)[0]
    np.testing.assert_array_equal(out, expected)
    np.testing.assert_array_equal(np.asarray(am.mav(maps)), out)  # a stack works the same
    # the general procedure: combine pairwise, one map after the other (§3.2.7)
    np.testing.assert_array_equal(np.asarray(am.mav(am.mav(maps[0], maps[1]), maps[2])), out)


def test_mav_gives_a_tie_to_the_obstacle():
    goto = np.full(GRID.shape, 0.5, np.float32)
    avoid = np.zeros(GRID.shape, np.float32)
    avoid[3, 4], avoid[5, 5] = -0.5, -0.2
    out = np.asarray(am.mav(goto, avoid))
    assert out[3, 4] == -0.5 and out[5, 5] == 0.5 and np.sum(out < 0) == 1


# ---------------------------------------------------------------------------------------------- filtering

def test_filtering_by_time_to_collision_zeroes_exactly_the_actions_slower_than_the_threshold():
    times = np.asarray(J.collision_times(polar(0.3, 0.12)[None], np.zeros((1, 2)), np.array([0.06]), GRID))
    avoid = np.asarray(am.avoid(times))
    out = np.asarray(am.filter_times(avoid, times, 0.5))
    slow = times > 0.5
    assert slow.any() and (~slow & np.isfinite(times)).any()
    assert np.all(out[slow] == 0.0) and np.array_equal(out[~slow], avoid[~slow])


def test_filtering_by_a_sector_and_by_a_speed_mask_zeroes_exactly_the_masked_actions():
    w = np.abs(random_maps(1, 1)[0]) + 0.01
    mask = np.asarray(am.sector_mask(GRID, math.radians(45.0), math.radians(30.0)))
    out = np.asarray(am.apply_mask(w, mask))
    deg = np.degrees(GRID.angles())
    inside = (deg >= 15 - 1e-3) & (deg <= 75 + 1e-3)
    assert inside.sum() == 13
    assert np.all(out[~inside] == 0.0) and np.array_equal(out[inside], w[inside])
    slow = np.asarray(am.apply_mask(w, am.speed_mask(GRID, 0.07)))
    assert np.all(slow[:, 3:] == 0.0) and np.array_equal(slow[:, :3], w[:, :3])
    cond = w > 0.5
    np.testing.assert_array_equal(np.asarray(am.filter_map(w, cond)), np.where(cond, 0.0, w))


# ---------------------------------------------------------------------------------------------- Eq. 3.1

def test_relaxation_only_raises_weights_and_keeps_local_maxima():
    w = np.abs(random_maps(2, 1)[0]) * (np.random.default_rng(3).random(GRID.shape) < 0.05)
    for passes in (1, 3, 8):
        out = np.asarray(J.relax(w, 0.15, passes))
        assert np.all(out >= w - 1e-7)
    # an action at least as heavy as its four neighbours is unchanged by a pass
    up, down = np.roll(w, -1, 0), np.roll(w, 1, 0)
    faster = np.concatenate([w[:, 1:], w[:, -1:]], 1)
    slower = np.concatenate([w[:, :1], w[:, :-1]], 1)
    peak = (w >= up) & (w >= down) & (w >= faster) & (w >= slower)
    np.testing.assert_allclose(np.asarray(J.relax(w, 0.15, 1))[peak], w[peak], rtol=1e-6)


def test_relaxation_follows_eq_3_1_pass_by_pass():
    w = np.zeros(GRID.shape, np.float32)
    w[10, 4] = 1.0
    one = np.asarray(J.relax(w, 0.15, 1))
    assert one[10, 4] == 1.0
    for i, j in ((11, 4), (9, 4), (10, 5), (10, 3)):  # immediate neighbours: (1 - p) 0 + p 1
        assert one[i, j] == pytest.approx(0.15)
    assert np.count_nonzero(one) == 5  # one pass reaches only immediate neighbours
    two = np.asarray(J.relax(w, 0.15, 2))
    assert two[11, 4] == pytest.approx(0.85 * 0.15 + 0.15 * 1.0) and two[12, 4] == pytest.approx(0.15 * 0.15)
    assert two[11, 5] == pytest.approx(0.15 * 0.15)
    wrap = np.zeros(GRID.shape, np.float32)
    wrap[0, 0] = 1.0
    assert np.asarray(J.relax(wrap, 0.15, 1))[71, 0] == pytest.approx(0.15)  # directions wrap round


def test_msa_keeps_the_satisfying_actions_at_their_collision_times():
    p = polar(math.radians(60.0), 0.4)
    t = np.asarray(J.satisfying_times(p, np.zeros(2), GRID))
    sat = np.isfinite(t)
    i = int(GRID.direction_index(math.radians(60.0)))
    assert np.array_equal(np.argwhere(sat)[:, 0], np.full(8, i))  # every speed towards it, nothing else
    np.testing.assert_allclose(t[i], 0.4 / GRID.speed_values(), rtol=1e-5)
    w = np.asarray(J.msa(p, np.zeros(2), GRID, p=0.15, passes=8))
    np.testing.assert_allclose(w[sat], np.asarray(am.weight(t[sat])), rtol=1e-6)  # unchanged by Eq. 3.1
    raw = np.asarray(am.weight(t))
    assert np.all(w >= raw - 1e-7)


def test_an_msa_map_for_a_stationary_object_peaks_in_its_direction():
    for deg in (0.0, 60.0, -120.0, 180.0):
        w = np.asarray(J.msa(polar(math.radians(deg), 0.4), np.zeros(2), GRID, p=0.15, passes=8))
        i, j = am.best(w)
        assert np.degrees(GRID.angles()[int(i)]) == pytest.approx(deg if deg != 180.0 else 180.0, abs=1e-3)
        assert int(j) == GRID.speeds - 1  # full speed: the shortest time
        # weights fall away from the object's direction (Fig. 19), both ways round
        ring = np.roll(w[:, -1], -int(i))
        assert np.all(np.diff(ring[:9]) <= 1e-7) and np.all(np.diff(ring[::-1][:8]) <= 1e-7)


def test_msa_satisfying_actions_for_a_moving_object_meet_it_on_its_trajectory():
    p, u = np.array([0.5, -0.3], np.float32), np.array([0.0, 0.04], np.float32)
    t = np.asarray(J.satisfying_times(p, u, GRID))
    cells = np.argwhere(np.isfinite(t))
    assert len(cells) > 10
    for i, j in cells:
        v = GRID.velocities()[i, j]
        miss = np.linalg.norm(v * t[i, j] - (p + u * t[i, j]))
        # within the cell's size at that time: half a direction step and half a speed step
        reach = t[i, j] * (GRID.speed_values()[j] * GRID.step_angle / 2 + GRID.step_speed / 2)
        assert miss <= reach + 1e-4


# ---------------------------------------------------------------------------------------------- OSA

def test_the_osa_optimal_action_for_a_moving_object_reaches_the_earliest_collision_point():
    p, u = np.array([0.6, -0.35], np.float32), np.array([0.0, 0.04], np.float32)
    t_opt, c, a_opt = (np.asarray(x) for x in J.optimum(p, u, 0.0, GRID.max_speed))
    np.testing.assert_allclose(c, p + u * t_opt, rtol=1e-5)  # the object is there at t*
    assert np.linalg.norm(c) == pytest.approx(GRID.max_speed * t_opt, rel=1e-4)  # the robot too, at c*
    # no earlier meeting at c*: at any earlier time the object is out of the robot's reach
    for t in np.linspace(0.0, float(t_opt) * 0.999, 50):
        assert np.linalg.norm(p + u * t) > GRID.max_speed * t
    w = np.asarray(J.osa(p, u, GRID))
    i, j = am.best(w)
    assert int(j) == GRID.speeds - 1
    assert abs(float(wrap(GRID.angles()[int(i)] - a_opt))) <= GRID.step_angle


def test_osa_actions_turning_past_the_optimal_direction_towards_a_moving_object_weigh_zero():
    p, u = np.array([0.6, -0.35], np.float32), np.array([0.0, 0.04], np.float32)  # object right, moving left
    _, _, a_opt = J.optimum(p, u, 0.0, GRID.max_speed)
    w = np.asarray(J.osa(p, u, GRID))
    delta = np.asarray(wrap(GRID.angles() - a_opt))
    toward = np.sign(float(wrap(math.atan2(p[1], p[0]) - a_opt)))  # the object's side of the optimum
    past = (np.sign(delta) == toward) & (np.abs(delta) > 1e-6)
    assert past.sum() > 10 and np.all(w[past] == 0.0)
    ahead_of_it = (np.sign(delta) == -toward) & (np.abs(delta) < math.radians(85))
    assert np.all(w[ahead_of_it] > 0.0)  # the other side keeps its projected weights
    # a stationary object has no such side: the map is symmetric round the object's direction
    ws = np.asarray(J.osa(polar(0.0, 0.5), np.zeros(2), GRID))
    np.testing.assert_allclose(ws[1:36], ws[71:36:-1], rtol=1e-5)


def test_osa_projects_onto_the_optimal_path_within_90_degrees():
    d = 0.5
    w_t = np.asarray(J.osa_times(polar(0.0, d), np.zeros(2), GRID))
    a, s = GRID.angles(), GRID.speed_values()
    front = np.abs(a) < math.pi / 2 - 1e-6
    np.testing.assert_allclose(w_t[front], d / (s[None, :] * np.cos(a[front, None])) * np.ones((1, 8)), rtol=1e-4)
    assert np.all(np.isinf(w_t[~front]))


def test_osa_for_a_circular_object_times_its_enlarged_edge_in_an_object_sector_that_widens_when_near():
    rho = 0.025 + 0.04  # robot radius + object radius
    widths = []
    for d in (0.6, 0.3, 0.12):
        t = np.asarray(J.osa_times(polar(0.0, d), np.zeros(2), GRID, radius=rho))
        beta = math.asin(rho / d)
        a = GRID.angles()
        sector = np.abs(a) <= beta
        along = d * np.cos(a[sector]) - np.sqrt(rho**2 - (d * np.sin(a[sector])) ** 2)
        np.testing.assert_allclose(t[sector, -1], along / GRID.max_speed, rtol=1e-4)
        assert t[0, -1] == pytest.approx((d - rho) / GRID.max_speed, rel=1e-4)  # the edge, not the centre
        edge = np.abs(a) > beta
        proj = np.cos(np.abs(a[edge]) - beta)
        ok = proj > 1e-3
        np.testing.assert_allclose(t[edge, -1][ok], math.sqrt(d**2 - rho**2) / (GRID.max_speed * proj[ok]),
                                   rtol=1e-4)
        widths.append(int(sector.sum()))
    assert widths[0] < widths[1] < widths[2]  # Fig. 25


# ---------------------------------------------------------------------------------------------- Avoid maps

def test_collision_times_are_exact_and_avoid_maps_inhibit_only_colliding_actions():
    q = np.array([[0.3, 0.05], [-0.1, 0.4]], np.float32)
    u = np.array([[0.0, 0.0], [0.02, -0.05]], np.float32)
    rho = np.array([0.06, 0.05], np.float32)
    t = np.asarray(J.collision_times(q, u, rho, GRID))
    v = GRID.velocities()
    hit = np.isfinite(t)
    assert hit.any() and (~hit).any()
    for i, j in np.argwhere(hit):
        gaps = [np.linalg.norm(q[k] + (u[k] - v[i, j]) * t[i, j]) - rho[k] for k in range(2)]
        assert min(gaps) == pytest.approx(0.0, abs=1e-5)  # touching at t
        for s in np.linspace(0, t[i, j] * 0.99, 20):  # and not before
            assert all(np.linalg.norm(q[k] + (u[k] - v[i, j]) * s) > rho[k] - 1e-6 for k in range(2))
    avoid = np.asarray(am.avoid(t))
    assert np.all(avoid[hit] < 0) and np.all(avoid[~hit] == 0) and avoid.min() >= -1.0
    # a stationary object's time is its ray distance over the speed
    d = np.asarray(J.ray_distances(q[:1], rho[:1], GRID))
    t0 = np.asarray(J.collision_times(q[:1], np.zeros((1, 2)), rho[:1], GRID))
    np.testing.assert_allclose(np.where(np.isinf(t0), -1, t0),
                               np.where(np.isinf(d[:, None]), -1, d[:, None] / GRID.speed_values()), rtol=1e-5)


def test_a_negated_goto_map_is_an_avoid_map_and_touching_blocks_only_closing_actions():
    g = np.asarray(J.osa(polar(0.5, 0.4), np.zeros(2), GRID))
    assert np.array_equal(np.asarray(am.negate(g)), -g) and np.asarray(am.negate(g)).max() <= 0
    t = np.asarray(J.collision_times(polar(0.0, 0.02)[None], np.zeros((1, 2)), np.array([0.035]), GRID))
    front = np.abs(GRID.angles()) < math.pi / 2 - 1e-6
    assert np.all(t[front] == 0.0) and np.all(np.isinf(t[~front]))


def test_the_maps_compile_whole_under_jit():
    osa = jax.jit(lambda p, u: am.osa(p, u, GRID, radius=0.025))
    msa = jax.jit(lambda p, u: am.msa(p, u, GRID))
    for f in (osa, msa):
        w = np.asarray(f(np.array([0.4, 0.1], np.float32), np.array([0.0, 0.03], np.float32)))
        assert w.shape == GRID.shape and np.all(np.isfinite(w)) and 0.0 <= w.min() and w.max() <= 1.0
