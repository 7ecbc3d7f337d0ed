"""Geometry (robots.geometry): the polygon check added for the physics (polygon_self_intersection)."""

import pytest

from robots.geometry import polygon_self_intersection

U_POINTS = [[0.45, 0.255], [0.77, 0.255], [0.77, 0.545], [0.45, 0.545],
            [0.45, 0.525], [0.75, 0.525], [0.75, 0.275], [0.45, 0.275]]


@pytest.mark.parametrize("points, crossing", [
    ([(0, 0), (1, 0), (1, 1), (0, 1)], None),
    ([tuple(p) for p in U_POINTS], None),
    ([(0, 0), (1, 1), (1, 0), (0, 1)], (0, 2)),  # bow tie
    ([(0, 0), (2, 0), (1, 0), (1, 1)], (0, 1)),  # spike folding back along itself
    ([(0, 0), (1, 0), (1, 1), (1, 1), (0, 1)], (1, 3)),  # repeated point
    ([(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)], (0, 2)),  # a vertex touching another edge
], ids=["square", "U", "bow-tie", "spike", "repeated-point", "touching"])
def test_polygon_self_intersection(points, crossing):
    assert polygon_self_intersection(points) == crossing
