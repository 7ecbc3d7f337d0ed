"""Drawing a plan like thesis Fig. 3.3b and 3.6: cells in their own colours, the graph, route and checkpoints.

:func:`draw_plan` draws on a given Matplotlib ``Axes``; :func:`save_plan` makes the figure and writes the
PNG atomically (temporary file + rename), so a reader never sees a half-written image. Uses
``matplotlib.figure.Figure`` directly: no pyplot state, no backend switching.
"""

from __future__ import annotations

import numpy as np

from planner.checkpoints import path_length
from planner.plan import Plan
from robots.plot import save_figure

_OCCUPIED_RGB = (0.86, 0.86, 0.86)


def cell_colours(n: int) -> np.ndarray:
    """RGB ``(n + 1, 3)``: a colour per cell label ``1 … n`` (row 0 unused), consecutive labels far apart.

    The 18 non-grey colours of ``tab20`` (grey is kept for occupied cells), stepped by 7 so that cells
    numbered one after the other — often neighbours — get unlike colours.
    """
    from matplotlib import colormaps

    palette = np.delete(np.asarray(colormaps["tab20"].colors)[:, :3], [14, 15], axis=0)
    return np.vstack([np.zeros((1, 3)), palette[(np.arange(n) * 7) % len(palette)]])


def cell_sites(labels: np.ndarray, cell: float) -> np.ndarray:
    """A point inside each cell to draw its graph node at, ``(n + 1, 2)`` (row 0 unused).

    The centre of the cell's bitmap square nearest to its centroid (a slippery cell need not hold its
    centroid).
    """
    n = int(labels.max(initial=0))
    iy, ix = np.nonzero(labels > 0)
    lab = labels[iy, ix]
    centres = (np.stack([ix, iy], axis=-1) + 0.5) * cell
    count = np.bincount(lab, minlength=n + 1)
    centroid = np.stack([np.bincount(lab, centres[:, k], minlength=n + 1) for k in range(2)], -1)
    centroid /= np.maximum(count, 1)[:, None]
    d = np.linalg.norm(centres - centroid[lab], axis=1)
    order = np.lexsort((d, lab))
    first = order[np.r_[True, lab[order][1:] != lab[order][:-1]]]
    sites = np.zeros((n + 1, 2))
    sites[lab[first]] = centres[first]
    return sites


def route_through_cells(plan: Plan) -> np.ndarray | None:
    """The shortest path ``(n, 2)`` from start to goal over the free bitmap cells of the plan's route — what the
    robot is led along, crossing from cell to cell through their shared edges, never through a wall (the
    thesis's checkpoints are joined by straight legs that may cross one: :class:`planner.plan.Plan`)."""
    from planner.visibility import route_path

    found = route_path(plan.bitmap, plan.labels, plan.route, plan.cell, plan.start, plan.goal, ())
    return None if found is None else found[0]


def draw_plan(ax, plan: Plan, world=None, t: float = 0.0) -> None:
    """Draw ``plan`` (and, if given, the walls and known obstacles of ``world`` at ``t``) on ``ax``."""
    from matplotlib.collections import LineCollection

    labels, c = plan.labels, plan.cell
    ny, nx = labels.shape
    rgb = cell_colours(plan.cells)[np.maximum(labels, 0)]
    rgb[labels < 0] = _OCCUPIED_RGB
    ax.imshow(rgb, origin="lower", extent=(0, nx * c, 0, ny * c), interpolation="nearest")

    if world is not None:
        from robots.plot import STYLE, draw_shape

        for s in world.border + world.walls:
            draw_shape(ax, s, STYLE["wall"], thickness=world.wall_thickness)
        for s in world.known_shapes(t)[len(world.walls):]:
            draw_shape(ax, s, STYLE["obstacle"])

    sites = cell_sites(labels, c)
    if len(plan.graph.edges):
        ax.add_collection(LineCollection(sites[plan.graph.edges], colors="0.3", linewidths=0.6, zorder=2))
    ax.plot(*sites[1:].T, ".", color="0.15", ms=3 if plan.cells < 200 else 1, zorder=3)

    path = np.vstack([np.asarray(plan.start)[None], plan.checkpoints])
    legs = "straight legs, through the free space" if plan.rule == "visible" else "straight legs, may cross walls"
    ax.plot(*path.T, "-", color="crimson", lw=2, zorder=4, label=f"checkpoint path {plan.length:.2f} m ({legs})")
    through = route_through_cells(plan)
    if through is not None and plan.rule != "visible":
        ax.plot(*through.T, "--", color="0.1", lw=1.0, zorder=4,
                label=f"route through the cells {path_length(through[0], through[1:]):.2f} m (their shared edges)")
    ax.plot(*plan.checkpoints[:-1].T, "o", mfc="white", mec="crimson", mew=1.5, ms=7, zorder=5,
            label=f"checkpoints ({len(plan.checkpoints) - 1} + goal)")
    ax.text(*plan.start, "X", color="k", fontsize=12, fontweight="bold", ha="center", va="center", zorder=6)
    ax.text(*plan.goal, "Y", color="k", fontsize=12, fontweight="bold", ha="center", va="center", zorder=6)
    ax.set_xlim(0, nx * c)
    ax.set_ylim(0, ny * c)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="upper right", fontsize=7, framealpha=0.85)


def save_plan(path, plan: Plan, world=None, t: float = 0.0, title: str | None = None) -> None:
    """Draw ``plan`` into a PNG at ``path``, written atomically. Raises :class:`InputError` if it cannot be written."""
    from matplotlib.figure import Figure

    ny, nx = plan.labels.shape
    fig = Figure(figsize=(9.0, max(3.0, 9.0 * ny / nx + 0.8)), layout="constrained")
    ax = fig.add_subplot()
    draw_plan(ax, plan, world, t)
    if title:
        ax.set_title(title, fontsize=10)
    save_figure(fig, path, dpi=120)
