"""The full ch. 6.1 protocol with the package defaults, both mappings, with per-trial spread.

Run from the repository root (about a minute)::

    python benchmarks/reproduce/protocol_ch61.py [--seed S] [--priority K] [--chart {signed,polar}]

5 trials × 100,000 steps, 15×15 neurons, the test of 50 random targets every 10,000 steps (the same
targets for every trial and checkpoint), 10 % actuator noise — exactly what ``ekm train`` runs. Prints
markdown: E at every checkpoint, the final E, P/T/D at 5/10/25 mm and capped targets, the per-trial
range, how far the trained neurons reach (Fig. 6.2: indirect to d ≈ 0.16 m, direct to ≈ 0.11 m) ahead
of the robot and behind it, and T(25), D(25) split by where each target appeared: ahead (|α| < π/2, the
robot drives forwards) or behind (it reverses).
"""

from __future__ import annotations

import argparse
import time

import jax
import numpy as np

from ekm.config import CHARTS, EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import evaluate
from training.online import TrainConfig
from training.run import train


def protocol(mapping: str, seed: int, priority: int | None = None, chart: str = "signed"):
    cfg, tcfg = EKMConfig(mapping=mapping, priority=priority, chart=chart), TrainConfig()
    curve, last = [], {}

    def on_eval(step, maps):
        last["rec"] = evaluate(maps, cfg, tcfg.arena)
        curve.append(summarize(last["rec"])["E_mm"])

    t0 = time.perf_counter()
    maps = train(cfg, tcfg, seed=seed, eval_every=10_000, on_eval=on_eval)
    return curve, last["rec"], np.asarray(maps.w), time.perf_counter() - t0


def split_table(rec) -> None:
    """T(25) and D(25) of the targets that appeared ahead of the robot and of those behind it."""
    ahead = np.abs(np.asarray(rec.bearing)) < np.pi / 2
    print("| target appeared | targets | P(25) | T(25) steps/m | D(25) |")
    print("|---|---:|---:|---:|---:|")
    for name, m in (("ahead (|α| < π/2)", ahead), ("behind", ~ahead)):
        sub = summarize(jax.tree.map(lambda a, m=m: np.asarray(a)[m][None], rec))
        print(f"| {name} | {int(m.sum())} | {sub['P']['25']:.3f} | {sub['T']['25']:.2f} | {sub['D']['25']:.3f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--priority", type=int, default=None, help="|A(α)| of Eq. 4.4 (default: N)")
    ap.add_argument("--chart", choices=CHARTS, default=CHARTS[0],
                    help="coordinates of the indirect map's linear model (ekm.charts; default signed)")
    args = ap.parse_args()
    for mapping in ("indirect", "direct"):
        curve, rec, w, seconds = protocol(mapping, args.seed, args.priority, args.chart)
        s = summarize(rec)
        per = [summarize(jax.tree.map(lambda a, i=i: a[i], rec)) for i in range(s["trials"])]
        print(f"\n### {mapping} (seed {args.seed}, chart {args.chart}, {seconds:.0f} s)\n")
        print("E (mm) at 0, 10k, …, 100k steps: " + ", ".join(f"{e:.1f}" for e in curve))
        print(f"\nE = {s['E_mm']:.2f} mm (trials {min(p['E_mm'] for p in per):.2f}–{max(p['E_mm'] for p in per):.2f}), "
              f"capped {s['capped']} of {s['trials'] * s['targets']}\n")
        print("| ε (mm) | P(ε) | T(ε) steps/m | T range over trials | D(ε) | D range over trials |")
        print("|---:|---:|---:|---|---:|---|")
        for e in ("5", "10", "25"):
            ts = [p["T"][e] for p in per if p["T"][e] is not None]
            ds = [p["D"][e] for p in per if p["D"][e] is not None]
            print(f"| {e} | {s['P'][e]:.3f} | {s['T'][e]:.2f} | {min(ts):.2f}–{max(ts):.2f} | {s['D'][e]:.3f} | "
                  f"{min(ds):.3f}–{max(ds):.3f} |")
        d, fwd = w[..., 1], np.abs(w[..., 0]) < np.pi / 2
        reach = [np.mean([d[i][m[i]].max() for i in range(len(d))]) for m in (fwd, ~fwd)]
        print(f"\nneurons reach d = {np.mean(d.max(axis=1)):.3f} m (max), {np.mean(np.percentile(d, 95, axis=1)):.3f} m "
              f"(95th percentile); {np.mean(fwd):.0%} encode |α| < π/2 and reach {reach[0]:.3f} m, the others "
              f"{reach[1]:.3f} m\n")
        split_table(rec)


if __name__ == "__main__":
    main()
