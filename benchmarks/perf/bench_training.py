"""How fast online EKM training runs (docs/design.md §7): JAX vs NumPy, neurons, trials, the whole ch. 6.1 protocol.

Run from the repository root (takes a few minutes on 2 cores)::

    python benchmarks/perf/bench_training.py            # markdown tables
    python benchmarks/perf/bench_training.py --quick    # fewer sizes

Prints: (1) trial-steps/s of the jitted ``lax.scan``/``vmap`` loop and of the NumPy reference for
both mappings; (2) JAX cost vs lattice size 5×5 … 30×30 (5 trials); (3) JAX cost vs trials 1 … 64
(15×15); (4) wall time of the full protocol — 100,000 steps × 5 trials with the test every 10,000
steps — per mapping, the way ``ekm train`` runs it.
"""

from __future__ import annotations

import argparse
import time

import jax

from ekm.config import EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import evaluate
from training.throughput import jax_trial_steps_per_s, numpy_trial_steps_per_s
from training.online import TrainConfig
from training.run import train


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer sizes, no full protocol")
    args = ap.parse_args()
    print(f"jax {jax.__version__} on {jax.devices()}\n")

    print("| mapping | JAX trial-steps/s | NumPy trial-steps/s | ratio | JAX first call (s) |")
    print("|---|---:|---:|---:|---:|")
    for mapping in ("direct", "indirect"):
        cfg = EKMConfig(mapping=mapping)
        j = jax_trial_steps_per_s(cfg)
        n = numpy_trial_steps_per_s(cfg)
        print(f"| {mapping} | {j['trial_steps_per_s']:,.0f} | {n:,.0f} | {j['trial_steps_per_s'] / n:.1f} | "
              f"{j['first_call_s']:.1f} |")

    print("\n| neurons (5 trials, indirect) | trial-steps/s | µs per trial-step |")
    print("|---|---:|---:|")
    for n in (5, 10, 15) if args.quick else (5, 10, 15, 20, 30):
        r = jax_trial_steps_per_s(EKMConfig(neurons=n), steps=2000)["trial_steps_per_s"]
        print(f"| {n}×{n} | {r:,.0f} | {1e6 / r:.1f} |")

    print("\n| trials (15×15, indirect) | trial-steps/s | steps/s per trial |")
    print("|---:|---:|---:|")
    for t in (1, 4, 16) if args.quick else (1, 2, 4, 8, 16, 32, 64):
        r = jax_trial_steps_per_s(EKMConfig(), trials=t, steps=2000)["trial_steps_per_s"]
        print(f"| {t} | {r:,.0f} | {r / t:,.0f} |")

    if args.quick:
        return
    print("\n| full protocol (100,000 steps × 5 trials, test every 10,000) | seconds | E after (mm) |")
    print("|---|---:|---:|")
    for mapping in ("direct", "indirect"):
        cfg, tcfg = EKMConfig(mapping=mapping), TrainConfig()
        last = {}

        def on_eval(step, maps, cfg=cfg, tcfg=tcfg, last=last):
            last.update(summarize(evaluate(maps, cfg, tcfg.arena)))

        t0 = time.perf_counter()
        train(cfg, tcfg, eval_every=10_000, on_eval=on_eval)
        print(f"| {mapping} | {time.perf_counter() - t0:.1f} | {last['E_mm']:.2f} |")


if __name__ == "__main__":
    main()
