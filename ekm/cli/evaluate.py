"""``ekm evaluate``: run the ch. 6.1 positioning test on saved maps (and draw Fig. 6.1/6.2 and their
paths for them)."""

from __future__ import annotations

from ekm.cli.args import nonneg_int, output_path, positive_int, print_json, provenance
from ekm.cli.summary import print_summary, summarize_test


def add_parser(sub) -> None:
    p = sub.add_parser("evaluate", help="run the ch. 6.1 positioning test on saved maps")
    p.add_argument("maps", nargs="+", metavar="MAP.npz", help="map file(s) from ekm train; several share one plot")
    p.add_argument("--targets", type=positive_int, default=50, help="test targets (default 50)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="seed of the test targets and noise (default 0)")
    p.add_argument("--plot", metavar="PNG", help="draw Fig. 6.1/6.2 with all maps on the same axes")
    p.add_argument("--paths", metavar="PNG", help="draw each map's paths through the first 10 test targets")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Run the ch. 6.1 test on saved maps (and draw Fig. 6.1/6.2 for them)."""
    from pathlib import Path

    import numpy as np

    from ekm.mapfile import load_maps

    plot = output_path(args.plot, "--plot", ".png") if args.plot else None
    paths = output_path(args.paths, "--paths", ".png") if args.paths else None
    loaded = [load_maps(path) for path in args.maps]
    results = []
    for path, saved in zip(args.maps, loaded):
        s = summarize_test(saved.ekm, saved.cfg, saved.arena, args.targets, args.seed)
        results.append({"file": path, "mapping": saved.cfg.mapping, **s, "ekm": saved.cfg.to_dict(),
                        "trained": {k: saved.meta.get(k) for k in ("seed", "steps", "package_version", "jax_version")}})
    if plot:
        from evaluation.plots import save_figure_6_1_6_2

        save_figure_6_1_6_2([{"label": f"{r['mapping']} ({Path(r['file']).name})", "curve": list(saved.curve),
                              "summary": r, "w": np.asarray(saved.ekm.w[0])} for r, saved in zip(results, loaded)],
                            plot)
    if paths:
        _save_paths(args.maps, loaded, args.targets, args.seed, paths)
    if args.json:
        keys = ("E_mm", "P", "T", "D", "trials", "targets", "capped")
        about = ("file", "mapping", "ekm", "trained")
        test = {"seed": args.seed, **provenance()}
        print_json({**{k: results[0][k] for k in keys + about}, **test} if len(results) == 1
                   else {"maps": [{k: r[k] for k in about[:2] + keys + about[2:]} for r in results], **test})
        return
    for r in results:
        print_summary(r, f"{r['file']} ({r['mapping']})")
    for out in (plot, paths):
        if out:
            print(f"plot written to {out}")


def _save_paths(files, loaded, targets: int, seed: int, out) -> None:
    """``ekm evaluate --paths``: the first trial's paths in the same test, one panel per map."""
    from pathlib import Path

    from evaluation.metrics import summarize
    from evaluation.plots import save_paths_figure
    from evaluation.protocol import trace_paths

    panels = []
    for path, saved in zip(files, loaded):
        pts, start, xy, rec = trace_paths(saved.ekm, saved.cfg, saved.arena, targets=targets, seed=seed)
        panels.append({"label": f"{saved.cfg.mapping} ({Path(path).name}, trial 1)", "targets": pts, "start": start,
                       "xy": xy, "summary": summarize(rec)})
    save_paths_figure(panels, loaded[0].arena, out)
