"""The measurements behind the third speed round, of the training step (docs/speed.md).

Run from the repository root (about 2 minutes)::

    python benchmarks/training_kernels.py

1. **wrap against wrap_once** on (5 trials, 225) angle differences, each in a jitted scan of 2,000 steps
   (µs per step, median of 7), and whether they give the same bits on a million angles in [-2π, 2π].
2. **The winner search in the training chunk**: ``train_chunk`` (indirect, 15×15, 5 trials, 5,000 steps)
   compiled once with :func:`ekm.kohonen.winner` and once with :func:`ekm.kohonen.winner_by_partition`
   (A(α) from ``jnp.partition``), called alternately in one process, 8 times each: trial-steps/s
   (median). Both give the same maps.
3. **How the search ends** over 5 chunks of 2,000 training steps (seed 0): the share of searches won by
   the first candidate, and rounds of the loop per batched search (5 trials) when a failed candidate rules
   out only itself and when it rules out every neuron at least as far in angle (the shipped rule).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

import ekm.direct  # noqa: E402
import ekm.indirect  # noqa: E402
from ekm import kohonen  # noqa: E402
from ekm.config import EKMConfig  # noqa: E402
from training.online import TrainConfig, start, train_chunk  # noqa: E402


def per_step_us(f, x, n: int = 2000) -> float:
    g = jax.jit(lambda x: jax.lax.scan(lambda c, _: (f(c) * 0.999 + x * 0.001, None), x, None, length=n)[0])
    jax.block_until_ready(g(x))
    times = []
    for _ in range(7):
        t = time.perf_counter()
        jax.block_until_ready(g(x))
        times.append(time.perf_counter() - t)
    return float(np.median(times)) / n * 1e6


def counted_search(rule_out_all: bool, rounds: list):
    """:func:`kohonen.winner` that records its loop's rounds; ``rule_out_all`` False: one neuron a round."""
    def search(w, u, cfg):
        dalpha, dist2 = kohonen._distances(w, u, cfg)

        def found(k, d2):
            return (jnp.sum(dalpha < dalpha[k]) < cfg.a_size) | (d2 == jnp.inf)

        def rule_out(carry):
            k, out, _, n = carry
            out = out | ((dalpha >= dalpha[k]) if rule_out_all else (jnp.arange(cfg.size) == k))
            k = jnp.argmin(jnp.where(out, jnp.inf, dist2))
            return k, out, found(k, jnp.where(out, jnp.inf, dist2)[k]), n + 1

        k = jnp.argmin(dist2)
        start_ = (k, jnp.zeros(cfg.size, bool), found(k, dist2[k]), 0)
        k, _, _, n = jax.lax.while_loop(lambda c: ~c[2], rule_out, start_)
        jax.debug.callback(lambda n: rounds.append(int(n)), n)
        return k
    return search


def main() -> int:
    x = jax.random.uniform(jax.random.PRNGKey(0), (5, 225), minval=-2 * np.pi, maxval=2 * np.pi)
    print(f"1. (5, 225) angles, µs per scan step: wrap {per_step_us(kohonen.wrap, x):.2f}, "
          f"wrap_once {per_step_us(kohonen.wrap_once, x):.2f}, identity {per_step_us(lambda a: a, x):.2f}")
    a = jax.random.uniform(jax.random.PRNGKey(1), (1_000_000,), minval=-2 * np.pi, maxval=2 * np.pi)
    same = bool(jnp.all(jax.jit(kohonen.wrap)(a).view(jnp.int32) == jax.jit(kohonen.wrap_once)(a).view(jnp.int32)))
    print(f"   same bits on a million angles in [-2π, 2π]: {same}")

    cfg, tcfg = EKMConfig(), TrainConfig(steps=100_000, trials=5)
    keys = jax.random.split(jax.random.PRNGKey(0), 5)
    s0 = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    searches = {"winner (nearest first)": kohonen.winner, "winner_by_partition": kohonen.winner_by_partition}
    length, rates, out = {}, {}, {}
    for i, (name, search) in enumerate(searches.items()):
        ekm.indirect.winner = search  # the chunk is traced now, with this search; distinct lengths compile apart
        length[name] = 5000 + i
        out[name] = jax.block_until_ready(train_chunk(s0, keys, 0.0, length=length[name], cfg=cfg, tcfg=tcfg))
    for _ in range(8):
        for name in searches:
            t = time.perf_counter()
            jax.block_until_ready(train_chunk(s0, keys, 0.0, length=length[name], cfg=cfg, tcfg=tcfg))
            rates.setdefault(name, []).append(5 * length[name] / (time.perf_counter() - t))
    print("2. training chunk, trial-steps/s (median of 8, alternating): "
          + ", ".join(f"{n} {np.median(r):,.0f}" for n, r in rates.items()))

    print("3. how the search ends (seed 0, 5 chunks of 2,000 steps; rounds per batched search of 5 trials):")
    for label, rule_out_all in (("one neuron ruled out a round", False), ("all as far in angle (shipped)", True)):
        rounds: list = []
        ekm.indirect.winner = counted_search(rule_out_all, rounds)
        s = s0
        for c in range(5):
            s = jax.block_until_ready(train_chunk(s, jax.random.split(keys[0] + c, 5), float(c * 20_000),
                                                  length=2000 + 10 * rule_out_all, cfg=cfg, tcfg=tcfg))
        r = np.asarray(rounds).reshape(-1, 5)
        print(f"   {label}: first candidate wins {np.mean(r == 0):.1%} of searches; "
              f"{r.max(axis=1).mean():.2f} rounds per batched search; at most {r.max()}")
    ekm.indirect.winner = kohonen.winner
    return 0


if __name__ == "__main__":
    sys.exit(main())
