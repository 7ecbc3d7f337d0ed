"""``ekm bench``: a quick speed check of the training loop, JAX vs the NumPy reference (the full study
is in ``benchmarks/``)."""

from __future__ import annotations

from ekm.cli.args import print_json, provenance


def add_parser(sub) -> None:
    p = sub.add_parser("bench", help="quick speed check of the training loop (JAX vs NumPy)")
    p.add_argument("--mapping", choices=("direct", "indirect"), default="indirect")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Quick speed check: JAX training loop vs the NumPy reference (full study: benchmarks/)."""
    from training.bench import quick

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
