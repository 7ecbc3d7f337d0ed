"""Slippery-cell planning in the workspace (thesis ch. 3): bitmap, labelling, graph, search, checkpoints.

Quick start::

    from robots.worldnames import load_world
    from planner import plan, replan

    world = load_world("three-rooms-changed")
    p = plan(world)                       # slippery cells, 2 cm bitmap, map known at t = 0
    p.checkpoints                         # (k, 2): one per boundary crossed, then the goal
    p2 = replan(p, world, position=(0.6, 0.3), t=6.0)   # after the known event closed a doorway

Modules, in pipeline order: :mod:`planner.bitmap` (padded workspace → 0/−1 bitmap, the grid baseline),
:mod:`planner.slippery` (labelling, Fig. 3.4/3.5), :mod:`planner.quadtree` (baseline),
:mod:`planner.graph` (connectivity graph and shared boundaries), :mod:`planner.checkpoints` (greedy rule,
ch. 3.2.3), :mod:`planner.search` (A* over (cell, checkpoint) states), :mod:`planner.lanes` (declared movers'
lanes a route may keep off, an extension), :mod:`planner.plan` (the pipeline), :mod:`planner.examples` (Fig. 3.3
as data, printer, random workspaces), :mod:`planner.plot`.
Besides NumPy the planner uses the robot's shapes and radius (:mod:`robots.geometry`, :mod:`robots.params`) and
the package's one-line errors (:mod:`ekm.errors`); :mod:`planner.plot` draws with Matplotlib (:mod:`robots.plot`).
"""

from planner.plan import (DEFAULT_CELL, METHODS, MIN_CELL, RULES, NoRouteError, Plan, decompose, map_changed, plan,
                          plan_bitmap, replan)

__all__ = ["DEFAULT_CELL", "METHODS", "MIN_CELL", "NoRouteError", "Plan", "RULES", "decompose", "map_changed", "plan",
           "plan_bitmap", "replan"]
