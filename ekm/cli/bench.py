"""``ekm bench``: a quick speed check of the training loop, JAX vs the NumPy reference (the full study
is in ``benchmarks/``)."""

from __future__ import annotations

from ekm.cli.args import command, print_json, provenance


def add_parser(sub) -> None:
    p = command(sub, "bench", "quick speed check of the training loop (JAX against the NumPy reference)",
                ["ekm bench", "ekm bench --mapping direct --json"],
                more="The full study: python benchmarks/perf/bench_training.py (docs/performance.md).")
    p.add_argument("--mapping", choices=("direct", "indirect"), default="indirect",
                   help="which map's training step to time (default indirect)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Quick speed check: JAX training loop vs the NumPy reference (full study: benchmarks/)."""
    from training.throughput import quick

    result = quick(args.mapping)
    if args.json:
        print_json({**result, **provenance()})
        return
    print(f"online training, {result['mapping']} {result['neurons']}x{result['neurons']} map, "
          f"{result['trials']} trials, on {', '.join(result['devices'])} (jax {result['jax_version']})")
    print(f"  JAX (lax.scan + vmap): {result['jax_trial_steps_per_s']:>10,.0f} trial-steps/s, best chunk "
          f"(median {result['jax_median_trial_steps_per_s']:,.0f}; first call with compilation "
          f"{result['jax_first_call_s']:.1f} s; {result['devices_used']} device(s) used)")
    print(f"  NumPy reference:       {result['numpy_trial_steps_per_s']:>10,.0f} trial-steps/s")
    print(f"  ratio {result['ratio']:.1f}x; 100,000 steps x 5 trials take about {result['protocol_estimate_s']:.0f} s")
