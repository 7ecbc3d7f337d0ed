"""Graph search for the route with the shortest checkpoint path (thesis ch. 3.2.3; left as future work in 7.1.2).

The thesis asks for "a sequence of adjacent cells … such that the start and goal positions are enclosed
within the first and last cell" and then places checkpoints greedily (:mod:`planner.checkpoints`). A
route is only as good as its checkpoint path, so the search minimises that path's length:

    cost(c_0 … c_k) = |s − p_1| + |p_1 − p_2| + … + |p_k − g|,
    p_i = closest point to p_{i−1} (p_0 = s) on the boundary between c_{i−1} and c_i.

Because p_i depends on p_{i−1}, the cost of entering a cell is not a property of the graph arc alone,
and a plain shortest path over cells optimises something else (a Dijkstra over cells that keeps the
checkpoint of the first arrival can return a longer checkpoint path, and on random workspaces sometimes
does). The search therefore runs over **states (cell, checkpoint at which it was entered)**:

* the start state is ``(c_0, s)``; from ``(c, p)`` the arc to a neighbour ``n`` leads to ``(n, q)`` with
  ``q`` the closest point to ``p`` on the boundary of ``c`` and ``n``, at cost ``|p − q|``;
* from any state ``(c_k, p)`` with ``c_k`` the goal's cell, a final arc of cost ``|p − g|`` ends the route.

The transitions are deterministic and the future cost depends only on the state, so a shortest path in
this state graph is exactly the route of least checkpoint-path length over all sequences of adjacent
cells. Such a sequence may revisit a cell when that shortens the greedy path: the rule is myopic, and
stepping into a neighbour and straight back (a zero-length leg) re-enters the cell at a corner from
which the next boundary is closer (some quadtree and slippery-cell plans on random workspaces do so).
The state graph is finite: a closest point on an axis-aligned run keeps a coordinate of the point it
was measured from or takes a grid coordinate, so every coordinate is a grid line or a coordinate of
the start. Costs are non-negative and ``|p − g|`` is a consistent heuristic (triangle inequality), so
A* has the optimum when it first pops the final state.
"""

from __future__ import annotations

import heapq
import math
from typing import NamedTuple

from planner.checkpoints import closest_point
from planner.graph import Graph


class Route(NamedTuple):
    """A route through the graph: ``cells`` in order (start cell first) and its checkpoint-path length (m)."""

    cells: tuple[int, ...]
    length: float


def shortest_route(graph: Graph, start_cell: int, start, goal_cell: int, goal) -> Route | None:
    """The route from ``start_cell`` (holding ``start`` (x, y)) to ``goal_cell`` (holding ``goal``) with the
    shortest greedy checkpoint path, by A* over (cell, entry checkpoint) states; ``None`` if there is none.
    """
    gx, gy = float(goal[0]), float(goal[1])
    first = (start_cell, float(start[0]), float(start[1]))
    cost = {first: 0.0}
    parent: dict = {first: None}
    done = None  # the final state: (cost, state it was reached from)
    heap = [(math.hypot(first[1] - gx, first[2] - gy), 0.0, 0, first)]
    tie = 1  # heap tie-breaker: states are never compared
    while heap:
        f, g, _, state = heapq.heappop(heap)
        if state is None:
            break  # the final state: every state with a lower f has been expanded
        if g > cost[state]:
            continue  # stale entry
        cell, x, y = state
        if cell == goal_cell:
            total = g + math.hypot(gx - x, gy - y)
            if done is None or total < done[0]:
                done = (total, state)
                heapq.heappush(heap, (total, total, tie, None))
                tie += 1
        for n in graph.neighbours.get(cell, ()):
            qx, qy = closest_point(x, y, graph.boundary[(cell, n)])
            nxt = (n, qx, qy)
            ng = g + math.hypot(qx - x, qy - y)
            if ng < cost.get(nxt, math.inf):
                cost[nxt] = ng
                parent[nxt] = state
                heapq.heappush(heap, (ng + math.hypot(gx - qx, gy - qy), ng, tie, nxt))
                tie += 1
    if done is None:
        return None
    cells = []
    state = done[1]
    while state is not None:
        cells.append(state[0])
        state = parent[state]
    return Route(cells=tuple(reversed(cells)), length=done[0])
