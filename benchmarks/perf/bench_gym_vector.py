"""Env steps per second of ``ekm/Khepera-v0``'s vector environment on the JAX engine against Gymnasium's
``SyncVectorEnv`` of the pymunk environment: random actions, long-range IR, one world.

    python benchmarks/perf/bench_gym_vector.py                              # three-rooms, 1..4096 envs
    python benchmarks/perf/bench_gym_vector.py --envs 1,64,4096 --world open-arena --sync-envs 8

An env step is one 0.128 s tick of one robot: ``num_envs`` of them per ``step()`` call. The JAX environment uses the
devices JAX sees (``JAX_PLATFORMS``; on a GPU the same script runs there); compilation and a warm-up are left out,
then ``--calls`` calls are timed (episodes that end are autoreset inside the calls). The pymunk row is Gymnasium's
``make_vec(..., vectorization_mode="sync")`` with ``--sync-envs`` environments, stepped ``--sync-steps`` times.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def jax_rate(world: str, n: int, calls: int) -> tuple[float, float]:
    """(steps/s, compile s) of the JAX vector environment with ``n`` environments."""
    import gymnasium

    import ekm.gym  # noqa: F401

    envs = gymnasium.make_vec("ekm/Khepera-v0", num_envs=n, vectorization_mode="vector_entry_point", world=world)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-0.16, 0.16, (calls + 3, n, 2)).astype(np.float32)
    t0 = time.perf_counter()
    envs.reset(seed=0)
    envs.step(actions[0])
    compile_s = time.perf_counter() - t0
    for a in actions[1:3]:
        envs.step(a)
    t0 = time.perf_counter()
    for a in actions[3:]:
        envs.step(a)
    return n * calls / (time.perf_counter() - t0), compile_s


def sync_rate(world: str, n: int, steps: int) -> float:
    """steps/s of Gymnasium's SyncVectorEnv of ``n`` pymunk environments."""
    import gymnasium

    import ekm.gym  # noqa: F401

    envs = gymnasium.make_vec("ekm/Khepera-v0", num_envs=n, vectorization_mode="sync", world=world)
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(20):
        envs.step(rng.uniform(-0.16, 0.16, (n, 2)))
    t0 = time.perf_counter()
    for _ in range(steps):
        envs.step(rng.uniform(-0.16, 0.16, (n, 2)))
    return n * steps / (time.perf_counter() - t0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--world", default="three-rooms")
    parser.add_argument("--envs", default="1,16,256,4096", help="JAX environments per call, comma-separated")
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--sync-envs", type=int, default=8)
    parser.add_argument("--sync-steps", type=int, default=150)
    args = parser.parse_args()

    import jax

    print(f"devices: {jax.devices()}")
    pymunk = sync_rate(args.world, args.sync_envs, args.sync_steps)
    print(f"{'engine':<8} {'envs':>6} {'steps/s':>10} {'x pymunk':>9} {'compile s':>9}")
    print(f"{'pymunk':<8} {args.sync_envs:>6} {pymunk:>10.0f} {1.0:>9.1f} {'':>9}")
    for n in (int(x) for x in args.envs.split(",")):
        rate, compile_s = jax_rate(args.world, n, args.calls)
        print(f"{'jax':<8} {n:>6} {rate:>10.0f} {rate / pymunk:>9.1f} {compile_s:>9.1f}")


if __name__ == "__main__":
    main()
