"""Checks shared by the planner tests (not a test module)."""

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planner.bitmap import FREE, OCCUPIED


def on_shared_edge(point, labels, a, b, cell, tol=1e-9):
    """Whether ``point`` lies on an edge shared by a bitmap cell labelled ``a`` and one labelled ``b``.

    Computed from ``labels`` directly, independently of :mod:`planner.graph`.
    """
    px, py = point
    for grid, (u, v) in ((labels, (px, py)), (labels.T, (py, px))):  # vertical edges, then horizontal ones
        left, right = grid[:, :-1], grid[:, 1:]
        r, c = np.nonzero(((left == a) & (right == b)) | ((left == b) & (right == a)))
        if np.any((np.abs((c + 1) * cell - u) <= tol) & (r * cell - tol <= v) & (v <= (r + 1) * cell + tol)):
            return True
    return False


def assert_checkpoints_on_shared_boundaries(p):
    """Checkpoint i lies on the boundary of route cells i and i+1 (ch. 3.2.3); the last is the goal."""
    for i, (a, b) in enumerate(zip(p.route[:-1], p.route[1:])):
        assert on_shared_edge(p.checkpoints[i], p.labels, a, b, p.cell), f"checkpoint {i} not between {a} and {b}"
    assert tuple(p.checkpoints[-1]) == p.goal


def flood(W, seed):
    """The free bitmap cells 4-connected to ``seed``."""
    seen, todo = {seed}, [seed]
    while todo:
        y, x = todo.pop()
        for n in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
            if 0 <= n[0] < W.shape[0] and 0 <= n[1] < W.shape[1] and W[n] == FREE and n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def check_decomposition(W, labels):
    free = W == FREE
    assert ((labels > 0) == free).all(), "labels must cover exactly the free cells"
    assert (labels[~free] == OCCUPIED).all()
    n = labels.max(initial=0)
    assert set(np.unique(labels[free]).tolist()) == set(range(1, n + 1)), "labels are 1 … n without gaps"


#: Random small workspaces: two free bitmap cells to one occupied.
workspaces = st.tuples(st.integers(1, 14), st.integers(1, 14)).flatmap(
    lambda shape: arrays(np.int32, shape, elements=st.sampled_from([FREE, FREE, OCCUPIED])))
