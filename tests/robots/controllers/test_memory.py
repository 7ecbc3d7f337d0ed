"""The memory of obstacles (robots.controllers.memory) of the extended fields and the other architectures that
remember: what it keeps, merges, clears and forgets, the body's width along a direction, and the fast paths,
which give what the plain ones give."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from robots.controllers import memory
from robots.controllers.memory import _add_hits, _add_hits_in_turn, over_packed
from robots.controllers.spec import parse_architecture
from robots.params import LONG_RANGE
from tests.robots.controllers.observations import long_ring, observation


def test_memory_keeps_hits_merges_repeats_clears_what_a_ray_sees_through_and_forgets_old_points():
    angles = jnp.asarray(LONG_RANGE.angles, jnp.float32)
    kw = dict(radius=0.025, range_m=0.175, merge=0.01, forget_after=10.0)
    m = memory.empty(16)
    pose = jnp.asarray([0.5, 0.5, 0.0])
    ir = np.full(12, np.inf)
    ir[0] = 0.1  # a point 12.5 cm ahead of the centre
    m = memory.update(m, pose, jnp.asarray(ir), angles, 0.0, **kw)
    assert int(jnp.sum(jnp.isfinite(m.seen))) == 1
    np.testing.assert_allclose(np.asarray(m.points[0]), [0.625, 0.5], atol=1e-6)
    m = memory.update(m, pose, jnp.asarray(ir * 1.02), angles, 1.0, **kw)  # the same point again: refreshed
    assert int(jnp.sum(jnp.isfinite(m.seen))) == 1 and float(m.seen[0]) == 1.0
    u, valid = memory.egocentric(m, jnp.asarray([0.5, 0.4, math.pi / 2]), radius=0.025)
    np.testing.assert_allclose(np.asarray(u[0]), [-math.atan2(0.125, 0.1), math.hypot(0.125, 0.1) - 0.025], atol=1e-6)
    kept = memory.update(m, pose, jnp.full(12, jnp.inf), angles, 5.0, **{**kw, "range_m": 0.05})  # ray too short
    assert int(jnp.sum(jnp.isfinite(kept.seen))) == 1
    cleared = memory.update(m, pose, jnp.full(12, jnp.inf), angles, 2.0, **kw)  # the ray now sees through it
    assert int(jnp.sum(jnp.isfinite(cleared.seen))) == 0
    forgotten = memory.update(m, jnp.asarray([0.1, 0.1, 0.0]), jnp.full(12, jnp.inf), angles, 11.5, **kw)
    assert int(jnp.sum(jnp.isfinite(forgotten.seen))) == 0


def test_blocked_along_uses_the_bodys_width_at_the_obstacles_distance():
    u = jnp.asarray([[0.0, 0.2]])  # an obstacle 20 cm ahead (from the surface)
    dirs = jnp.radians(jnp.asarray([0.0, 5.0, 8.8, 9.2]))
    blocked = np.asarray(memory.blocked_along(dirs, 0.5, u, jnp.asarray([True]), radius=0.025, clearance=0.01))
    assert blocked.tolist() == [True, True, True, False]  # asin(0.035 / 0.225) = 8.95 degrees
    assert not bool(memory.blocked_along(dirs[:1], 0.15, u, jnp.asarray([True]), radius=0.025, clearance=0.01)[0])


def test_blocked_along_measures_how_far_the_centre_travels_before_the_grown_body_touches():
    """By hand, R = 2.5 cm, clearance 1 cm (grown 3.5 cm). Straight ahead, a point 20 cm from the surface (22.5 cm
    from the centre) is touched after 22.5 − 3.5 = 19 cm: it blocks a reach of 19.5 cm, not one of 18.5 cm. A point
    19 cm along and 3.4 cm across (19.3018 cm from the centre, d = 16.8018 cm) is touched after
    19 − √(3.5² − 3.4²) = 19 − 0.83066 = 18.1693 cm: it does not block a target 17.5 cm ahead, though nearer than it
    from the body's surface (a wall beside a checkpoint at a bend), and blocks one 18.5 cm ahead."""
    kw = dict(radius=0.025, clearance=0.01)
    ahead = jnp.zeros(1)
    on = jnp.asarray([True])
    head_on = jnp.asarray([[0.0, 0.2]], jnp.float32)
    assert bool(memory.blocked_along(ahead, 0.195, head_on, on, **kw)[0])
    assert not bool(memory.blocked_along(ahead, 0.185, head_on, on, **kw)[0])
    beside = jnp.asarray([[math.atan2(0.034, 0.19), math.hypot(0.19, 0.034) - 0.025]], jnp.float32)
    assert not bool(memory.blocked_along(ahead, 0.175, beside, on, **kw)[0])
    assert bool(memory.blocked_along(ahead, 0.185, beside, on, **kw)[0])


