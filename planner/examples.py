"""Worked examples as data: the workspace of thesis Fig. 3.3/3.6, a printer for labellings, random workspaces.

**Fig. 3.3.** The thesis prints only the caption: "The entire workspace is divided into a grid of 20 by
10 uniform square cells … The labeling of the first slippery cell '1' starts at the robot's initial
position marked by 'X'. When the algorithm has finished labeling all the free cells, three slippery cells
are formed." Fig. 3.2 shows three rooms joined by two open doorways and Fig. 3.6 two checkpoints between
'X' and the goal 'Y'. How many slippery cells form depends on where the doorways are (a doorway halfway
up a wall lets the first cell run a strip through the next room, which splits it), so
:data:`FIG_3_3` is a reconstruction consistent with all three captions: a one-cell border and two
one-cell walls (the padded walls), a doorway at the top of the first wall and one at the bottom of the
second, 'X' in the left room and 'Y' in the right one. Its labelling gives three slippery cells in a
chain, and the route from X to Y two checkpoints.

Map legend (top line = top row, as printed in the thesis): ``#`` occupied, ``.`` free, ``X`` the robot
(free), ``Y`` the goal (free).
"""

from __future__ import annotations

import numpy as np

from planner.bitmap import FREE, OCCUPIED

FIG_3_3_MAP = """
####################
#............#.....#
#............#.....#
#.....#......#.....#
#.X...#......#.....#
#.....#......#..Y..#
#.....#......#.....#
#.....#............#
#.....#............#
####################
"""

def parse_map(text: str) -> tuple[np.ndarray, dict[str, tuple[int, int]]]:
    """Bitmap ``W`` ``(ny, nx)`` (0 free, −1 occupied; row 0 at the bottom) and the marked cells ``{'X': (iy, ix)}``.

    ``text``: one line per row, top row first; ``#`` occupied, any other character free, letters mark cells.
    """
    lines = [line for line in text.strip("\n").splitlines() if line.strip()]
    if len({len(line) for line in lines}) != 1:
        raise ValueError("map lines must all have the same length")
    rows = lines[::-1]
    W = np.array([[OCCUPIED if ch == "#" else FREE for ch in row] for row in rows], dtype=np.int32)
    marks = {ch: (iy, ix) for iy, row in enumerate(rows) for ix, ch in enumerate(row) if ch.isalpha()}
    return W, marks


def fig_3_3() -> tuple[np.ndarray, tuple[int, int], tuple[int, int]]:
    """The reconstructed Fig. 3.3 workspace: ``(W, robot_cell, goal_cell)`` with cells as ``(iy, ix)``."""
    W, marks = parse_map(FIG_3_3_MAP)
    return W, marks["X"], marks["Y"]


def format_labels(labels: np.ndarray, marks: dict[tuple[int, int], str] | None = None) -> str:
    """The bitmap or labelling ``labels`` ``(ny, nx)`` as the thesis prints it (Fig. 3.3): one line per row,
    top row first, each entry right-aligned (−1 occupied, 0 free, k slippery cell k), with ``marks``
    (``{(iy, ix): 'X'}``) in place of the labels of those cells.
    """
    labels = np.asarray(labels)
    marks = marks or {}
    width = max(len(str(v)) for v in labels.ravel().tolist() + [-1]) + 1
    lines = []
    for iy in range(labels.shape[0] - 1, -1, -1):
        lines.append("".join(marks.get((iy, ix), str(v)).rjust(width) for ix, v in enumerate(labels[iy].tolist())))
    return "\n".join(lines)


def random_bitmap(shape: tuple[int, int], density: float, rng: np.random.Generator,
                  max_side: int | None = None) -> np.ndarray:
    """A random workspace bitmap ``shape`` = (ny, nx) of rectangular obstacles covering about ``density``.

    Axis-aligned rectangles with sides uniform in ``1 … max_side`` cells (default a tenth of the larger
    side) are dropped uniformly until at least ``density`` of the cells are occupied; the outer frame is
    occupied too (the arena's padded border), like a padded world at that resolution.
    """
    ny, nx = shape
    if not 0.0 <= density < 1.0:
        raise ValueError(f"density must be in [0, 1), got {density}")
    max_side = max_side or max(2, max(ny, nx) // 10)
    occupied = np.zeros(shape, dtype=bool)
    occupied[[0, -1], :] = occupied[:, [0, -1]] = True
    while occupied.mean() < density:
        h, w = rng.integers(1, max_side + 1, size=2)
        y, x = rng.integers(0, ny), rng.integers(0, nx)
        occupied[y:y + h, x:x + w] = True
    return np.where(occupied, OCCUPIED, FREE).astype(np.int32)


def main() -> None:
    """Print the Fig. 3.3 reconstruction as the thesis does: (a) the bitmap, (b) its slippery-cell labelling."""
    from planner.slippery import label_slippery

    W, robot, goal = fig_3_3()
    labels = label_slippery(W, robot)
    marks = {robot: "X", goal: "Y"}
    print("Fig. 3.3(a) bitmap (0 free, -1 occupied):")
    print(format_labels(W, marks))
    print(f"\nFig. 3.3(b) slippery cells, labelled from the robot's cell X: {int(labels.max())} cells")
    print(format_labels(labels, marks))


if __name__ == "__main__":
    main()
