"""The pymunk world: walls, obstacles, moving obstacles, events, and the one robot in them (docs/design.md §2).

This is the imperative shell around :mod:`robots.kinematics` for every run that has obstacles in it
(thesis ch. 6.2: Figs. 6.3–6.8). One :class:`PymunkWorld` holds one robot in one :class:`World`::

    from robots.worldnames import load_world
    from robots.world import PymunkWorld

    sim = PymunkWorld(load_world("three-rooms-static"), seed=0)
    readings = sim.sense()                     # 12 long-range IR readings (m from the body surface)
    state, trace = sim.step([0.08, 0.10])      # one 0.128 s control period

The robot — its motors and their noise, how it slides along what it touches, its contact episodes, its IR —
is a :class:`robots.body.RobotBody` (read there how it moves); this module holds the world round it.

Moving obstacles are kinematic bodies: before each sub-step their velocity is set to the secant
``(path(t + dt) - position) / dt``, so they sit exactly on their path after every sub-step and their
contacts see the true velocity. Events add their shapes (static) at the first sub-step with
``t >= at_s`` at which the robot's body is clear of them (a door does not close on the robot). A moving
goal is ``world.goal_at(t)``.

Randomness: one seed → the robot's two independent noise streams (actuators, sensors). Same seed, same calls
→ the same trajectory, bit for bit.
"""

from __future__ import annotations

import numpy as np
import pymunk
from pymunk.autogeometry import convex_decomposition

from ekm.angles import wrap
from robots.body import SLOP, RobotBody
from robots.geometry import Box, Circle, Polygon, Segment, Shape, distance, signed_area
from robots.kinematics import RobotState
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.worldfile import World


def convex_pieces(vertices) -> list[np.ndarray]:
    """Split a simple polygon ``(m, 2)`` into convex pieces (``pymunk.Poly`` takes only convex hulls).

    Uses Chipmunk's exact convex decomposition (``pymunk.autogeometry.convex_decomposition`` with zero
    tolerance); a convex polygon comes back as one piece. The pieces tile the polygon: their areas add up
    to its area.
    """
    v = [tuple(map(float, p)) for p in vertices]
    if signed_area(v) < 0:  # Chipmunk wants counter-clockwise outlines
        v = v[::-1]
    hulls = convex_decomposition(v + [v[0]], 0.0)
    return [np.array([tuple(p) for p in hull[:-1]]) for hull in hulls]


def pymunk_shapes(shape: Shape, body: pymunk.Body, thickness: float = 0.0) -> list[pymunk.Shape]:
    """The pymunk shapes of a world ``shape``, attached to ``body`` (in the body's frame).

    Segments get radius ``thickness / 2`` (walls are as thick as the world's ``wall_thickness``; a
    ``segment`` obstacle is infinitely thin, as :func:`robots.geometry.distance` treats it). Shapes have
    no friction and no bounce.
    """
    if isinstance(shape, Circle):
        shapes = [pymunk.Circle(body, shape.radius, offset=shape.center)]
    elif isinstance(shape, Segment):
        shapes = [pymunk.Segment(body, shape.start, shape.end, 0.5 * thickness)]
    elif isinstance(shape, Box):
        shapes = [pymunk.Poly(body, [tuple(p) for p in shape.vertices()])]
    elif isinstance(shape, Polygon):
        shapes = [pymunk.Poly(body, [tuple(p) for p in piece]) for piece in convex_pieces(shape.vertices())]
    else:
        raise TypeError(f"not a world shape: {shape!r}")
    for s in shapes:
        s.friction = 0.0
        s.elasticity = 0.0
    return shapes


