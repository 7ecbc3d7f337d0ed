"""Known values of the training schedules (training.schedules) at the start, middle and end of a run.

x(t) = x0 (x1/x0)^min(t / (f·T), 1): exponential from x0 to x1 over the first fraction f of T steps,
then x1; linear when one end is zero. Numbers are worked out by hand in the comments.
"""

import math

import jax
import jax.numpy as jnp
import pytest

from training.schedules import Schedule, Schedules

TOTAL = 100_000  # steps of the ch. 6.1 protocol


def value(schedule, t, total=TOTAL):
    return float(schedule(jnp.float32(t), total))


def test_default_eta_decays_from_0_1_to_0_005_over_the_first_60_percent():
    eta = Schedules().eta
    assert value(eta, 0) == pytest.approx(0.1, rel=1e-6)  # start
    assert value(eta, 30_000) == pytest.approx(math.sqrt(0.1 * 0.005), rel=1e-5)  # half-way: geometric mean 0.02236
    assert value(eta, 50_000) == pytest.approx(0.1 * 0.05 ** (5 / 6), rel=1e-5)  # middle of the run: 0.008237
    assert value(eta, 60_000) == pytest.approx(0.005, rel=1e-5)  # end of the decay
    assert value(eta, 100_000) == pytest.approx(0.005, rel=1e-5)  # end of the run: held at the end value


def test_default_sigma_decays_from_3_to_0_3_lattice_units_over_the_first_60_percent():
    sigma = Schedules().sigma
    assert value(sigma, 0) == pytest.approx(3.0, rel=1e-6)
    assert value(sigma, 30_000) == pytest.approx(math.sqrt(3.0 * 0.3), rel=1e-5)  # 0.9487
    assert value(sigma, 50_000) == pytest.approx(3.0 * 0.1 ** (5 / 6), rel=1e-5)  # 0.4403
    assert value(sigma, 60_000) == pytest.approx(0.3, rel=1e-5)
    assert value(sigma, 100_000) == pytest.approx(0.3, rel=1e-5)


def test_default_exploration_is_a_constant_0_2_of_c_star():
    explore = Schedules().explore
    for t in (0, 30_000, 50_000, 60_000, 100_000):
        assert value(explore, t) == pytest.approx(0.2, rel=1e-6)
    assert (explore.start, explore.end, explore.fraction) == (0.2, 0.2, 1.0)


def test_default_schedules_are_the_documented_ones():
    s = Schedules()
    assert (s.eta.start, s.eta.end, s.eta.fraction) == (0.1, 0.005, 0.6)
    assert (s.sigma.start, s.sigma.end, s.sigma.fraction) == (3.0, 0.3, 0.6)
    assert s.to_dict() == {"eta": {"start": 0.1, "end": 0.005, "fraction": 0.6},
                           "sigma": {"start": 3.0, "end": 0.3, "fraction": 0.6},
                           "explore": {"start": 0.2, "end": 0.2, "fraction": 1.0}}


@pytest.mark.parametrize("name", ["eta", "sigma"])
def test_the_decaying_schedules_fall_from_start_to_end_and_never_rise(name):
    s = getattr(Schedules(), name)
    ts = [0, 1_000, 10_000, 30_000, 50_000, 59_999, 60_000, 80_000, 100_000]
    vals = [value(s, t) for t in ts]
    assert vals[0] == pytest.approx(s.start, rel=1e-6) and vals[-1] == pytest.approx(s.end, rel=1e-5)
    assert all(a > b for a, b in zip(vals[:6], vals[1:7])), vals  # strictly falling while decaying
    assert vals[6] == vals[7] == vals[8]  # then held


def test_a_full_length_schedule_reaches_its_end_only_at_the_last_step():
    s = Schedule(2.0, 0.5)  # fraction 1
    assert value(s, 0, 1000) == pytest.approx(2.0)
    assert value(s, 500, 1000) == pytest.approx(1.0, rel=1e-6)  # 2 · (1/4)^(1/2)
    assert value(s, 250, 1000) == pytest.approx(2.0 * 0.25**0.25, rel=1e-6)  # 1.4142
    assert value(s, 1000, 1000) == pytest.approx(0.5, rel=1e-6)


def test_an_increasing_schedule_rises():
    s = Schedule(0.5, 2.0, 0.5)
    assert value(s, 0, 1000) == pytest.approx(0.5)
    assert value(s, 250, 1000) == pytest.approx(1.0, rel=1e-6)  # 0.5 · 4^(1/2)
    assert value(s, 900, 1000) == pytest.approx(2.0, rel=1e-6)


@pytest.mark.parametrize("start,end,expected", [
    (0.4, 0.0, (0.4, 0.3, 0.2, 0.0, 0.0)),  # linear down to zero: x0 + (x1 - x0) s
    (0.0, 0.4, (0.0, 0.1, 0.2, 0.4, 0.4)),  # linear up from zero
    (0.0, 0.0, (0.0, 0.0, 0.0, 0.0, 0.0)),
])
def test_a_schedule_with_a_zero_end_is_linear(start, end, expected):
    s = Schedule(start, end, 0.8)
    got = [value(s, t, 1000) for t in (0, 200, 400, 800, 1000)]  # s = 0, 1/4, 1/2, 1, 1
    assert got == pytest.approx(list(expected), abs=1e-7)


def test_steps_before_the_start_are_clipped_to_the_start_value():
    assert value(Schedules().eta, -5_000) == pytest.approx(0.1, rel=1e-6)


def test_schedules_work_on_traced_steps():
    eta = Schedules().eta
    f = jax.jit(lambda t: eta(t, TOTAL))
    assert float(f(jnp.float32(30_000))) == pytest.approx(math.sqrt(0.1 * 0.005), rel=1e-5)
    got = jax.vmap(lambda t: eta(t, TOTAL))(jnp.asarray([0.0, 60_000.0]))
    assert got.tolist() == pytest.approx([0.1, 0.005], rel=1e-5)


@pytest.mark.parametrize("bad", [(-0.1, 0.1, 1.0), (0.1, -0.1, 1.0), (0.1, 0.1, 0.0), (0.1, 0.1, 1.5),
                                 (0.1, 0.1, -0.5)])
def test_bad_schedules_are_refused(bad):
    with pytest.raises(ValueError, match=r"^bad schedule Schedule\(.*\): need start, end >= 0 and 0 < fraction <= 1$"):
        Schedule(*bad)


def test_edge_schedules_are_accepted():
    Schedule(0.0, 0.0, 1.0)
    Schedule(1.0, 1.0, 1e-6)