# ----------------------------------------------------------------------------------------------- fast paths

# `_add_hits` adds a tick's hits without a loop over the memory; `_add_hits_in_turn` is the definition (one
# hit after the other). `over_packed` runs a per-point function on the points that count only.

FAST = jax.jit(_add_hits, static_argnames="merge")
IN_TURN = jax.jit(_add_hits_in_turn, static_argnames="merge")


def random_tick(rng, k: int, m: int):
    """A memory of ``k`` slots, some empty, and ``m`` hits, all within a few merge radii of each other (so that
    hits merge with points, with each other, and overwrite points they would have merged with)."""
    scale = rng.choice([0.01, 0.03, 0.1])
    pts = rng.uniform(0, scale, (k, 2)).astype(np.float32)
    seen = np.where(rng.random(k) < rng.random(), rng.uniform(0, 5, k), -np.inf).astype(np.float32)
    hits = rng.uniform(0, scale, (m, 2)).astype(np.float32)
    if rng.random() < 0.3:
        hits[rng.integers(m)] = hits[rng.integers(m)]  # two sensors see the same point
    ok = rng.random(m) < rng.random()
    moving, on_mover = rng.random(k) < 0.5, rng.random(m) < 0.5
    return pts, seen, np.int32(rng.integers(k)), moving, hits, ok, on_mover, np.float32(rng.uniform(5, 10))


@pytest.mark.parametrize("k, m", [(12, 12), (16, 8), (256, 12)])
def test_adding_hits_at_once_equals_adding_them_one_after_the_other_to_the_bit(k, m):
    rng = np.random.default_rng(k * 100 + m)
    for _ in range(150):
        tick = random_tick(rng, k, m)
        fast, in_turn = FAST(*tick, merge=0.01), IN_TURN(*tick, merge=0.01)
        for a, b in zip(fast, in_turn):
            np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


def test_a_wrapping_ring_overwrites_the_point_a_later_hit_would_have_merged_with():
    # Slot 0 holds a point at the origin; the ring's next slot is 1 of 2. Hit 0 (far away) goes to slot 1,
    # hit 1 (far away, elsewhere) wraps round to slot 0 and overwrites the origin point; hit 2 at the origin
    # then finds nothing to merge with and is put again, into slot 1.
    pts = np.array([[0.0, 0.0], [9.0, 9.0]], np.float32)
    seen = np.array([1.0, -np.inf], np.float32)
    hits = np.array([[1.0, 1.0], [2.0, 2.0], [0.0, 0.0]], np.float32)
    ok = np.ones(3, bool)
    out = IN_TURN(pts, seen, np.int32(1), np.zeros(2, bool), hits, ok, np.zeros(3, bool), np.float32(3.0), merge=0.01)
    np.testing.assert_array_equal(np.asarray(out[0]), [[2.0, 2.0], [0.0, 0.0]])
    np.testing.assert_array_equal(np.asarray(out[1]), [3.0, 3.0])
    assert int(out[2]) == 0


def per_point(u, valid):
    """Sum, any and min over the valid rows — the kinds of per-neuron work the fields and Samba do."""
    x = jnp.where(valid[:, None], jnp.exp(-u[:, :1] * jnp.arange(1.0, 6.0)), 0.0)
    return x.sum(axis=0), jnp.any(valid & (u[:, 1] > 0.5)), jnp.min(jnp.where(valid, u[:, 1], jnp.inf))


# Compiled once for every count below (the shapes are the same), not once per test.
WHOLE = jax.jit(per_point)
PACKED = jax.jit(lambda u, v: over_packed(per_point, u, v))


@pytest.mark.parametrize("count", [0, 1, 16, 17, 64, 65, 200])
def test_over_packed_gives_what_the_whole_memory_gives(count):
    rng = np.random.default_rng(count)
    u = rng.uniform(0, 1, (200, 2)).astype(np.float32)
    valid = np.zeros(200, bool)
    valid[rng.choice(200, count, replace=False)] = True
    whole = WHOLE(u, valid)
    packed = PACKED(u, valid)
    np.testing.assert_allclose(np.asarray(packed[0]), np.asarray(whole[0]), rtol=1e-6)  # a sum: order may differ
    assert bool(packed[1]) == bool(whole[1])
    assert float(packed[2]) == float(whole[2])  # a min: exact
    if count:
        assert float(whole[0][0]) > 0


