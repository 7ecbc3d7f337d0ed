"""``ekm plan``: plan checkpoints through a world with slippery cells or a baseline decomposition
(thesis ch. 3)."""

from __future__ import annotations

from ekm.api.planning import METHODS, RULES
from ekm.cli.args import command, nonneg_float, one_of, positive_float, print_json, xy_point


def add_parser(sub) -> None:
    p = command(sub, "plan", "plan checkpoints through a world (slippery cells, quadtree or grid)",
                ["ekm plan --world three-rooms --plot plan.png", "ekm plan --world my-lab.json --cell 0.01 --json"])
    p.add_argument("--world", required=True, metavar="W", help="named world or world file")
    p.add_argument("--start", type=xy_point, metavar="X,Y", help="start in metres (default: the world's)")
    p.add_argument("--goal", type=xy_point, metavar="X,Y", help="goal in metres (default: the world's)")
    p.add_argument("--cell", type=positive_float, metavar="M",
                   help="bitmap cell size in metres (default 0.02; halved automatically while no route fits)")
    p.add_argument("--checkpoints", type=one_of(RULES), default="visible", metavar="{" + ",".join(RULES) + "}",
                   help="checkpoint rule: visible (consecutive checkpoints see each other with the robot's "
                        "clearance; default) or thesis (the greedy rule of ch. 3.2.3)")
    p.add_argument("--method", type=one_of(METHODS), default="slippery", metavar="{" + ",".join(METHODS) + "}",
                   help="cell decomposition (default slippery)")
    p.add_argument("--at", type=nonneg_float, default=0.0, metavar="SECONDS",
                   help="plan on the map known at this time (after the known events so far; default 0)")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="draw cells, graph, route and checkpoints")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Plan checkpoints through a world with slippery cells or a baseline decomposition (thesis ch. 3;
    :func:`ekm.plan`)."""
    from ekm.api.checks import plot_path
    from ekm.api.planning import plan

    if args.plot:
        plot_path(args.plot)  # checked before the work
    result = plan(args.world, args.start, args.goal, cell=args.cell, method=args.method, at=args.at,
                  checkpoints=args.checkpoints)
    p, world, seconds = result.plan, result.world, result.seconds
    route = " -> ".join(map(str, p.route[:12])) + (f" -> ... ({len(p.route)} cells)" if len(p.route) > 12 else "")
    if args.plot:
        result.save_plot(args.plot)
    if args.json:
        print_json(result.to_dict())
        return
    ny, nx = p.bitmap.shape
    print(f"{world.name} at t = {args.at:g} s: {p.method} decomposition of a {nx} x {ny} bitmap "
          f"({p.cell:g} m cells, {int((p.bitmap == 0).sum())} free)")
    print(f"  {p.cells} cells, {len(p.graph.edges)} graph edges")
    print(f"  route: {route}")
    print(f"  start ({p.start[0]:.3f}, {p.start[1]:.3f})")
    k = len(p.checkpoints) - 1
    for i, (x, y) in enumerate(p.checkpoints[:-1][:10], 1):
        print(f"  checkpoint {i} ({x:.3f}, {y:.3f})")
    if k > 10:
        print(f"  ... {k - 10} more checkpoints (--json lists them all)")
    print(f"  goal ({p.goal[0]:.3f}, {p.goal[1]:.3f})")
    print(f"  checkpoint path {p.length:.3f} m ({p.rule} checkpoints: the straight legs start - checkpoints - goal), "
          f"planned in {seconds:.3f} s")
    if p.rule != "visible":
        from planner.checkpoints import path_length
        from planner.plot import route_through_cells

        through = route_through_cells(p)
        if through is not None:
            print(f"  route through the cells {path_length(through[0], through[1:]):.3f} m (the thesis's legs may cross walls; "
                  f"the reactive layer goes round)")
    if args.plot:
        print(f"  plot written to {args.plot}")
