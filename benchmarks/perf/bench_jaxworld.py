"""Runs per second and simulated seconds per wall second of the JAX world (robots.jaxworld) against the batch size,
on every device present — CPU devices or a GPU.

    python benchmarks/perf/bench_jaxworld.py                                # 1..10,000 runs, the devices present
    python benchmarks/perf/bench_jaxworld.py --cpu-devices 2 --sizes 1,100,1000 --ticks 100

A run is ``--ticks`` control periods (0.128 s) of one robot in ``--world``: sense the 12 long-range IR, send a
command, eight sub-steps with contact. Commands and all noise are drawn up front; the ticks are one ``lax.scan``,
the runs one ``vmap``, and the batch is sharded over the devices along the runs (``--cpu-devices N`` makes XLA show
N CPU devices; it must be set before JAX starts, so the script sets it). Compilation is left out (one warm-up call).
"""

from __future__ import annotations

import argparse
import os
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--world", default="three-rooms")
    parser.add_argument("--sizes", default="1,10,100,1000,10000")
    parser.add_argument("--ticks", type=int, default=100)
    parser.add_argument("--block", type=int, default=16, help="runs vmapped together (lax.map over blocks; 0: all)")
    parser.add_argument("--cpu-devices", type=int, default=0, help="show this many CPU devices to XLA (0: as is)")
    args = parser.parse_args()
    if args.cpu_devices:
        os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") +
                                   f" --xla_force_host_platform_device_count={args.cpu_devices}")

    import jax
    import jax.numpy as jnp
    import numpy as np
    from jax.sharding import Mesh, NamedSharding, PartitionSpec

    from ekm.api.worlds import world as load_world
    from robots.jaxworld import engine
    from robots.jaxworld.scene import scene_of
    from robots.params import KHEPERA

    world = load_world(args.world)
    scene = jax.tree.map(jnp.asarray, scene_of(world))
    sensors, n = KHEPERA.long_range, KHEPERA.substeps(KHEPERA.avoid_period)
    start = jnp.asarray(world.start, jnp.float32)
    devices = jax.devices()
    mesh = Mesh(np.array(devices), ("runs",))

    def run(commands, slip, ir_noise):
        def tick(state, x):
            command, xi, eta = x
            readings = engine.sense(state, scene, sensors, eta)
            state, _ = engine.step(state, scene, command, xi, KHEPERA, n)
            return state, readings[0]

        state, first = jax.lax.scan(tick, engine.reset(start, scene), (commands, slip, ir_noise))
        return state.robot.pose, state.collisions, first

    if args.block:
        batch = jax.jit(lambda *xs: jax.lax.map(lambda x: run(*x), xs, batch_size=min(args.block, xs[0].shape[0])))
    else:
        batch = jax.jit(jax.vmap(run))
    print(f"devices: {devices}")
    print(f"{'runs':>6} {'ticks':>5} {'wall s':>8} {'runs/s':>9} {'sim s / wall s':>14} {'ticks/s':>10}")
    for size in (int(s) for s in args.sizes.split(",")):
        padded = -(-size // len(devices)) * len(devices)
        rng = np.random.default_rng(0)
        data = (rng.uniform(-0.05, 0.16, (padded, args.ticks, 2)).astype(np.float32),
                rng.uniform(-1, 1, (padded, args.ticks, 4, 2)).astype(np.float32),
                rng.standard_normal((padded, args.ticks, len(sensors.angles))).astype(np.float32))
        sharding = NamedSharding(mesh, PartitionSpec("runs"))
        data = tuple(jax.device_put(x, sharding) for x in data)
        jax.block_until_ready(batch(*data))
        t0 = time.perf_counter()
        jax.block_until_ready(batch(*data))
        wall = time.perf_counter() - t0
        sim = size * args.ticks * KHEPERA.avoid_period
        print(f"{size:>6} {args.ticks:>5} {wall:>8.3f} {size / wall:>9.1f} {sim / wall:>14.0f} "
              f"{size * args.ticks / wall:>10.0f}", flush=True)


if __name__ == "__main__":
    main()
