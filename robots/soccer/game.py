"""A game's physics: robots and a ball on a pitch, stepped together in control periods (the imperative shell).

:class:`Game` puts N :class:`robots.body.RobotBody` robots (own motors, motor and sensor noise, IR ring,
contact bookkeeping; read there how a robot moves) into a :class:`robots.soccer.ball.Pitch` (the walls and the
ball) and steps them together. Each 16 ms physics sub-step: every robot's velocity is set from its motors
(:meth:`RobotBody.drive`), the ball rolls and the space steps once (:meth:`Pitch.step`), every robot settles,
and the referee (:func:`robots.soccer.referee.judge`) judges the ball's move.

* Robots see each other: each has its own category bit, and the IR of each sees the walls and the others —
  not the ball (it rolls below the sensors' plane, :mod:`robots.soccer.play`).
* Robots push the ball: a robot drives into it unhindered (touching it is not a collision), and the ball
  bounces off a robot with the ball's ``restitution``, as off a wall: a robot at speed v sends a still ball
  off at (1 + e)·m_r/(m_r + m_b)·v — 0.96 (1 + e) v, 0.262 m/s at full speed — for in the sub-step of the
  bounce the robot is a free 70 g body (its velocity is set again only before the next). Robots shove each
  other: each removes from its velocity only the part that would push into the other *relative to the
  other's motion*, so a robot driving into a still one pushes it.
* After a counted goal under rule ``"centre"`` the ball goes back on the centre spot and every robot to its
  kick-off pose, at rest (a kick-off, as in soccer; the robots' motor and sensor noise streams go on).
  Under ``"sahota"`` play goes on.
* A dead ball is restarted: when the ball has stayed within ``stall_m`` (2 cm) of where it was for ``stall_s``
  (15 s) — pinned against a wall that the players' avoidance keeps them off, or held between two players that
  avoid each other — the game restarts from kick-off, whatever the rule (:attr:`Game.restarts` counts them).
  Sahota's field had corner barriers against a trapped ball (ch. 4.1.1); this rule is ours, and keeps a game
  of wall-shy players a game rather than a stand-off.
"""

from __future__ import annotations

import math

import numpy as np

from ekm.angles import wrap
from robots.body import RobotBody, finite
from robots.params import KHEPERA, RobotParams
from robots.soccer.ball import BALL_COLLISION_TYPE, BallParams, Pitch
from robots.soccer.field import Field
from robots.soccer.referee import RULES, Score, judge
from ekm.errors import InputError

BALL_CATEGORY = 1 << 20
"""Collision category bit of the ball: every robot's IR skips it."""


def kickoff_poses(field: Field, robot: RobotParams = KHEPERA) -> tuple[np.ndarray, np.ndarray]:
    """The two kick-off poses: side 0 a quarter of the length from its own goal line on the centre line, facing
    the other goal (θ = 0); side 1 its mirror image (θ = π)."""
    y = 0.5 * field.width
    return np.array([0.25 * field.length, y, 0.0]), np.array([0.75 * field.length, y, np.pi])


def robot_list(params, robots: int) -> list[RobotParams]:
    """``params`` — one robot for all, or one per robot — as a list of ``robots``; refused in one line if their
    physics sub-steps or control periods differ (the game steps them together)."""
    each = [params] * robots if isinstance(params, RobotParams) else list(params)
    if len(each) != robots or not all(isinstance(r, RobotParams) for r in each):
        raise InputError(f"Game: {robots} robots need one robot or {robots}, got {params!r}")
    for r in each[1:]:
        for key in ("dt", "avoid_period"):
            if getattr(r, key) != getattr(each[0], key):
                raise InputError(f"Game: robots {each[0].name} and {r.name} must share {key} (the game steps them "
                                 f"together), got {getattr(each[0], key)} and {getattr(r, key)}")
    return each


