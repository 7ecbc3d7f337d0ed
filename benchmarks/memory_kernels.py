"""The three measurements behind the second speed round of the remembered obstacles (docs/speed.md).

Run from the repository root (about a minute)::

    python benchmarks/memory_kernels.py

1. **A reduction over a trailing axis of 2** against an elementwise op on the same (256, 12, 2) array, each
   jitted alone (µs per call, best of 11 blocks of 300 calls).
2. **The forget step of** :func:`robots.controllers.memory.update` **as it was** (rays as (m, 2) vectors, the
   sums over their axis of 2, cos/sin left for XLA to fuse into the (K, m) loop) **and as it is** (x/y
   components, directions behind ``lax.optimization_barrier``: :func:`memory.forget`), on one random memory of 256 points and 12
   readings: µs per call, and whether the two give the same bits.
3. **How many remembered points count** for the extended neural fields — stored, and nearer than the
   target — per tick, over seeds 0–2 of every named world (the shipped signed-chart map).
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from ekm.data import load_default_map  # noqa: E402
from evaluation.scenario import run_scenario  # noqa: E402
from robots.controllers import memory as mem  # noqa: E402
from robots.controllers.spec import parse_architectures  # noqa: E402
from robots.worldfile import load_world, named_worlds  # noqa: E402

K, M, RADIUS, RANGE, MERGE = 256, 12, 0.025, 0.175, 0.01


def per_call_us(fn, *args, calls: int = 300, blocks: int = 11) -> float:
    jax.block_until_ready(fn(*args))
    best = np.inf
    for _ in range(blocks):
        t0 = time.perf_counter()
        for _ in range(calls):
            jax.block_until_ready(fn(*args))
        best = min(best, (time.perf_counter() - t0) / calls)
    return best * 1e6


def forget_as_it_was(pts, seen, pose, readings, angles, t):
    """The forget step before the second round (git show fefe5d4:robots/controllers/memory.py)."""
    phi = pose[2] + angles
    direction = jnp.stack([jnp.cos(phi), jnp.sin(phi)], axis=-1)
    origin = pose[:2] + RADIUS * direction
    rel = pts[:, None, :] - origin[None, :, :]
    along = jnp.sum(rel * direction[None], axis=-1)
    across = jnp.abs(rel[..., 0] * direction[None, :, 1] - rel[..., 1] * direction[None, :, 0])
    free_to = jnp.where(jnp.isfinite(readings), readings, RANGE) - MERGE
    through = (along >= 0) & (along < free_to[None, :]) & (across < MERGE)
    return jnp.where(jnp.any(through, axis=1) | (t - seen > 60.0), -jnp.inf, seen)


def counted_points(seeds=(0, 1, 2)):
    """Per named world: (ticks, mean and p90 of the stored points, mean and p90 of those that count)."""
    spec = parse_architectures("fields")[0]
    maps = load_default_map(spec.default_chart)
    ctl = spec.build(jax.tree.map(lambda a: a[0], maps.ekm), maps.cfg)
    rows = {}
    for name in named_worlds():
        counts = []

        def step(state, obs):
            state, command = ctl.step(state, obs)
            u, valid = mem.egocentric(state.memory, obs.pose, radius=ctl.robot.radius)
            valid = np.asarray(valid)
            counts.append((valid.sum(), (valid & (np.asarray(u[:, 1]) < obs.target[1])).sum()))
            return state, command

        for seed in seeds:
            run_scenario(load_world(name), dataclasses.replace(ctl, step=step), seed=seed)
        a = np.asarray(counts)
        rows[name] = (len(a), a[:, 0].mean(), np.percentile(a[:, 0], 90), a[:, 1].mean(), np.percentile(a[:, 1], 90))
    return rows


def main() -> int:
    rng = np.random.default_rng(0)
    x = jnp.ones((K, M, 2))
    print(f"1. (256, 12, 2): sum over the trailing axis {per_call_us(jax.jit(lambda a: jnp.sum(a * a, -1)), x):.0f} µs, "
          f"elementwise {per_call_us(jax.jit(lambda a: a * 2 + 1), x):.0f} µs a call")
    pts = jnp.asarray(rng.uniform(0, 1, (K, 2)), jnp.float32)
    seen = jnp.asarray(np.where(rng.random(K) < 0.3, 1.0, -np.inf), jnp.float32)
    pose = jnp.asarray([0.5, 0.5, 0.3], jnp.float32)
    readings = jnp.asarray(np.where(rng.random(M) < 0.4, 0.05, np.inf), jnp.float32)
    angles = jnp.asarray(np.linspace(-np.pi, np.pi, M, endpoint=False), jnp.float32)
    args = (pts, seen, pose, readings, angles, jnp.float32(3.0))
    was = jax.jit(forget_as_it_was)
    now = jax.jit(lambda *a: mem.forget(*a, radius=RADIUS, range_m=RANGE, merge=MERGE, forget_after=60.0))
    same = np.array_equal(np.asarray(was(*args)), np.asarray(now(*args)))
    print(f"2. forget step: as it was {per_call_us(was, *args):.0f} µs, as it is {per_call_us(now, *args):.0f} µs a call; "
          f"same bits: {same}")
    print("3. remembered points per tick of the extended fields (seeds 0-2):")
    print("| world | ticks | stored: mean | p90 | counted: mean | p90 |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, (n, sm, sp, cm, cp) in counted_points().items():
        print(f"| {name} | {n} | {sm:.1f} | {sp:.0f} | {cm:.1f} | {cp:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
