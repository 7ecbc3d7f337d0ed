"""Do the two engines agree on a whole task? One fixed policy through ``ekm/Khepera-v0`` on pymunk (``ekm.gym``) and
through the JAX task (``robots.jaxworld.task``), 10 seeds per named world: goal reached (stopped there without a
collision) with its 95 % Wilson interval, mean collisions, mean time of the runs that reach.

    python benchmarks/perf/agreement_gym.py
    python benchmarks/perf/agreement_gym.py --worlds open-arena,three-rooms --seeds 20 --time-limit 60

The policy steers at the current checkpoint of the observation (α, d): forward speed ``0.12 cos α`` (none when
the checkpoint is behind), slowed within 5 cm, turn rate ``2 α``, and a stop command within 4 mm of it. It has no
obstacle avoidance: the plan's checkpoints lead round the known shapes. The pymunk environment also has the trap
monitor's replanning, which the JAX task has not; runs differ one by one (different noise streams) and should
agree in their rates.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def policy(obs, xp=np, base: float = 0.053):
    """Wheel speeds ``(..., 2)`` for observations ``(..., m + 2)`` (module docstring)."""
    alpha, d = obs[..., -2], obs[..., -1]
    v = 0.12 * xp.clip(xp.cos(alpha), 0.0, 1.0) * xp.minimum(1.0, d / 0.05)
    w = 2.0 * alpha
    wheels = xp.stack([v - 0.5 * base * w, v + 0.5 * base * w], axis=-1)
    return xp.where((d < 0.004)[..., None], 0.0, wheels)


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson score interval of k successes in n."""
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    centre, half = p + z * z / (2 * n), z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (max(0.0, (centre - half) / (1 + z * z / n)), min(1.0, (centre + half) / (1 + z * z / n)))


def pymunk_runs(world: str, seeds: int, time_limit: float) -> list[tuple[bool, int, float]]:
    from ekm.gym import KheperaEnv

    env, out = KheperaEnv(world=world, time_limit=time_limit), []
    for seed in range(seeds):
        obs, _ = env.reset(seed=seed)
        while True:
            obs, _, terminated, truncated, info = env.step(policy(obs))
            if terminated or truncated:
                o = info["outcome"]
                out.append((bool(o["reached"]), int(o["collisions"]), float(o["time_s"])))
                break
    return out


def jax_runs(world: str, seeds: int, time_limit: float) -> list[tuple[bool, int, float]]:
    import jax
    import jax.numpy as jnp

    from ekm.api.worlds import world as load_world
    from robots.jaxworld import task as jt

    config = jt.config_for(time_limit=time_limit)
    task = jax.tree.map(jnp.asarray, jt.make_task(load_world(world), config))

    def run(key):
        state, obs = jt.reset(key, task, config)

        def tick(carry, _):
            state, obs, done, reached, t = carry
            new, new_obs, _, terminated, truncated = jt.step(state, policy(obs, jnp), task, config)
            keep = lambda a, b: jnp.where(done, a, b)
            state = jax.tree.map(keep, state, new)
            reached = reached | (~done & terminated & (new.engine.collisions == 0))
            t = jnp.where(done, t, new.tick.astype(jnp.float32) * config.params.avoid_period)
            return (state, keep(obs, new_obs), done | terminated | truncated, reached, t), None

        init = (state, obs, jnp.bool_(False), jnp.bool_(False), jnp.float32(0.0))
        (state, _, _, reached, t), _ = jax.lax.scan(tick, init, None, length=config.ticks)
        return reached, state.engine.collisions, t

    keys = jax.vmap(jax.random.fold_in, in_axes=(None, 0))(jax.random.key(0), jnp.arange(seeds))
    reached, collisions, t = jax.jit(jax.vmap(run))(keys)
    return list(zip(np.asarray(reached).tolist(), np.asarray(collisions).tolist(), np.asarray(t).tolist()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", default="open-arena,three-rooms,three-rooms-static,concave-obstacle,"
                                            "extended-obstacle")
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--time-limit", type=float, default=60.0)
    args = parser.parse_args()
    print("| world | engine | reached | 95 % interval | collisions (mean) | time of reached runs (s) | wall s |")
    print("|---|---|---|---|---|---|---|")
    for world in args.worlds.split(","):
        for name, runs in (("pymunk", pymunk_runs), ("jax", jax_runs)):
            t0 = time.perf_counter()
            out = runs(world, args.seeds, args.time_limit)
            wall = time.perf_counter() - t0
            k = sum(r for r, _, _ in out)
            lo, hi = wilson(k, len(out))
            times = [t for r, _, t in out if r]
            mean_t = f"{np.mean(times):.1f}" if times else "–"
            collisions = np.mean([c for _, c, _ in out])
            print(f"| {world} | {name} | {k}/{len(out)} | {lo:.2f}–{hi:.2f} | {collisions:.1f} | {mean_t} | {wall:.1f} |",
                  flush=True)


if __name__ == "__main__":
    main()