class PymunkWorld:
    """One robot in one world, stepped in control periods.

    Parameters
    ----------
    world : World
        A validated world (:func:`robots.worldnames.load_world`).
    params : RobotParams
        The robot (body radius, motors, sub-step ``dt``, sensor sets).
    seed : int
        Seeds the actuator- and sensor-noise streams.

    Attributes
    ----------
    world, params : the world and robot this simulation runs.
    space : pymunk.Space
        The physics space (for inspection; change it at your own risk).
    robot : RobotBody
        The robot's body, motors and sensors.
    wheels : ndarray ``(2,)``
        Current wheel speeds (m/s), the motor state carried between periods.
    collisions : int
        Contact episodes between the robot and anything (wall, obstacle, mover): an episode begins when the
        robot touches something after touching nothing for at least :data:`robots.body.REJOIN_S` and lasts while it keeps
        touching. Sliding along a wall, bumping into a corner where two walls meet, or jittering against a
        door jamb (contact made and broken every few sub-steps) is one collision each.
    contact_s : float
        Time (s) the robot has spent touching something, summed over the sub-steps that end in contact.
    trace : ndarray ``(n, 3)``
        Poses after every sub-step of the last :meth:`step` (the start pose before the first step).
    """

    def __init__(self, world: World, params: RobotParams = KHEPERA, seed: int = 0):
        self.world = world
        self.params = params
        self._k = 0  # sub-steps taken; t = k dt without drift

        self.space = pymunk.Space()
        self.space.collision_slop = SLOP
        static = self.space.static_body
        for wall in world.border + world.walls:
            self.space.add(*pymunk_shapes(wall, static, world.wall_thickness))
        for shape in world.obstacles + world.unforeseen:
            self.space.add(*pymunk_shapes(shape, static))
        self._pending = sorted(world.events, key=lambda e: e.at_s)

        self._movers = []
        for m in world.moving:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            body.position = m.path.position(0.0)
            self.space.add(body, *pymunk_shapes(m.shape, body))
            self._movers.append((body, m.path))

        self.robot = RobotBody(self.space, lambda: self._k * self.params.dt, params, seed)
        self.place(world.start)
        self._fire_events()

    # ------------------------------------------------------------------------------------------ state
    @property
    def t(self) -> float:
        """Simulated time (s)."""
        return self._k * self.params.dt

    @property
    def pose(self) -> np.ndarray:
        """Robot pose ``(3,)`` = (x, y, θ), θ wrapped to (-π, π] (as in :mod:`robots.kinematics`)."""
        return self.robot.pose

    @property
    def state(self) -> RobotState:
        """Pose and wheel speeds as the kinematics' :class:`~robots.kinematics.RobotState`."""
        return self.robot.state

    @property
    def wheels(self) -> np.ndarray:
        return self.robot.wheels

    @property
    def collisions(self) -> int:
        return self.robot.collisions

    @property
    def contact_s(self) -> float:
        return self.robot.contact_s

    @property
    def trace(self) -> np.ndarray:
        return self.robot.trace

    @property
    def goal(self) -> tuple[float, float]:
        """Where the goal is now (a moving target moves, Samba's scenario)."""
        return self.world.goal_at(self.t)

    def moving_positions(self) -> np.ndarray:
        """Positions ``(k, 2)`` of the moving obstacles' origins, in ``world.moving`` order."""
        return np.array([[b.position.x, b.position.y] for b, _ in self._movers]).reshape(-1, 2)

    def place(self, pose) -> None:
        """Put the robot at ``pose`` = (x, y, θ), at rest (wheels stopped). Does not check for overlap."""
        self.robot.place(pose)

    # ------------------------------------------------------------------------------------------- step
    def step(self, command, noise=None, period: float | None = None):
        """Drive with wheel ``command`` = (v_l, v_r) m/s for one control period.

        Parameters
        ----------
        command : array ``(2,)``
            Wheel speed command; clipped to c* and rounded to the speed unit by the motors.
        noise : array ``params.noise_shape(period)`` = ``(K, 2)``, optional
            Slip draws ξ in [-1, 1], one per wheel and 32 ms (each wheel's speed times ``1 + 0.1 ξ``, the
            10 % noise of thesis ch. 6.1). Drawn from the world's actuator stream if omitted; pass
            zeros for a noise-free step.
        period : float, optional
            Control period in seconds, a whole number of sub-steps: ``params.avoid_period`` (0.128 s) by
            default, ``params.target_period`` (1.024 s) for target reaching (thesis ch. 6.1).

        Returns
        -------
        state : RobotState
            Pose and wheel speeds at the end of the period.
        trace : ndarray ``(n, 3)``
            Pose after each sub-step (also kept as :attr:`trace`).
        """
        robot = self.robot
        v, omega = robot.motors(command, noise, period)
        trace = np.empty((len(v), 3))
        body = robot.body
        for j, (vj, wj) in enumerate(zip(v, omega)):
            self._substep(vj, wj)
            x, y = body.position
            trace[j] = (x, y, wrap(body.angle))
        robot.trace = trace
        return self.state, trace

    def _substep(self, v: float, omega: float) -> None:
        dt = self.params.dt
        if self._pending:
            self._fire_events()
        if self._movers:
            t_next = (self._k + 1) * dt
            for body, path in self._movers:
                x, y = path.position(t_next)
                bx, by = body.position
                body.velocity = ((x - bx) / dt, (y - by) / dt)
        self.robot.drive(v, omega)
        self.space.step(dt)
        self._k += 1
        self.robot.settle(unsqueeze=bool(self._movers))

    def _fire_events(self) -> None:
        """Add the shapes of every event whose time has come (``at_s <= t``) — once the robot's body is clear of
        them: a door that closes on the robot waits until the robot has left the doorway (a shape dropped onto
        the robot would be a collision no controller could avoid)."""
        t = self.t + 1e-9  # t = k dt carries rounding; an event at 6.0 s fires at the sub-step that starts at 6.0 s
        due = [e for e in self._pending if e.at_s <= t]
        if not due:
            return
        centre = np.asarray(self.robot.body.position)
        for event in due:
            if all(float(distance(centre, shape)) >= self.params.radius for shape in event.add):
                for shape in event.add:
                    self.space.add(*pymunk_shapes(shape, self.space.static_body))
                self._pending.remove(event)

    # ---------------------------------------------------------------------------------------- sensors
    def ranges(self, sensors: SensorSet | None = None) -> np.ndarray:
        """True distances ``(m,)`` from the body surface along each sensor ray (:meth:`RobotBody.ranges`)."""
        return self.robot.ranges(sensors)

    def sense(self, sensors: SensorSet | None = None, noise=None) -> np.ndarray:
        """IR readings ``(m,)``: noisy, quantised distances from the body surface (:meth:`RobotBody.sense`:
        ``params.long_range`` by default; ``noise=0`` for noise-free readings)."""
        return self.robot.sense(sensors, noise)

    def __repr__(self) -> str:
        x, y, theta = self.pose
        return (f"PymunkWorld({self.world.name!r}, t={self.t:.3f} s, pose=({x:.3f}, {y:.3f}, {theta:.3f}), "
                f"collisions={self.collisions})")
