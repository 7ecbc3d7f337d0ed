"""Plan and replan: world → padded bitmap → cells → graph → route → checkpoints (thesis ch. 3.2, Fig. 6.5).

:func:`plan` is the planner's front door; :func:`plan_bitmap` is the same pipeline on a ready bitmap
(used by the benchmark and by tests on random workspaces); :func:`replan` plans again from where the
robot is when the map changes (a known event, Fig. 6.5). All three are pure: they return a :class:`Plan`
and keep no state.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ekm.errors import InputError
from planner.bitmap import clearance_ok, free_cell_at, grid_cells, padded_obstacles, rasterise
from planner.checkpoints import greedy_checkpoints, path_length
from planner.graph import Graph, adjacency
from planner.lanes import keeping_off, runs_along
from planner.lanes import lanes as mover_lanes
from planner.quadtree import label_quadtree
from planner.search import shortest_route
from planner.slippery import label_slippery
from planner.visibility import segment_slack, visible_checkpoints
from robots.params import KHEPERA

#: The decompositions: slippery cells (ch. 3.2.2) and the two baselines of docs/design.md §4.
METHODS = ("slippery", "quadtree", "grid")

#: Default cell size (m): with the 25 mm cushion, a 0.12 m doorway of ``three-rooms`` keeps two free cells.
DEFAULT_CELL = 0.02

#: Checkpoint rules: ``visible`` (consecutive checkpoints see each other with the robot's clearance,
#: :mod:`planner.visibility`, the default) and ``thesis`` (the greedy rule of ch. 3.2.3 as written).
RULES = ("visible", "thesis")


class NoRouteError(InputError):
    """No sequence of adjacent cells joins the start to the goal on this map, or the start or goal has no free
    bitmap cell near it (a bad start/goal pair, or a cell too coarse for the map's narrow places)."""


@dataclass(frozen=True)
class Plan:
    """A planned route (thesis ch. 3.2.3).

    Attributes
    ----------
    method : ``"slippery"``, ``"quadtree"`` or ``"grid"``.
    cell : bitmap cell size (m).
    bitmap : ``(ny, nx)`` int32, 0 free / −1 occupied (Fig. 3.3a); ``bitmap[iy, ix]`` covers
        ``[ix·cell, (ix+1)·cell] × [iy·cell, (iy+1)·cell]``.
    labels : ``(ny, nx)`` int32, −1 occupied, ``1 … n`` the cell each free bitmap cell belongs to (Fig. 3.3b).
    graph : the connectivity graph of the cells (:class:`planner.graph.Graph`).
    route : the cells from the start's to the goal's, in order (the ``path_cells`` of ``ekm plan --json``).
    start, goal : (x, y) in metres.
    checkpoints : ``(k, 2)``, the goal last. ``rule="thesis"``: one per boundary crossed, checkpoint
        ``i`` on the boundary of ``route[i]`` and ``route[i+1]`` (Fig. 3.6); ``rule="visible"``: the
        corners of a path through the same cells whose legs keep the robot's clearance
        (:mod:`planner.visibility`).
    rule : the checkpoint rule, ``"visible"`` or ``"thesis"`` (:data:`RULES`).
    avoided : the declared movers' lanes the route keeps off (:mod:`planner.lanes`; empty unless :func:`plan`'s
        ``lanes`` found it cheap to): part of the map the route was planned on, with the robot's radius as cushion.

    The thesis's checkpoints are waypoints for the reactive layer, not a collision-free polyline: a
    slippery cell need not be convex, so the straight leg between two checkpoints of one cell may cut a
    corner of the cushion — or, in a staircase of a cell, run through several walls. Two consecutive
    thesis checkpoints can coincide where the route hops through a corner (see :mod:`planner.search`);
    the reactive layer reaches such a checkpoint at once.
    """

    method: str
    cell: float
    bitmap: np.ndarray
    labels: np.ndarray
    graph: Graph
    route: tuple[int, ...]
    start: tuple[float, float]
    goal: tuple[float, float]
    checkpoints: np.ndarray
    rule: str = "thesis"
    avoided: tuple = ()

    @property
    def cells(self) -> int:
        """Number of cells of the decomposition (graph nodes)."""
        return self.graph.n

    @property
    def length(self) -> float:
        """Length (m) of the checkpoint path start → checkpoints → goal."""
        return path_length(self.start, self.checkpoints)


def decompose(W: np.ndarray, method: str, seed: tuple[int, int] | None = None) -> np.ndarray:
    """Cell labels ``(ny, nx)`` of the bitmap ``W`` by ``method``; slippery labelling starts at ``seed`` (iy, ix)."""
    if method == "slippery":
        return label_slippery(W, seed)
    if method == "quadtree":
        return label_quadtree(W)
    if method == "grid":
        return grid_cells(W)
    raise InputError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")


def plan_bitmap(W: np.ndarray, cell: float, start, goal, method: str = "slippery") -> Plan:
    """Plan on a ready bitmap ``W`` (0 free / −1 occupied) of ``cell``-metre squares.

    ``start`` and ``goal`` (x, y) must each lie in, or within one cell of, a free bitmap cell (see
    :func:`planner.bitmap.free_cell_at`). Raises :class:`InputError` if not, and :class:`NoRouteError`
    if no route joins them.
    """
    W = np.asarray(W)
    start, goal = _point(start, "start"), _point(goal, "goal")
    where = {}
    for name, p in (("start", start), ("goal", goal)):
        where[name] = free_cell_at(W, p, cell)
        if where[name] is None:
            raise NoRouteError(f"{name} {_fmt(p)}: no free bitmap cell within {cell} m (cell size {cell} m is too "
                               "coarse here, or the point is walled in)")
    labels = decompose(W, method, seed=where["start"])
    graph = adjacency(labels, cell)
    start_cell, goal_cell = (int(labels[where[k]]) for k in ("start", "goal"))
    route = shortest_route(graph, start_cell, start, goal_cell, goal)
    if route is None:
        raise NoRouteError(f"no route from start {_fmt(start)} to goal {_fmt(goal)}: they lie in parts of the "
                           "free space that do not connect at this cell size")
    checkpoints = greedy_checkpoints(graph, route.cells, start, goal)
    return Plan(method=method, cell=float(cell), bitmap=W, labels=labels, graph=graph, route=route.cells,
                start=start, goal=goal, checkpoints=checkpoints)


#: The finest cell (m) that automatic refinement tries: a 2.5 m arena is then a 500 x 500 bitmap.
MIN_CELL = 0.005


def plan(world, start=None, goal=None, *, cell: float = DEFAULT_CELL, method: str = "slippery",
         t: float = 0.0, padding: float = KHEPERA.radius, checkpoints: str = "visible", refine: bool = True,
         lanes: tuple[float, float] | None = None) -> Plan:
    """Plan checkpoints from ``start`` to ``goal`` through ``world`` on the map known at time ``t`` (s).

    ``start``/``goal`` default to the world's (the goal where it is at ``t``); ``padding`` (m) defaults to
    the robot radius (ch. 3.2.2: "the cushion width approximates the robot radius"); ``checkpoints`` is
    the rule (:data:`RULES`). With ``refine``, a bitmap too coarse to hold a route — a doorway narrower
    than two cells can lose every free cell — is refined: the cell is halved until a route exists or
    :data:`MIN_CELL` is passed, and the plan says which cell it used (``Plan.cell``). Raises
    :class:`InputError` when start or goal lie outside the padded free space or the cell size is bad, and
    :class:`NoRouteError` when no route exists at any cell tried.

    ``lanes`` = ``(margin, detour)`` keeps the route off the declared movers' lanes where that leaves the robot
    ``margin`` (m) beside each and makes the route at most ``detour`` times as long (:func:`kept_off_lanes`); None
    plans on the a-priori map alone.
    """
    start = _point(world.start[:2] if start is None else start, "start")
    goal = _point(world.goal_at(t) if goal is None else goal, "goal")

    def make(on):
        key = (on, start, goal, cell, method, t, padding, checkpoints, refine)
        try:
            hash(key)
        except TypeError:  # an unhashable argument: plan without remembering (the pipeline reports what is wrong)
            return _refined(*key, check=("start", "goal"))
        return _remembered_plan(*key)

    return kept_off_lanes(make, world, lanes, padding)


def kept_off_lanes(make, world, lanes: tuple[float, float] | None, padding: float) -> Plan:
    """``make(world)`` — or, with ``lanes`` = ``(margin, detour)``, ``make`` on ``world`` with its movers' lanes as
    obstacles (:mod:`planner.lanes`) where that plan exists, is at most ``detour`` times as long, and every leg of it
    leaves the robot (radius ``padding``, m) at least ``margin`` (m) beside every lane kept off; its ``avoided`` the
    lanes kept off. First all the lanes as they are; where no such plan keeps off them all, each lane the plain route
    runs along (:func:`planner.lanes.runs_along`), grown by ``margin``, on its own merits, in the world's order: kept
    off if the route still meets the conditions with it and those kept before. Why: a route beside a shuttling
    mover's lane spares the reactive layer a head-on meeting in a corridor; one round the building, or one that
    grazes the mover, is not worth it — and a mover crossing the only doorway must not stop the route keeping beside
    another that shuttles along a corridor further on (issue 35, ``movers:7``; the lane grown, since a route planned
    beside the lane as it is cut its corner closer than the margin). Growing every lane cost routes squeezed between a
    wall and a lane, and keeping off lanes the route only crosses cost detours through other movers' ways (both
    measured in ``docs/reproduce/every-kind.md``)."""
    plain = make(world)
    if lanes is None:
        return plain
    margin, detour = lanes
    shapes = mover_lanes(world)
    if not shapes:
        return plain

    def keep_off(some, on):  # the plan off the lanes ``on`` numbered ``some``, or None where it breaks a condition
        try:
            kept = make(keeping_off(world, tuple(on[i] for i in some)))
        except InputError:  # NoRouteError included; or the start or goal lies in a lane
            return None
        beside = [(shapes[i], padding) for i in some]
        ends = np.vstack([kept.start, kept.checkpoints])
        spare = min(segment_slack(a, b, beside) for a, b in zip(ends[:-1], ends[1:]))
        ok = kept.length <= detour * plain.length and spare >= margin
        return replace(kept, avoided=tuple(on[i] for i in some)) if ok else None

    best = keep_off(range(len(shapes)), shapes)
    if best is None:
        grown = mover_lanes(world, margin)
        some, along = (), runs_along(world, np.vstack([plain.start, plain.checkpoints]))
        for i in (i for i in range(len(shapes)) if along[i]):
            tried = keep_off(some + (i,), grown)
            if tried is not None:
                some, best = some + (i,), tried
    return plain if best is None else best


@functools.lru_cache(maxsize=64)
def _remembered_plan(world, start, goal, cell, method, t, padding, checkpoints, refine) -> Plan:
    """:func:`plan`, remembered: a plan is a pure function of its arguments, and ``ekm compare`` plans the same
    world from the same start for every architecture and seed. The plan's arrays are read-only, as it is
    shared."""
    plan_ = _refined(world, start, goal, cell, method, t, padding, checkpoints, refine, check=("start", "goal"))
    for a in (*(getattr(plan_, f.name) for f in fields(plan_)), plan_.graph.edges):
        if isinstance(a, np.ndarray):
            a.flags.writeable = False
    return plan_


def replan(previous: Plan, world, position, t: float, padding: float = KHEPERA.radius, reach: float = 0.0,
           refine: bool = True, lanes: tuple[float, float] | None = None) -> Plan:
    """Plan again from the robot's ``position`` (x, y) on the map known at ``t`` (s) (Fig. 6.5).

    Keeps the method, cell size, checkpoint rule and goal of ``previous``; the slippery labelling restarts
    from the robot's current cell, as it did from its initial cell (Fig. 3.3b). The robot is where it is:
    its position is not required to clear the cushion (contact or sensor noise can leave it a little
    inside), only to lie within one cell of a free bitmap cell — or, with ``reach`` > 0 (m), the route
    starts at the nearest point within ``reach`` that does (a robot pressed against an obstacle just added
    to the map stands inside its cushion). ``refine`` and ``lanes`` as in :func:`plan`.
    """
    return kept_off_lanes(lambda on: _refined(on, position, previous.goal, previous.cell, previous.method, t, padding,
                                              previous.rule, refine, check=("goal",), reach=reach), world, lanes,
                          padding)


def _refined(world, start, goal, cell, method, t, padding, checkpoints, refine, check, reach: float = 0.0) -> Plan:
    """:func:`_plan` at ``cell``, and with ``refine`` at half the cell, a quarter … down to :data:`MIN_CELL`
    while no route exists; the error of the finest cell tried if none does."""
    while True:
        try:
            return _plan(world, start, goal, cell, method, t, padding, check, checkpoints, reach)
        except NoRouteError as exc:
            finer = cell / 2
            if not refine or finer < MIN_CELL - 1e-12:
                raise NoRouteError(f"{world.name}: {exc}" + (f" (tried cells down to {cell:g} m)" if refine else "")) \
                    from None
            cell = finer


def _nearest_startable(W, point, cell: float, reach: float):
    """The point nearest ``point``, on rings of one cell up to ``reach``, that lies within one cell of a free
    bitmap cell; ``point`` itself if it does, None if none does."""
    x, y = point
    for r in np.arange(0.0, reach + 1e-9, cell):
        angles = [0.0] if r == 0 else np.linspace(0.0, 2 * math.pi, max(8, int(2 * math.pi * r / cell * 2)),
                                                  endpoint=False)
        for a in angles:
            q = (x + r * math.cos(a), y + r * math.sin(a))
            if free_cell_at(W, q, cell) is not None:
                return q
    return None


def _plan(world, start, goal, cell, method, t, padding, check, checkpoints: str = "thesis",
          reach: float = 0.0) -> Plan:
    """:func:`plan` at one cell size with the free-space test applied to the points named in ``check``, and
    the start moved to the nearest startable point within ``reach`` (see :func:`replan`)."""
    if method not in METHODS:
        raise InputError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")
    if checkpoints not in RULES:
        raise InputError(f"checkpoints: must be one of {', '.join(RULES)}, got {checkpoints!r}")
    points = {"start": _point(start, "start"), "goal": _point(goal, "goal")}
    obstacles = padded_obstacles(world, t, padding)
    for name in check:
        if not clearance_ok(points[name], obstacles, world.size):
            raise InputError(f"{name} {_fmt(points[name])}: not in the free space of {world.name} (outside the "
                             f"arena or closer than {padding} m to a wall or known obstacle)")
    W = rasterise(obstacles, world.size, cell)
    if reach > 0:
        points["start"] = _nearest_startable(W, points["start"], cell, reach) or points["start"]
    result = plan_bitmap(W, cell, points["start"], points["goal"], method)
    if checkpoints == "visible":
        seen = visible_checkpoints(W, result.labels, result.route, cell, result.start, result.goal, obstacles)
        if seen is not None:
            result = replace(result, checkpoints=seen, rule="visible")
    return result


def map_changed(world, since: float, now: float) -> bool:
    """Whether the planner's map changed in ``(since, now]``: a known event happened (time to :func:`replan`)."""
    return any(e.known and since < e.at_s <= now for e in world.events)


def _point(p, name: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in p[:2])
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a point (x, y) in metres, got {p!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise InputError(f"{name}: must be finite, got {_fmt((x, y))}")
    return x, y


def _fmt(p) -> str:
    return f"({p[0]:.3g}, {p[1]:.3g})"