class Game:
    """Robots and a ball on a pitch (module docstring).

    Parameters
    ----------
    field, ball : the pitch. ``robots`` : int, how many robots (robot i plays side ``i % 2``).
    seeds : sequence of int, one per robot: its motor and sensor noise.
    params : RobotParams, or a sequence of them, one per robot (:mod:`robots.robotfile`); they must share the
        physics sub-step ``dt`` and the control period.
    kickoff : sequence of ``(3,)`` poses, one per robot (default :func:`kickoff_poses` for two robots).
    rule : ``"centre"`` or ``"sahota"`` (:mod:`robots.soccer.referee`).
    stall_s, stall_m : a ball that stays within ``stall_m`` m for ``stall_s`` s is dead: kick-off again.

    Attributes
    ----------
    pitch : Pitch. ``robots`` : list of RobotBody. ``score`` : Score. ``goals`` : list of ``(t, side)`` of every
    counted goal. ``restarts`` : list of ``t`` of every dead-ball restart. ``ball_trace`` : ndarray ``(n, 2)``, the ball after each sub-step of the last period.
    """

    def __init__(self, field: Field = Field(), ball: BallParams = BallParams(), robots: int = 2, seeds=(0, 1),
                 params: RobotParams = KHEPERA, kickoff=None, rule: str = "centre", stall_s: float = 15.0,
                 stall_m: float = 0.02):
        if rule not in RULES:
            raise InputError(f"rule: must be one of {', '.join(RULES)}, got {rule!r}")
        if len(seeds) != robots:
            raise InputError(f"Game: {robots} robots need {robots} seeds, got {len(seeds)}")
        each = robot_list(params, robots)
        kickoff = kickoff_poses(field, each[0]) if kickoff is None else kickoff
        if len(kickoff) != robots:
            raise InputError(f"Game: {robots} robots need {robots} kick-off poses, got {len(kickoff)}")
        self.field, self.params, self.rule = field, each[0], rule
        self.pitch = Pitch(field, ball)
        self.pitch.ball_shape.filter = self.pitch.ball_shape.filter._replace(categories=BALL_CATEGORY)
        self._k = 0
        self.robots = [RobotBody(self.pitch.space, self._clock, robot, seed, index=i,
                                 pushes=(BALL_COLLISION_TYPE,), unseen=BALL_CATEGORY)
                       for i, (robot, seed) in enumerate(zip(each, seeds))]
        for r in self.robots:
            self.pitch.space.on_collision(BALL_COLLISION_TYPE, r.collision_type, begin=self._bounce)
        self.kickoff = [finite(p, 3, "kickoff") for p in kickoff]
        for i, (r, pose) in enumerate(zip(self.robots, self.kickoff)):
            if not field.contains(pose[:2], margin=r.params.radius):
                raise InputError(f"Game: kick-off pose {i} {pose.tolist()} puts the robot off the pitch or into a wall")
            r.place(pose)
        if not (stall_s > 0 and stall_m > 0):
            raise InputError(f"Game: stall_s and stall_m must be > 0, got {stall_s}, {stall_m}")
        self.stall_s, self.stall_m = float(stall_s), float(stall_m)
        self.score = Score()
        self.goals: list[tuple[float, int]] = []
        self.restarts: list[float] = []
        self._anchor, self._anchor_t = self.pitch.ball_position, 0.0
        self.ball_trace = self.pitch.ball_position[None, :]

    def _clock(self) -> float:
        return self._k * self.params.dt

    def _bounce(self, arbiter, space, data) -> None:
        arbiter.restitution = self.pitch.params.restitution

    @property
    def t(self) -> float:
        """Game time (s)."""
        return self._k * self.params.dt

    def restart(self) -> None:
        """A kick-off: the ball on the centre spot, every robot at its kick-off pose, at rest."""
        self.pitch.place(*self.field.centre_spot)
        for r, pose in zip(self.robots, self.kickoff):
            r.place(pose)
        self._anchor, self._anchor_t = self.pitch.ball_position, self.t

    def step(self, commands, period: float | None = None) -> list[tuple[float, int]]:
        """Drive every robot with its wheel command ``(2,)`` (m/s) for one control period (0.128 s by default),
        refereeing every sub-step; returns the goals ``(t, side)`` counted in this period. After a kick-off (a
        goal under rule "centre", a dead ball) the robots stay at rest on their kick-off poses for the rest of
        the period: the next period starts from the kick-off."""
        if len(commands) != len(self.robots):
            raise InputError(f"Game.step: {len(self.robots)} robots need as many commands, got {len(commands)}")
        twists = [r.motors(c, period=period) for r, c in zip(self.robots, commands)]
        n = len(twists[0][0])
        still = False  # after a kick-off the robots stay at rest on their poses to the period's end
        traces = [np.empty((n, 3)) for _ in self.robots]
        balls = np.empty((n, 2))
        scored = []
        dt = self.params.dt
        for j in range(n):
            for r, (v, omega) in zip(self.robots, twists):
                r.drive(0.0 if still else v[j], 0.0 if still else omega[j])
            before = self.pitch.ball_body.position
            self.pitch.step(dt)
            self._k += 1
            for i, r in enumerate(self.robots):
                r.settle(unsqueeze=False)
                x, y = r.body.position
                traces[i][j] = (x, y, r.body.angle)
            after = self.pitch.ball_body.position
            verdict = judge(self.score, before, after, self.field, self.rule)
            self.score = verdict.score
            if verdict.scored is not None:
                scored.append((self.t, verdict.scored))
                self.goals.append((self.t, verdict.scored))
            if verdict.recentre:
                self.restart()
                still = True
                self.score = self.score._replace(in_goal=None)
            elif math.hypot(after.x - self._anchor[0], after.y - self._anchor[1]) > self.stall_m:
                self._anchor, self._anchor_t = (after.x, after.y), self.t
            elif self.t - self._anchor_t >= self.stall_s - 1e-9:
                self.restarts.append(self.t)
                self.restart()
                still = True
            balls[j] = tuple(self.pitch.ball_body.position)
        for r, tr in zip(self.robots, traces):
            tr[:, 2] = wrap(tr[:, 2])
            r.trace = tr
        self.ball_trace = balls
        return scored
