"""The trap monitor as arrays (evaluation.jaxmonitor): the answers of evaluation.monitor.TrapMonitor's rule, worked
out by hand, and the same answers as the Python monitor on the same inputs."""

import jax
import jax.numpy as jnp
import numpy as np

from evaluation import jaxmonitor
from evaluation.monitor import TrapMonitor

RULE = jaxmonitor.MonitorRule(after=20.0, progress=0.01, ground=0.05, loop=1.45)
GRID = jaxmonitor.grid_size((1.0, 1.0), 0.05)
_update = jax.jit(jaxmonitor.update, static_argnames="rule")


def first_trap(positions, distances, period=0.128):
    """The update (1-based) at which each monitor first says trapped, fed the same (t, distance, position)."""
    py = TrapMonitor(RULE.after, RULE.progress, RULE.ground, RULE.loop)
    m = jaxmonitor.init(GRID)
    py_at = jx_at = None
    for k, (p, d) in enumerate(zip(positions, distances), 1):
        t = np.float32(k * period)
        m, trapped = _update(m, t, jnp.float32(d), jnp.asarray(p, jnp.float32), RULE)
        if py.update(float(t), float(d), p) and py_at is None:
            py_at = k
        if bool(trapped) and jx_at is None:
            jx_at = k
    return py_at, jx_at


def test_a_robot_standing_still_is_trapped_after_twenty_seconds():
    # Update 1 (t = 0.128 s) is progress (the first distance, and new ground); nothing after it is. Trapped at the
    # first t with t - 0.128 >= 20: k * 0.128 >= 20.128, k >= 157.25, so update 158 (t = 20.224 s).
    n = 170
    assert first_trap([(0.525, 0.525)] * n, [1.0] * n) == (158, 158)


def test_coming_closer_by_a_centimetre_postpones_the_trap():
    # Still, but 1.5 cm closer at update 50 (t = 6.4 s): trapped at k * 0.128 >= 26.4, k >= 206.25, update 207.
    n = 220
    distances = [1.0] * 49 + [0.985] * (n - 49)
    assert first_trap([(0.525, 0.525)] * n, distances) == (207, 207)


def test_driving_to_and_fro_over_old_ground_is_a_loop():
    # Between the middles of squares (0, 0) and (2, 0), 0.1 m apart, never closer. Updates 1 and 2 enter new
    # squares; from update 3 on every move is on ground visited before: 0.1 m each, 1.5 m >= 1.45 after 15 such
    # moves, update 17 (2.2 s: long before the 20 s time-out).
    a, b = (0.025, 0.025), (0.125, 0.025)
    positions = [a if k % 2 == 0 else b for k in range(40)]
    assert first_trap(positions, [1.0] * 40) == (17, 17)


def test_reset_measures_the_distance_afresh_but_keeps_the_ground():
    m = jaxmonitor.init(GRID)
    m, _ = _update(m, jnp.float32(0.128), jnp.float32(0.5), jnp.array([0.525, 0.525], jnp.float32), RULE)
    m = jaxmonitor.reset(m, jnp.float32(3.0))
    assert float(m.best) == np.inf and float(m.since) == 3.0 and float(m.looped) == 0.0
    assert bool(m.visited[10, 10]) and int(m.visited.sum()) == 1
    kept = jaxmonitor.reset(m, jnp.float32(9.0), when=False)
    assert float(kept.since) == 3.0


def test_aim_keeps_the_best_distance_of_the_last_eight_checkpoints_as_the_python_monitor_does():
    """Checkpoints 0, 1, …, 9 aimed at in turn, 0.5 m from each when it is left (ground updates far apart, no loop);
    then back to 2 (its 0.5 m comes back; the time-out goes on from 9 s), to 0 (forgotten: afresh at 11 s), and a
    reset. Each monitor's (best, since) after each step, the Python one the reference."""
    py = TrapMonitor(RULE.after, RULE.progress, RULE.ground, RULE.loop)
    m = jaxmonitor.init(GRID)
    aim = jax.jit(jaxmonitor.aim)
    seen = []
    for i in range(10):
        if i:
            py.aim(i, float(i))
            m = aim(m, jnp.int32(i), jnp.float32(i))
        p = (0.025 + 0.1 * i, 0.025)
        py.update(float(i), 0.5, p)
        m, _ = _update(m, jnp.float32(i), jnp.float32(0.5), jnp.asarray(p, jnp.float32), RULE)
    for i, t in ((2, 10.0), (0, 11.0), (1, 12.0)):
        py.aim(i, t)
        m = aim(m, jnp.int32(i), jnp.float32(t))
        seen.append(((py.best, py.since), (float(m.best), float(m.since))))
    assert [a for a, _ in seen] == [(0.5, 9.0), (np.inf, 11.0), (np.inf, 12.0)]  # 1 was evicted by 0's return
    assert [b for _, b in seen] == [a for a, _ in seen]
    m = jaxmonitor.reset(m, jnp.float32(13.0))
    assert int(m.index) == 0 and bool(jnp.all(m.keys == -1))
