"""XLA's CPU ``sin``/``cos`` against :func:`robots.trig.sincos`: time per element and error against float64.

Run from the repository root (a few seconds)::

    python benchmarks/trig_kernels.py

Both are jitted over (5,000 steps, 5 trials, 64 sub-steps) headings in [-10, 10] rad — the shape one
training chunk's kinematics evaluate — and timed alternately, the best and the median of ``--repeat``
calls each. The error is the largest absolute difference from NumPy's float64 ``sin``/``cos`` over
[-40, 40] rad.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from robots.trig import sincos  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=9)
    args = ap.parse_args(argv)
    kernels = {"XLA sin, cos": jax.jit(lambda a: (jnp.sin(a), jnp.cos(a))),
               "robots.trig.sincos": jax.jit(lambda a: sincos(a, jnp))}
    a = jnp.asarray(np.random.default_rng(0).uniform(-10, 10, (5000, 5, 64)), jnp.float32)
    times = {name: [] for name in kernels}
    for f in kernels.values():
        jax.block_until_ready(f(a))
    for _ in range(args.repeat):
        for name, f in kernels.items():
            t0 = time.perf_counter()
            jax.block_until_ready(f(a))
            times[name].append((time.perf_counter() - t0) / a.size * 1e9)
    grid = np.linspace(-40, 40, 4_000_001, dtype=np.float32)
    exact = grid.astype(np.float64)
    print(f"{a.size:,} headings; ns per element for the pair (sin and cos), best and median of {args.repeat}; "
          "largest error against float64 over [-40, 40] rad\n")
    print("| kernel | best ns | median ns | sin error | cos error |\n|---|---:|---:|---:|---:|")
    for name, f in kernels.items():
        s, c = (np.asarray(x, np.float64) for x in f(jnp.asarray(grid)))
        print(f"| {name} | {min(times[name]):.2f} | {np.median(times[name]):.2f} | "
              f"{np.max(np.abs(s - np.sin(exact))):.1e} | {np.max(np.abs(c - np.cos(exact))):.1e} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
