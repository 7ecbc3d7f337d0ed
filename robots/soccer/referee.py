"""The referee, a pure function: from the ball's last two positions, is there a goal, and does it count?

A goal is scored when the ball's centre crosses a goal line *inside the mouth* from the field into the goal
between two positions p → q. For the goal side 0 defends (x = 0) that is ``p.x > 0 >= q.x`` with the crossing
point's y,

    y* = p.y + (q.y − p.y) · p.x / (p.x − q.x),

between the posts, ``y0 <= y* <= y1`` (:attr:`Field.mouth`); for side 1's goal the same with x − length and
the inequalities turned round (``p.x < length <= q.x``). The side that did *not* defend that goal scores.

A goal counts only on the ball's *entering* a goal: once in, the ball is "in" that goal (``Score.in_goal``)
until its centre leaves the goal area — the goal box and its mirror image in front of the line
(``|x − goal_x| <= goal_depth`` with y between the posts) — so a ball that bounces off the back of the goal
and rocks back and forth across the line is one goal, not one per crossing.

Two rules (:data:`RULES`):

* ``"centre"``: after every counted goal the caller puts the ball back on the centre spot (the verdict's
  ``recentre`` says so) and passes the centre spot as the next ``previous_ball_xy``.
* ``"sahota"`` (Sahota 1993, ch. 4.3, the LCI Cup: "a robot that had been scored upon had to clear the ball
  from its end before any more goals were counted"): play goes on without re-centring; after a counted goal
  the side scored upon is ``locked`` until the ball's centre is in the other half (:meth:`Field.half`), and no
  goal scored meanwhile counts. Why: in continuous play one robot could otherwise score over and over from
  the rebound.
"""

from __future__ import annotations

from typing import NamedTuple

from ekm.errors import InputError
from robots.soccer.field import SIDES, Field

RULES = ("centre", "sahota")
"""The restart rules :func:`judge` knows (module docstring)."""


class Score(NamedTuple):
    """The state of the game the referee keeps.

    ``goals``: goals counted for (side 0, side 1); side 0 defends x = 0. ``locked``: under rule "sahota", the
    side scored upon that has not yet cleared the ball from its half (no goal counts while set), else None.
    ``in_goal``: the side whose goal the ball has entered and not yet left the goal area of, else None.
    """

    goals: tuple[int, int] = (0, 0)
    locked: int | None = None
    in_goal: int | None = None


class Verdict(NamedTuple):
    """What :func:`judge` decided: the new ``score``; ``scored``, the side credited with a goal on this step
    (None if no goal counted); ``recentre``, True when the caller must put the ball on the centre spot now
    (a counted goal under rule "centre")."""

    score: Score
    scored: int | None
    recentre: bool


def crossing(field: Field, side: int, p, q) -> bool:
    """Whether the ball's centre moving p → q (each (x, y), m) crosses the goal line of the goal ``side``
    defends from the field side into the goal, between the posts (module docstring: the test and y*)."""
    g = field.goal_x(side)
    sign = 1.0 if side == 0 else -1.0  # distance in front of the line, positive on the field side
    a, b = sign * (float(p[0]) - g), sign * (float(q[0]) - g)
    if not (a > 0.0 >= b):
        return False
    y = float(p[1]) + (float(q[1]) - float(p[1])) * a / (a - b)
    y0, y1 = field.mouth
    return y0 <= y <= y1


def in_goal_area(field: Field, side: int, q) -> bool:
    """Whether ``q`` = (x, y) is in the goal area of the goal ``side`` defends: within ``goal_depth`` of its goal
    line on either side (``|x − goal_x| <= goal_depth``) and between the posts."""
    y0, y1 = field.mouth
    return abs(float(q[0]) - field.goal_x(side)) <= field.goal_depth and y0 <= float(q[1]) <= y1


def judge(score: Score, previous_ball_xy, ball_xy, field: Field, rule: str = "centre") -> Verdict:
    """Referee one step of the ball from ``previous_ball_xy`` to ``ball_xy`` (each (x, y), m): the new score,
    who scored, and whether to re-centre (:class:`Verdict`). Pure: the same arguments give the same verdict.

    In order: (1) a crossing into the goal side s defends, with the ball not already in that goal, is an
    entry; it counts for side 1 − s unless a side is locked (rule "sahota"); counted under "sahota", it locks
    s. (2) The ball leaving the goal area of ``in_goal`` clears ``in_goal``. (3) Under "sahota", the ball's
    centre in the half opposite the locked side (:meth:`Field.half`) unlocks it.
    ``rule`` not in :data:`RULES` raises :class:`~ekm.errors.InputError`.
    """
    if rule not in RULES:
        raise InputError(f"rule: must be one of {', '.join(RULES)}, got {rule!r}")
    goals, locked, inside = list(score.goals), score.locked, score.in_goal
    scored = None
    for s in SIDES:
        if inside != s and crossing(field, s, previous_ball_xy, ball_xy):
            inside = s
            if locked is None:
                scored = 1 - s
                goals[scored] += 1
                if rule == "sahota":
                    locked = s
    if inside is not None and not in_goal_area(field, inside, ball_xy):
        inside = None
    if locked is not None and field.half(ball_xy) == 1 - locked:
        locked = None
    new = Score(goals=(goals[0], goals[1]), locked=locked, in_goal=inside)
    return Verdict(new, scored, scored is not None and rule == "centre")
