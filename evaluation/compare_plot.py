"""The picture of ``ekm compare --plot``: success rates with their 95 % intervals, and one path per cell
(:func:`comparison_figure`; with generated worlds, by family, :func:`family_figure`).

Top: for each world a group of bars, one per architecture, the bar the success rate and the whisker its
Wilson interval. Below: a grid — architectures down, worlds across — each cell the world to scale with
the path of the comparison's first trial, ending in a green dot (reached), an orange square (trapped), a red
ring (arrived after a collision: not reached) or a red cross (anything else), with a red cross where each
collision began. Built on :class:`matplotlib.figure.Figure`, written atomically.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from robots.plot import STYLE, draw_shape

_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:pink", "tab:gray")


def comparison_figure(rows, records, worlds, labels) -> Figure:
    """The figure for summary ``rows`` (in :func:`evaluation.compare.summarize`'s order) and run ``records``."""
    from robots.worldnames import load_world

    n_w = len(worlds)
    fig, grid, bars = _layout(n_w, len(labels), width=2.4)
    _success_bars(bars, labels, n_w, lambda j, i: rows[j * n_w + i])  # summarize's order: architectures, then worlds
    bars.set_xticks(range(n_w), [load_world(w).name for w in worlds], rotation=15, fontsize=8)
    bars.set_title("reached the goal without a collision (95 % Wilson intervals)")
    _path_grid(fig, grid, worlds, labels, records, [load_world(w).name for w in worlds])
    return fig


def family_figure(families, records, labels) -> Figure:
    """The figure of a comparison over generated worlds (``ekm compare --suite``): for each family a group of
    bars, one per architecture, the success rate over its worlds with the 95 % Wilson interval; below, one
    world of each family (the first, by seed) with each architecture's path. ``families``: the rows of
    :func:`evaluation.compare.by_family`."""
    names = [f for f in dict.fromkeys(r["family"] for r in families) if f != "all"]
    fig, grid, bars = _layout(len(names), len(labels), width=2.2)
    row = {(r["family"], r["architecture"]): r for r in families}
    _success_bars(bars, labels, len(names), lambda j, i: row[(names[i], labels[j])])
    bars.set_xticks(range(len(names)), [f"{f}\n({row[(f, labels[0])]['worlds']} worlds)" for f in names], fontsize=8)
    bars.set_title("generated worlds: reached the goal without a collision (95 % Wilson intervals)")
    first = [min((r["given"] for r in records if r.get("family") == f), key=lambda g: int(g.split(":")[1]))
             for f in names]
    _path_grid(fig, grid, first, labels, records, first)
    return fig


def _layout(n_groups: int, n_labels: int, width: float):
    """A figure with a bar chart across the top and a grid of ``n_labels`` rows × ``n_groups`` maps below."""
    fig = Figure(figsize=(max(8.0, width * n_groups), 3.3 + 1.9 * n_labels), layout="constrained")
    grid = fig.add_gridspec(1 + n_labels, n_groups, height_ratios=[1.65] + [1.0] * n_labels)
    return fig, grid, fig.add_subplot(grid[0, :])


def _success_bars(bars, labels, n_groups: int, row) -> None:
    """For each group i a bar per architecture j: ``row(j, i)``'s success rate with its Wilson interval."""
    width = 0.8 / max(1, len(labels))
    for j, label in enumerate(labels):
        rows = [row(j, i) for i in range(n_groups)]
        ys = [r["success_rate"] or 0.0 for r in rows]
        ci = [r["success_ci95"] or (0.0, 0.0) for r in rows]  # None: every run failed, no bar
        err = [[y - c[0] for y, c in zip(ys, ci)], [c[1] - y for y, c in zip(ys, ci)]]
        xs = [i - 0.4 + width * (j + 0.5) for i in range(n_groups)]
        bars.bar(xs, ys, width * 0.9, color=_COLOURS[j % len(_COLOURS)], label=label, yerr=err, capsize=2,
                 error_kw={"linewidth": 0.8})
        for x, r in zip(xs, rows):
            if r["success_rate"] is None:
                bars.text(x, 0.02, "failed", rotation=90, ha="center", va="bottom", fontsize=7, color="#b2182b")
    bars.set(ylim=(0, 1.05), ylabel="success rate")
    bars.legend(fontsize=7, ncols=min(len(labels), 4), loc="upper center", bbox_to_anchor=(0.5, -0.28), frameon=False)
    bars.grid(axis="y", alpha=0.3)


def _path_grid(fig, grid, givens, labels, records, titles) -> None:
    """Each world ``givens[i]`` (as the jobs spelt it) across, each architecture down, with the path its first
    trial left in ``records``."""
    from robots.worldnames import load_world

    for i, (given, title) in enumerate(zip(givens, titles)):
        world = load_world(given)
        for j, label in enumerate(labels):
            ax = fig.add_subplot(grid[1 + j, i])
            _draw_cell(ax, world, next((r for r in records if r["label"] == label and r["given"] == given
                                        and "path" in r), None))
            if i == 0:
                ax.set_ylabel(label, fontsize=7)
            if j == 0:
                ax.set_title(title, fontsize=8)


def _draw_cell(ax, world, record) -> None:
    w, h = world.size
    for wall in world.border + world.walls:
        draw_shape(ax, wall, STYLE["wall"], thickness=world.wall_thickness)
    for shape in world.obstacles:
        draw_shape(ax, shape, STYLE["obstacle"])
    for shape in world.unforeseen:
        draw_shape(ax, shape, STYLE["unforeseen"])
    for event in world.events:
        for shape in event.add:
            draw_shape(ax, shape, STYLE["event"])
    for mover in world.moving:
        draw_shape(ax, mover.at(0.0), STYLE["moving"])
    gx, gy = world.goal_at(0.0)
    ax.plot([gx], [gy], "*", color="tab:green", ms=7)
    if record is not None and "path" in record:
        path = np.asarray(record["path"])
        ax.plot(path[:, 0], path[:, 1], "-", color="tab:blue", lw=0.9)
        for x, y in record.get("collided_at") or []:  # where it collided, not where it ended
            ax.plot([x], [y], "x", color="red", ms=5, mew=1.5)
        marker = end_marker(record)
        ax.plot(path[-1, 0], path[-1, 1], marker[0], color=marker[1], ms=5, mew=1.5, fillstyle="none")
    ax.set(xlim=(-0.02, w + 0.02), ylim=(-0.02, h + 0.02), aspect="equal", xticks=[], yticks=[])


def end_marker(record: dict) -> tuple[str, str]:
    """The marker and colour at the end of a run's path: reached, trapped, arrived after a collision (a ring: the
    collisions have their own crosses), or neither."""
    if record["reached"]:
        return ("o", "tab:green")
    if record["trapped"]:
        return ("s", "darkorange")
    return ("o", "red") if record.get("arrived") else ("x", "red")
