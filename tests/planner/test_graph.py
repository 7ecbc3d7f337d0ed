"""The graph of cells (planner.graph): the cells that touch and the boundaries they share."""

from planner.examples import fig_3_3
from planner.graph import adjacency


def test_graph_of_fig_3_3_is_a_chain_with_straight_boundaries():
    W, robot, _ = fig_3_3()
    from planner.slippery import label_slippery

    g = adjacency(label_slippery(W, robot), 1.0)
    assert g.n == 3
    assert g.edges.tolist() == [[1, 2], [2, 3]]
    assert g.boundary[(1, 2)] == ((7.0, 7.0, 13.0, 7.0),)  # below the strip cell 1 runs through the middle room
    assert g.boundary[(2, 3)] == ((14.0, 3.0, 19.0, 3.0),)
    assert g.boundary[(2, 1)] == g.boundary[(1, 2)]
    assert g.neighbours == {1: (2,), 2: (1, 3), 3: (2,)}
