"""The soccer field: a walled rectangle with a goal at each end (Sahota 1993, ch. 4.1.1, at Khepera scale).

Coordinates are metres, origin at the bottom-left corner of the playing surface, x along the field, y across.
The playing surface is ``[0, length] × [0, width]``. Side 0 (the "left" team) defends the goal at x = 0,
side 1 the goal at x = ``length``. Each goal is a box ``goal_depth`` deep behind its end wall, open to the
field through a mouth ``goal_mouth`` wide centred on the end, between y = (width − mouth)/2 and
(width + mouth)/2. The goal line is the mouth's segment on the end line (x = 0 or x = length).

Walls stand *outside* the surface they bound: each is a segment of thickness ``wall_thickness`` whose inner
face lies on the field's edge (or the goal box's), so the lines of the game are exactly x = 0, x = length,
y = 0, y = width and the goal box is exactly ``[−depth, 0] × mouth`` (mirrored at x = length). Joints are
rounded with radius ``wall_thickness / 2``, as a pymunk segment is.

Where the numbers come from
---------------------------
Sahota's field is 244 cm × 122 cm for 1/24-scale cars 22 cm long and 8 cm wide driving at up to 1.4 m/s
(ch. 4.1.1); he gives no goal size. The Khepera is 5.5 cm across and drives at 0.16 m/s (``KHEPERA``).

* ``width`` 0.8 m: Sahota's width is about 15 car widths (122 / 8); 15 Khepera diameters are 0.83 m.
* ``length`` 1.2 m: Sahota's length halved (1.22 m), rounded. Scaling it by the body width too (1.68 m)
  would make a full-speed crossing take 10.5 s where his cars took under 2 s; 1.2 m takes 7.5 s, and is
  the length of the project's own arenas (``three-rooms``).
* ``goal_mouth`` 0.24 m: our choice, 30 % of the width, about 4.4 robot diameters — wide enough for a
  goalkeeper to have to move, narrow enough to miss — and six ball diameters.
* ``goal_depth`` 0.06 m: our choice, deeper than a ball's diameter (4 cm) so a scored ball lies wholly
  behind the line and its bounce off the back wall stays near the mouth.
* ``wall_thickness`` 0.01 m: the world files' default (``robots.worldfile``).

Sahota's corner barriers (ch. 4.1.1: they keep the ball from being trapped in a corner) are not modelled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ekm.errors import InputError
from robots.geometry import Point, Segment, segment_distance

SIDES = (0, 1)
"""Side 0 defends the goal at x = 0 (the "left" team), side 1 the goal at x = length."""


def _check(name: str, value, *, positive: bool = True) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"Field.{name}: must be a number, got {value!r}")
    if not math.isfinite(value):
        raise InputError(f"Field.{name}: must be finite, got {value}")
    if positive and value <= 0:
        raise InputError(f"Field.{name}: must be > 0 m, got {value}")
    if not positive and value < 0:
        raise InputError(f"Field.{name}: must be >= 0 m, got {value}")


@dataclass(frozen=True)
class Field:
    """A rectangular soccer field with two goals (module docstring: layout and the numbers' sources).

    All sizes in metres. ``goal_mouth`` must be narrower than ``width`` (the end wall keeps a piece beside
    each post); every size is > 0 except ``wall_thickness`` (>= 0). A bad value raises
    :class:`ekm.errors.InputError` with one line naming it.
    """

    length: float = 1.2
    width: float = 0.8
    goal_mouth: float = 0.24
    goal_depth: float = 0.06
    wall_thickness: float = 0.01

    def __post_init__(self):
        for name in ("length", "width", "goal_mouth", "goal_depth"):
            _check(name, getattr(self, name))
        _check("wall_thickness", self.wall_thickness, positive=False)
        if self.goal_mouth >= self.width:
            raise InputError(f"Field.goal_mouth: must be narrower than the field's width {self.width} m, "
                             f"got {self.goal_mouth}")

    # ------------------------------------------------------------------------------------------ points
    @property
    def centre_spot(self) -> Point:
        """``(length / 2, width / 2)``: where the ball is placed to start and, under rule "centre", after a goal."""
        return (0.5 * self.length, 0.5 * self.width)

    @property
    def mouth(self) -> tuple[float, float]:
        """``(y0, y1) = ((width − mouth) / 2, (width + mouth) / 2)``: the posts' y (m), the same at both ends."""
        return (0.5 * (self.width - self.goal_mouth), 0.5 * (self.width + self.goal_mouth))

    def goal_x(self, side: int) -> float:
        """x of the goal line that ``side`` defends: 0 for side 0, ``length`` for side 1."""
        _side(side)
        return 0.0 if side == 0 else self.length

    def goal_line(self, side: int) -> Segment:
        """The goal line ``side`` defends: the mouth on its end line, from ``(x, y0)`` to ``(x, y1)``."""
        x = self.goal_x(side)
        y0, y1 = self.mouth
        return Segment((x, y0), (x, y1))

    def goal_box(self, side: int) -> tuple[float, float, float, float]:
        """The inside of the goal ``side`` defends, ``(xmin, ymin, xmax, ymax)``: ``[−depth, 0] × [y0, y1]`` for
        side 0, ``[length, length + depth] × [y0, y1]`` for side 1."""
        x = self.goal_x(side)
        y0, y1 = self.mouth
        return (x - self.goal_depth, y0, x, y1) if side == 0 else (x, y0, x + self.goal_depth, y1)

    def half(self, point) -> int | None:
        """Whose half ``point`` = (x, y) is in: 0 if x < length / 2 (side 0's, goal box included), 1 if
        x > length / 2, None on the half-way line itself (it belongs to neither, so "cleared" means crossed)."""
        x, mid = float(point[0]), 0.5 * self.length
        return 0 if x < mid else 1 if x > mid else None

    def clearance(self, point) -> float:
        """Distance (m) from ``point`` = (x, y) to the nearest wall's surface: min over :meth:`walls` of the
        distance to the centre line minus ``wall_thickness / 2`` (negative inside a wall)."""
        p = np.asarray(point, dtype=float)
        h = 0.5 * self.wall_thickness
        return float(min(segment_distance(p, s.start, s.end) for s in self.walls())) - h

    def contains(self, point, margin: float = 0.0) -> bool:
        """Whether a disc of radius ``margin`` centred on ``point`` = (x, y) lies on the pitch without
        overlapping a wall: the centre is in the field ``[0, length] × [0, width]`` or in the channel through
        both mouths ``[−depth, length + depth] × [y0, y1]``, and :meth:`clearance` >= ``margin``."""
        x, y = float(point[0]), float(point[1])
        y0, y1 = self.mouth
        in_field = 0.0 <= x <= self.length and 0.0 <= y <= self.width
        in_channel = -self.goal_depth <= x <= self.length + self.goal_depth and y0 <= y <= y1
        return (in_field or in_channel) and self.clearance((x, y)) >= margin

    # ------------------------------------------------------------------------------------------ walls
    def walls(self) -> tuple[Segment, ...]:
        """The centre lines of every wall, 12 segments, each to be given thickness ``wall_thickness``.

        With h = thickness / 2 and (y0, y1) the mouth: the bottom and top side walls (y = −h and y = width + h,
        from x = −h to length + h); at each end two pieces of end wall (x = −h or length + h) from the corner
        to the post, ending at y0 − h and y1 + h; and each goal box's two sides (y = y0 − h and y1 + h) and
        back (x = −depth − h, or length + depth + h). Every end point is shared by exactly two segments: the
        outline is closed, the only openings are the mouths.
        """
        h = 0.5 * self.wall_thickness
        L, W, d = self.length, self.width, self.goal_depth
        y0, y1 = self.mouth
        segs = [Segment((-h, -h), (L + h, -h)), Segment((-h, W + h), (L + h, W + h))]
        for x, out in ((-h, -1.0), (L + h, 1.0)):  # end line, and which way the goal box points
            back = x + out * d
            segs += [
                Segment((x, -h), (x, y0 - h)),  # end wall, corner to the lower post
                Segment((x, y1 + h), (x, W + h)),  # end wall, upper post to the corner
                Segment((x, y0 - h), (back, y0 - h)),  # goal box, lower side
                Segment((back, y0 - h), (back, y1 + h)),  # goal box, back
                Segment((back, y1 + h), (x, y1 + h)),  # goal box, upper side
            ]
        return tuple(segs)


def _side(side) -> int:
    if side not in SIDES or isinstance(side, bool):
        raise InputError(f"side: must be 0 or 1, got {side!r}")
    return side
