"""Planning in Python: :func:`plan` (thesis ch. 3, ``ekm plan``) and its :class:`Plan`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ekm.api.checks import choice, number
from ekm.api.result import Result, new_axes

_PROG = "ekm plan"
METHODS = ("slippery", "quadtree", "grid")
RULES = ("visible", "thesis")  # planner.RULES, without importing the planner


@dataclass(frozen=True)
class Plan(Result):
    """A planned route: ``plan`` the :class:`planner.plan.Plan` (cells, graph, route, ``checkpoints``
    ``(k, 2)`` in metres with the goal last), ``world`` it was planned in, ``at`` the time (s) of the known
    map used, ``seconds`` the planning time. ``to_dict()`` is ``ekm plan --json``; ``plot()`` draws
    cells, graph, route and checkpoints."""

    plan: object
    world: object
    at: float
    seconds: float

    @property
    def checkpoints(self):
        """``(k, 2)`` checkpoints in metres, the goal last."""
        return self.plan.checkpoints

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        p = self.plan
        return {"method": p.method, "cells": p.cells, "graph_edges": len(p.graph.edges), "path_cells": list(p.route),
                "checkpoints": p.checkpoints.round(6).tolist(), "seconds": round(self.seconds, 6),
                "rule": p.rule, "length_m": round(p.length, 4),
                "world": self.world.name, "cell": p.cell, "at": self.at, **provenance(jax=False)}

    @property
    def title(self) -> str:
        p = self.plan
        return f"{self.world.name} at t = {self.at:g} s: {p.method}, {p.cells} cells, {len(p.graph.edges)} arcs"

    def plot(self, ax=None):
        """Cells, graph, route and checkpoints on ``ax`` (a new figure's if None); returns the axes."""
        from planner.plot import draw_plan

        ny, nx = self.plan.labels.shape
        ax = new_axes(ax, (9.0, max(3.0, 9.0 * ny / nx + 0.8)))
        draw_plan(ax, self.plan, self.world, self.at)
        ax.set_title(self.title, fontsize=10)
        return ax

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path`` (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from planner.plot import save_plan

        out = plot_path(path, "--plot")
        save_plan(out, self.plan, self.world, self.at, title=self.title)
        return out


def plan(world, start=None, goal=None, *, cell: float | None = None, method: str = "slippery",
         at: float = 0.0, checkpoints: str = "visible") -> Plan:
    """Plan checkpoints from ``start`` to ``goal`` through ``world`` with slippery cells (thesis ch. 3) or
    a baseline decomposition.

    Parameters
    ----------
    world : str or World
        A named world or world file (:func:`ekm.world`), or a loaded world.
    start, goal : (x, y) in metres, optional
        Default: the world's start and goal.
    cell : float, optional
        Bitmap cell size in metres (default 0.02); halved automatically while no route fits (a doorway
        narrower than two cells can lose every free cell). ``Plan.plan.cell`` is the cell used.
    method : {"slippery", "quadtree", "grid"}, default "slippery"
        The cell decomposition.
    at : float, default 0
        Plan on the map known at this time (s): after the known events until then.
    checkpoints : {"visible", "thesis"}, default "visible"
        ``visible``: consecutive checkpoints see each other with the robot's clearance (a labelled
        extension, :mod:`planner.visibility`); ``thesis``: the greedy rule of ch. 3.2.3 as written.

    Returns
    -------
    Plan
        Its ``to_dict()`` is ``ekm plan --json`` for the same arguments (``seconds``, the planning time,
        differs from run to run).

    Examples
    --------
    ::

        p = ekm.plan("three-rooms-changed", at=7)
        p.checkpoints          # (k, 2) metres, goal last
    """
    import time

    from ekm.api.worlds import world as load
    from planner import DEFAULT_CELL
    from planner import plan as make_plan

    choice(method, METHODS, "--method", _PROG)
    choice(checkpoints, RULES, "--checkpoints", _PROG)
    at = number(at, "--at", _PROG, strict=False)
    cell = DEFAULT_CELL if cell is None else number(cell, "--cell", _PROG, strict=True)
    w = load(world)
    t0 = time.perf_counter()
    p = make_plan(w, start, goal, cell=cell, method=method, t=at, checkpoints=checkpoints)
    return Plan(plan=p, world=w, at=at, seconds=time.perf_counter() - t0)
