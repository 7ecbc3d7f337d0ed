"""Cells and planning time of slippery cells vs. quadtree vs. uniform grid (thesis ch. 3.2.2, docs/design.md §4).

Run from the repository root::

    python benchmarks/perf/bench_planner.py

(options: ``--seeds 3`` random workspaces per density, ``--repeat 3`` timing repeats, best kept,
``--size 200`` side of the random bitmaps). Prints a markdown table and a last line saying whether slippery
cells were fewer than quadtree cells on every workspace (exit status 1 if not).

Workspaces: every named world at the default 2 cm cell (start and goal the world's), and random
``size × size`` bitmaps of rectangular obstacles (:func:`planner.examples.random_bitmap`, seeded) at
densities 0.1–0.4, read as a 1 m square, with start and goal the free cells of the largest connected
free region nearest the bottom-left and top-right corners. For random workspaces the numbers are means
over the seeds. Times are the best of ``--repeat`` runs of each stage: *bitmap* (rasterising the padded
world; shared by all methods), *decompose* (labelling), *graph* (adjacency and shared boundaries),
*search* (A* over (cell, checkpoint) states plus the greedy checkpoints).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from planner import DEFAULT_CELL, METHODS, decompose
from planner.bitmap import FREE, free_cell_at, padded_obstacles, rasterise
from planner.checkpoints import greedy_checkpoints, path_length
from planner.graph import adjacency
from planner.examples import random_bitmap
from planner.search import shortest_route
from robots.params import KHEPERA
from robots.worldnames import load_world, named_worlds

DENSITIES = (0.1, 0.2, 0.3, 0.4)


def best_time(fn, repeat: int):
    """``(result, seconds)``: the result of ``fn()`` and the best wall time of ``repeat`` calls."""
    best, result = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return result, best


def measure(W, cell, start, goal, method, repeat):
    """One method on one bitmap: counts and stage times (s)."""
    s_cell, g_cell = free_cell_at(W, start, cell), free_cell_at(W, goal, cell)
    labels, t_dec = best_time(lambda: decompose(W, method, s_cell), repeat)
    graph, t_graph = best_time(lambda: adjacency(labels, cell), repeat)

    def search():
        route = shortest_route(graph, int(labels[s_cell]), start, int(labels[g_cell]), goal)
        return route, greedy_checkpoints(graph, route.cells, start, goal)

    (route, checkpoints), t_search = best_time(search, repeat)
    return {"cells": graph.n, "edges": len(graph.edges), "route": len(route.cells),
            "path": path_length(start, checkpoints), "decompose": t_dec, "graph": t_graph, "search": t_search}


def largest_region_corners(W):
    """Free cells ``(iy, ix)`` of the largest 4-connected free region nearest the bottom-left and top-right."""
    ny, nx = W.shape
    region = np.zeros(W.shape, dtype=np.int32)
    sizes = [0]
    for seed in zip(*np.nonzero(W == FREE)):
        if region[seed]:
            continue
        sizes.append(0)
        todo = [seed]
        region[seed] = len(sizes) - 1
        while todo:
            y, x = todo.pop()
            sizes[-1] += 1
            for n in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if 0 <= n[0] < ny and 0 <= n[1] < nx and W[n] == FREE and not region[n]:
                    region[n] = len(sizes) - 1
                    todo.append(n)
    cells = np.argwhere(region == int(np.argmax(sizes)))
    return tuple(cells[np.argmin(cells.sum(axis=1))]), tuple(cells[np.argmax(cells.sum(axis=1))])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3, help="random workspaces per density (default 3)")
    parser.add_argument("--repeat", type=int, default=3, help="timing repeats, best kept (default 3)")
    parser.add_argument("--size", type=int, default=200, help="side of the random bitmaps in cells (default 200)")
    args = parser.parse_args(argv)

    rows = []  # (workspace, bitmap, bitmap_ms, {method: stats})
    fewer = []  # per workspace: slippery cells < quadtree cells
    for name in named_worlds():
        world = load_world(name)
        obstacles = padded_obstacles(world, 0.0, KHEPERA.radius)
        W, t_bitmap = best_time(lambda: rasterise(obstacles, world.size, DEFAULT_CELL), args.repeat)
        start, goal = world.start[:2], world.goal_at(0.0)
        stats = {m: measure(W, DEFAULT_CELL, start, goal, m, args.repeat) for m in METHODS}
        fewer.append(stats["slippery"]["cells"] < stats["quadtree"]["cells"])
        rows.append((name, f"{W.shape[1]}×{W.shape[0]}", f"{1e3 * t_bitmap:.1f}", stats))

    cell = 1.0 / args.size
    for density in DENSITIES:
        runs = []
        for seed in range(args.seeds):
            W = random_bitmap((args.size, args.size), density, np.random.default_rng(seed))
            s, g = largest_region_corners(W)
            start, goal = ((s[1] + 0.5) * cell, (s[0] + 0.5) * cell), ((g[1] + 0.5) * cell, (g[0] + 0.5) * cell)
            runs.append({m: measure(W, cell, start, goal, m, args.repeat) for m in METHODS})
            fewer.append(runs[-1]["slippery"]["cells"] < runs[-1]["quadtree"]["cells"])
        stats = {m: {k: float(np.mean([r[m][k] for r in runs])) for k in runs[0][m]} for m in METHODS}
        rows.append((f"random density {density} ({args.seeds} seeds)", f"{args.size}×{args.size}", "–", stats))

    print("| workspace | bitmap | method | cells | graph edges | route cells | path (m) | bitmap ms "
          "| decompose ms | graph ms | search ms |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, shape, t_bitmap, stats in rows:
        for m in METHODS:
            r = stats[m]
            print(f"| {name} | {shape} | {m} | {r['cells']:.0f} | {r['edges']:.0f} | {r['route']:.1f} | "
                  f"{r['path']:.3f} | {t_bitmap} | {1e3 * r['decompose']:.1f} | {1e3 * r['graph']:.1f} | "
                  f"{1e3 * r['search']:.1f} |")
    ok = all(fewer)
    print(f"\nslippery cells fewer than quadtree cells on {sum(fewer)} of {len(fewer)} workspaces: "
          f"{'yes' if ok else 'NO'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
