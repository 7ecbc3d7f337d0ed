"""The full ch. 6.1 protocol with the package defaults, both mappings: the tuning report's table.

5 trials × 100,000 training steps, 15×15 neurons, a test of 50 random targets every 10,000 steps (same
targets for every trial and checkpoint), 10 % actuator noise. Prints, per mapping, E at every
checkpoint, the final P/T/D at 5/10/25 mm, capped targets, and the per-trial spread; also the extent of
the trained neurons (Fig. 6.2: indirect to d ~ 0.16 m, direct to ~ 0.11 m).

Run: python -m benchmarks.protocol_ch61 [--seed S] [--trials R] [--steps N]   (~2 min on 2 cores)
"""

from __future__ import annotations

import argparse
import time

import jax
import jax.numpy as jnp
import numpy as np

from ekm.config import EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import run_test
from training.online import TrainConfig, random_points, start, train_chunk


def protocol(mapping: str, seed: int, trials: int, steps: int, every: int = 10_000, n_targets: int = 50):
    cfg, tcfg = EKMConfig(mapping=mapping), TrainConfig(steps=steps, trials=trials)
    root = jax.random.PRNGKey(seed)
    k_init, k_targets, k_test, k_train = jax.random.split(root, 4)
    trainees = jax.vmap(lambda k: start(k, cfg, tcfg))(jax.random.split(k_init, trials))
    targets = random_points(k_targets, (n_targets,), tcfg.arena, tcfg.margin)
    centre = jnp.asarray([0.5 * tcfg.arena[0], 0.5 * tcfg.arena[1], 0.0])
    test = jax.jit(jax.vmap(lambda m, k: run_test(m, targets, centre, k, cfg=cfg)))
    curve, rec = [], None
    for c in range(steps // every):
        keys = jax.random.split(jax.random.fold_in(k_train, c), trials)
        trainees = train_chunk(trainees, keys, float(c * every), length=every, cfg=cfg, tcfg=tcfg)
        rec = test(trainees.ekm, jax.random.split(k_test, trials))
        curve.append(summarize(rec)["E_mm"])
    return curve, rec, np.asarray(trainees.ekm.w)


def fmt(x):
    return "  -  " if x is None else f"{x:5.2f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--trials", type=int, default=5)
    ap.add_argument("--steps", type=int, default=100_000)
    args = ap.parse_args()
    for mapping in ("indirect", "direct"):
        t0 = time.time()
        curve, rec, w = protocol(mapping, args.seed, args.trials, args.steps)
        s = summarize(rec)
        per = [summarize(jax.tree.map(lambda a, i=i: a[i], rec)) for i in range(args.trials)]
        print(f"== {mapping}  ({args.trials} trials x {args.steps} steps, seed {args.seed}, {time.time() - t0:.0f} s)")
        print("E mm every 10k: " + " ".join(f"{e:.1f}" for e in curve))
        print(f"E {s['E_mm']:.2f} mm  capped {s['capped']}/{s['trials'] * s['targets']}")
        for key in ("5", "10", "25"):
            print(f"  eps {key:>2s} mm: P {s['P'][key]:.3f}  T {fmt(s['T'][key])} steps/m  D {fmt(s['D'][key])}")
        print("per trial E  " + " ".join(f"{p['E_mm']:5.1f}" for p in per))
        print("per trial P25" + " ".join(f"{p['P']['25']:6.2f}" for p in per))
        print("per trial T25" + " ".join(fmt(p['T']['25']).rjust(6) for p in per))
        print("per trial D25" + " ".join(fmt(p['D']['25']).rjust(6) for p in per))
        print("per trial cap" + " ".join(f"{p['capped']:6d}" for p in per))
        d = w[..., 1]
        fwd = np.mean(np.abs(w[..., 0]) < np.pi / 2, axis=1)
        print("neurons: d 95th pct (m) " + " ".join(f"{np.percentile(x, 95):.3f}" for x in d)
              + " | max " + " ".join(f"{x.max():.3f}" for x in d)
              + " | share |alpha|<pi/2 " + " ".join(f"{x:.2f}" for x in fwd), flush=True)


if __name__ == "__main__":
    main()