@pytest.mark.parametrize("beside, through, kept", [(0.008, None, False), (0.008, 0.005, True), (0.003, 0.005, False)])
def test_a_ray_forgets_a_point_it_passes_within_through_of_and_keeps_one_beside_it(beside, through, kept):
    """A point remembered at (0.625, 0.5); the robot at (0.5, 0.5 + beside) facing +x, nothing seen. Its ray 0
    starts on the rim at (0.525, 0.5 + beside) and passes the point 0.1 m along it and ``beside`` across, short of
    its free length (0.175 - 0.01 m); the rays at ±30° pass it 5.5 cm and more away. Within ``through`` (``merge``,
    1 cm, when None) it is forgotten: 8 mm beside the ray with the old 1 cm, 3 mm beside it with 5 mm. 8 mm
    beside it with 5 mm it is kept: the ray that just misses a wall's end proves free its own line, not the end."""
    angles = jnp.asarray(LONG_RANGE.angles, jnp.float32)
    kw = dict(radius=0.025, range_m=0.175, merge=0.01, forget_after=10.0)
    ir = np.full(12, np.inf)
    ir[0] = 0.1
    m = memory.update(memory.empty(16), jnp.asarray([0.5, 0.5, 0.0]), jnp.asarray(ir), angles, 0.0, **kw)
    np.testing.assert_allclose(np.asarray(m.points[0]), [0.625, 0.5], atol=1e-6)
    after = memory.update(m, jnp.asarray([0.5, 0.5 + beside, 0.0]), jnp.full(12, jnp.inf), angles, 1.0, through=through,
                          **kw)
    assert int(jnp.sum(jnp.isfinite(after.seen))) == int(kept)


@pytest.mark.parametrize("mover_at, kept", [(None, True), ((0.645, 0.5), False), ((0.745, 0.5), True)])
def test_a_point_sensed_on_a_declared_mover_is_forgotten_by_a_ray_passing_beside_it(mover_at, kept):
    """The point of the test above, seen at (0.625, 0.5) with a declared mover of radius 2 cm at ``mover_at``: centred
    2 cm behind the point, the hit is on the mover's surface and remembered as moving — the ray passing 8 mm beside
    it a tick later forgets it within ``merge`` (1 cm), as a mover's trail must clear; a mover 12 cm behind the
    point (10 cm from its surface, beyond the 1 cm binding margin) leaves the hit still, kept within ``through``."""
    angles = jnp.asarray(LONG_RANGE.angles, jnp.float32)
    kw = dict(radius=0.025, range_m=0.175, merge=0.01, forget_after=10.0, through=0.005)
    markers = np.zeros((0, 5), np.float32) if mover_at is None else np.array([[*mover_at, 0.0, 0.0, 0.02]], np.float32)
    ir = np.full(12, np.inf)
    ir[0] = 0.1
    m = memory.update(memory.empty(16), jnp.asarray([0.5, 0.5, 0.0]), jnp.asarray(ir), angles, 0.0,
                      markers=jnp.asarray(markers), **kw)
    assert bool(m.moving[0]) == (not kept)
    after = memory.update(m, jnp.asarray([0.5, 0.508, 0.0]), jnp.full(12, jnp.inf), angles, 1.0,
                          markers=jnp.asarray(markers), **kw)
    assert int(jnp.sum(jnp.isfinite(after.seen))) == int(kept)


@pytest.mark.parametrize("spec, kept", [("samba", True), ("samba:see_through=0.01", False), ("damn", True),
                                        ("subsumption", True), ("deliberation", False),
                                        ("deliberation:see_through=0.005", True)])
def test_each_architecture_that_remembers_forgets_a_point_a_ray_passes_beside_within_its_see_through(spec, kept):
    """Through each architecture's own step: tick 1 at (0.5, 0.5) facing +x, sensor 0 sees a pillar's edge 10 cm
    ahead, remembered at (0.625, 0.5); tick 2 at (0.5, 0.508), nothing seen: sensor 0's ray passes 8 mm beside the
    point, 10 cm along (the other rays 6 cm and more away). Samba, DAMN and subsumption forget within 5 mm by
    default and keep it — with 1 cm (merge) a ray grazing a pillar forgot its edge and the robot drove into it;
    reactive deliberation keeps the 1 cm, which forgets it (docs/reproduce/every-kind.md)."""
    ctl = parse_architecture(spec).build()
    state, _ = ctl.step(ctl.init(), observation(long_ring(s0=0.1), target=(0.0, 0.3)))
    assert int(np.isfinite(np.asarray(state.memory.seen)).sum()) == 1
    np.testing.assert_allclose(np.asarray(state.memory.points)[np.isfinite(np.asarray(state.memory.seen))][0],
                               [0.625, 0.5], atol=1e-6)
    state, _ = ctl.step(state, observation(long_ring(), target=(0.0, 0.3), t=0.128, pose=(0.5, 0.508, 0.0)))
    assert int(np.isfinite(np.asarray(state.memory.seen)).sum()) == int(kept)
