"""The pymunk world: walls, obstacles, moving obstacles, events, contact and IR sensors (docs/design.md §2).

This is the imperative shell around :mod:`robots.kinematics` for every run that has obstacles in it
(thesis ch. 6.2: Figs. 6.3–6.8). One :class:`PymunkWorld` holds one robot in one :class:`World`::

    from robots.worldfile import load_world
    from robots.world import PymunkWorld

    sim = PymunkWorld(load_world("three-rooms-static"), seed=0)
    readings = sim.sense()                     # 12 long-range IR readings (m from the body surface)
    state, trace = sim.step([0.08, 0.10])      # one 0.128 s control period

How the robot moves
-------------------
The motors are the kinematics' own: :func:`~robots.kinematics.quantize_command` (clip to c*, speed unit),
:func:`~robots.kinematics.motor_twist` (first-order lag, then 10 % Webots slip noise). Before each physics
sub-step the body's velocity is *set* from that speed and turn rate — velocity control —
and ``space.step(dt)`` moves it by explicit Euler, exactly the integration of
:func:`robots.kinematics.advance`. In free space both simulators therefore trace the same path (to
floating-point rounding).

Contact: the body is a dynamic circle of radius 25 mm without friction or bounce. While it touches
something, the part of its commanded velocity that would push into the contact (relative to the other
body, so a moving obstacle shoves the robot) is removed before the sub-step: the wheels keep turning and
the robot slides along walls instead of being driven through them. Without this the solver's gentle
position correction lets a velocity-controlled body sink about a body radius into a wall.
Overlaps stay within one sub-step of travel (about 2.6 mm at full speed) and decay to the 0.1 mm slop.
A moving obstacle (a kinematic body, of infinite mass) that shoves the robot against a wall would squeeze
it through: there the wall wins, and the robot is set back onto the wall's surface (``_unsqueeze``).

Moving obstacles are kinematic bodies: before each sub-step their velocity is set to the secant
``(path(t + dt) - position) / dt``, so they sit exactly on their path after every sub-step and their
contacts see the true velocity. Events add their shapes (static) at the first sub-step with
``t >= at_s`` at which the robot's body is clear of them (a door does not close on the robot). A moving
goal is ``world.goal_at(t)``.

Randomness: one seed → two independent streams (``numpy`` ``Generator.spawn``), one for actuator noise
and one for sensor noise, so how often a controller reads its sensors does not change the motor noise
it gets. Same seed, same calls → the same trajectory, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
from pymunk.autogeometry import convex_decomposition

from robots import kinematics
from robots.geometry import Box, Circle, Polygon, Segment, Shape, distance, signed_area
from robots.kinematics import RobotState
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.sensors import ir_readings, sensor_rays
from robots.worldfile import World

ROBOT_CATEGORY = 0b1
"""Collision category bit of the robot's body: IR rays use a filter that excludes it."""

_SENSOR_FILTER = pymunk.ShapeFilter(mask=pymunk.ShapeFilter.ALL_MASKS() ^ ROBOT_CATEGORY)
_ROBOT_COLLISION_TYPE = 1
_ROBOT_MASS = 0.07  # kg, Khepera I (K-Team manual). Walls are static and movers kinematic, so it never matters.
_SLOP = 1e-4  # m of overlap pymunk tolerates before it pushes shapes apart (its default, 0.1, is in pixels)

#: s without contact after which a new contact is a new collision: shorter breaks are the same episode
#: (a robot pressed against a jamb makes and breaks contact every few 16 ms sub-steps).
REJOIN_S = 0.5


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
        A validated world (:func:`robots.worldfile.load_world`).
    params : RobotParams
        The robot (body radius, motors, sub-step ``dt``, sensor sets).
    seed : int
        Seeds the actuator- and sensor-noise streams.

    Attributes
    ----------
    world, params : the world and robot this simulation runs.
    space : pymunk.Space
        The physics space (for inspection; change it at your own risk).
    wheels : ndarray ``(2,)``
        Current wheel speeds (m/s), the motor state carried between periods.
    collisions : int
        Contact episodes between the robot and anything (wall, obstacle, mover): an episode begins when the
        robot touches something after touching nothing for at least ``rejoin_s`` and lasts while it keeps
        touching. Sliding along a wall, bumping into a corner where two walls meet, or jittering against a
        door jamb (contact made and broken every few sub-steps) is one collision each.
    contact_s : float
        Time (s) the robot has spent touching something, summed over the sub-steps that end in contact.
    trace : ndarray ``(n, 3)``
        Poses after every sub-step of the last :meth:`step` (the start pose before the first step).
    """

    def __init__(self, world: World, params: RobotParams = KHEPERA, seed: int = 0):
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ValueError(f"PymunkWorld: seed must be a non-negative integer, got {seed!r}")
        self.world = world
        self.params = params
        self._motor_rng, self._sensor_rng = np.random.default_rng(int(seed)).spawn(2)
        self._k = 0  # sub-steps taken; t = k dt without drift

        self.space = pymunk.Space()
        self.space.collision_slop = _SLOP
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

        self._body = pymunk.Body(_ROBOT_MASS, pymunk.moment_for_circle(_ROBOT_MASS, 0.0, params.radius))
        disc = pymunk.Circle(self._body, params.radius)
        disc.friction, disc.elasticity = 0.0, 0.0
        disc.collision_type = _ROBOT_COLLISION_TYPE
        disc.filter = pymunk.ShapeFilter(categories=ROBOT_CATEGORY)
        self.space.add(self._body, disc)
        self._disc = disc
        # Deepest overlap with a wall that the robot's own motion can cause: one sub-step at full speed.
        self._max_overlap = (1.0 + params.actuator_noise) * params.max_wheel_speed * params.dt
        self.collisions = 0
        self.contact_s = 0.0
        self._last_contact = -math.inf  # time of the last sub-step that ended in contact
        self._touching = 0  # contacts begun and not yet separated: without any, the robot has no arbiter
        self.space.on_collision(_ROBOT_COLLISION_TYPE, None, begin=self._begin_contact, separate=self._end_contact)

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
        x, y = self._body.position
        return np.array([x, y, _wrap(self._body.angle)])

    @property
    def state(self) -> RobotState:
        """Pose and wheel speeds as the kinematics' :class:`~robots.kinematics.RobotState`."""
        return RobotState(pose=self.pose, wheels=self.wheels.copy())

    @property
    def goal(self) -> tuple[float, float]:
        """Where the goal is now (a moving target moves, Samba's scenario)."""
        return self.world.goal_at(self.t)

    def moving_positions(self) -> np.ndarray:
        """Positions ``(k, 2)`` of the moving obstacles' origins, in ``world.moving`` order."""
        return np.array([[b.position.x, b.position.y] for b, _ in self._movers]).reshape(-1, 2)

    def place(self, pose) -> None:
        """Put the robot at ``pose`` = (x, y, θ), at rest (wheels stopped). Does not check for overlap."""
        x, y, theta = _finite(pose, 3, "place: pose")
        self._body.position = (x, y)
        self._body.angle = theta
        self._body.velocity = (0.0, 0.0)
        self._body.angular_velocity = 0.0
        self.space.reindex_shapes_for_body(self._body)
        self.wheels = np.zeros(2)
        self.trace = self.pose[None, :]

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
        period = self.params.avoid_period if period is None else period
        n = self.params.substeps(period)
        command = _finite(command, 2, "step: command")
        shape = self.params.noise_shape(period)
        noise = self._motor_rng.uniform(-1.0, 1.0, shape) if noise is None else _finite(noise, shape, "step: noise")
        setpoint = kinematics.quantize_command(command, self.params)
        v, omega, self.wheels = kinematics.motor_twist(self.wheels, setpoint, noise, n, self.params)
        trace = np.empty((n, 3))
        body = self._body
        for j, (vj, wj) in enumerate(zip(v.tolist(), omega.tolist())):
            self._substep(vj, wj)
            x, y = body.position
            trace[j] = (x, y, _wrap(body.angle))
        self.trace = trace
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
        robot = self._body
        theta = robot.angle
        velocity = (v * math.cos(theta), v * math.sin(theta))
        robot.velocity = self._slide(velocity) if self._touching else velocity
        robot.angular_velocity = omega
        self.space.step(dt)
        if self._movers and self._touching:  # an overlap after the step is a contact the step has begun
            self._unsqueeze()
        self._k += 1
        if self._touching:
            self.contact_s += dt
            self._last_contact = self._k * dt

    def _unsqueeze(self) -> None:
        """Move the robot out of any static shape it was pressed into deeper than its own motion can go.

        A kinematic mover has infinite mass: shoving the robot against a wall, it would squeeze it through.
        Here the wall wins — the robot is set back onto the wall's surface and the mover overlaps it
        instead (a contact already counted as a collision).
        """
        for info in self.space.shape_query(self._disc):
            points = info.contact_point_set.points
            if info.shape.body.body_type != pymunk.Body.STATIC or not points:
                continue
            depth = -min(pt.distance for pt in points)
            if depth > self._max_overlap:
                self._body.position -= info.contact_point_set.normal * (depth - _SLOP)
                self.space.reindex_shapes_for_body(self._body)

    def _slide(self, velocity) -> tuple[float, float]:
        """``velocity`` without the parts that push into current contacts (relative to the other body)."""
        contacts: list[tuple[float, float, float, float]] = []
        self._body.each_arbiter(self._contact, contacts)
        vx, vy = velocity
        for nx, ny, ox, oy in contacts:
            push = (vx - ox) * nx + (vy - oy) * ny
            if push > 0.0:
                vx, vy = vx - push * nx, vy - push * ny
        return (vx, vy)

    def _contact(self, arbiter: pymunk.Arbiter, out: list) -> None:
        """Append (normal from the robot into the other shape, other body's velocity there) for ``arbiter``."""
        points = arbiter.contact_point_set.points
        if not points:
            return
        nx, ny = arbiter.normal  # points from shapes[0] to shapes[1]
        other = arbiter.shapes[1].body
        if arbiter.shapes[0].body is not self._body:
            nx, ny, other = -nx, -ny, arbiter.shapes[0].body
        ox, oy = other.velocity_at_world_point(points[0].point_a)
        out.append((nx, ny, ox, oy))

    def _fire_events(self) -> None:
        """Add the shapes of every event whose time has come (``at_s <= t``) — once the robot's body is clear of
        them: a door that closes on the robot waits until the robot has left the doorway (a shape dropped onto
        the robot would be a collision no controller could avoid)."""
        t = self.t + 1e-9  # t = k dt carries rounding; an event at 6.0 s fires at the sub-step that starts at 6.0 s
        due = [e for e in self._pending if e.at_s <= t]
        if not due:
            return
        centre = np.asarray(self._body.position)
        for event in due:
            if all(float(distance(centre, shape)) >= self.params.radius for shape in event.add):
                for shape in event.add:
                    self.space.add(*pymunk_shapes(shape, self.space.static_body))
                self._pending.remove(event)

    def _begin_contact(self, arbiter, space, data) -> None:
        if not self._touching and self._k * self.params.dt - self._last_contact >= REJOIN_S - 1e-9:
            self.collisions += 1  # a new episode (see ``collisions``)
        self._touching += 1

    def _end_contact(self, arbiter, space, data) -> None:
        # Chipmunk calls begin and separate in balanced pairs, and a body's arbiters are those of contacts
        # between the two: with none open, ``_slide`` has nothing to remove (and its ``each_arbiter`` would
        # still cost time on every sub-step).
        self._touching -= 1

    # ---------------------------------------------------------------------------------------- sensors
    def ranges(self, sensors: SensorSet | None = None) -> np.ndarray:
        """True distances ``(m,)`` from the body surface along each sensor ray; ``inf`` beyond the range.

        Rays are pymunk segment queries from the rim outwards that ignore the robot's own body; a rim
        already inside an obstacle (pressed against a wall) reads 0.
        """
        sensors = self.params.long_range if sensors is None else sensors
        out = np.full(len(sensors.angles), np.inf)
        # Every ray lies in the square of half-side radius + range round the centre, and a ray can hit only a
        # shape whose bounding box it crosses: when no shape's box meets the square, no ray hits anything.
        x, y = self._body.position
        reach = self.params.radius + sensors.range_m
        if not self.space.bb_query(pymunk.BB(x - reach, y - reach, x + reach, y + reach), _SENSOR_FILTER):
            return out
        start, end = sensor_rays(self.pose, sensors, self.params.radius)
        query = self.space.segment_query_first
        for i, (a, b) in enumerate(zip(start.tolist(), end.tolist())):
            hit = query(a, b, 0.0, _SENSOR_FILTER)
            if hit is not None:
                out[i] = hit.alpha * sensors.range_m
        return out

    def sense(self, sensors: SensorSet | None = None, noise=None) -> np.ndarray:
        """IR readings ``(m,)``: noisy, quantised distances from the body surface (:func:`robots.sensors.ir_readings`).

        Parameters
        ----------
        sensors : SensorSet, optional
            ``params.long_range`` (12 around, 17.5 cm; thesis ch. 6.2.2) by default, or
            ``params.short_range`` (8 Khepera sensors, 5 cm; ch. 6.2.1).
        noise : array ``(m,)`` or scalar, optional
            Standard-normal sensor noise ξ; drawn from the world's sensor stream if omitted. ``noise=0``
            gives noise-free readings (still quantised to τ = 0.5 cm).

        Returns
        -------
        ndarray ``(m,)``
            Readings in ``[0, range]`` metres, ``inf`` where nothing is within range.
        """
        sensors = self.params.long_range if sensors is None else sensors
        m = len(sensors.angles)
        if noise is None:
            xi = self._sensor_rng.standard_normal(m)
        else:
            xi = np.asarray(noise, dtype=float)
            xi = _finite(np.full(m, xi) if xi.ndim == 0 else xi, m, "sense: noise")
        return ir_readings(self.ranges(sensors), xi, sensors)

    def __repr__(self) -> str:
        x, y, theta = self.pose
        return (f"PymunkWorld({self.world.name!r}, t={self.t:.3f} s, pose=({x:.3f}, {y:.3f}, {theta:.3f}), "
                f"collisions={self.collisions})")


def _wrap(a: float) -> float:
    """:func:`robots.kinematics.wrap_angle` of one float, without NumPy's per-call cost: Python's float ``%``
    is NumPy's ``mod`` for float64 (both take C's ``fmod`` and move the result to the divisor's sign), so
    the value is the same to the bit."""
    return math.pi - (math.pi - a) % (2.0 * math.pi)


def _finite(value, shape, where: str) -> np.ndarray:
    """``value`` as finite floats of ``shape`` (an int n means ``(n,)``), or a ValueError naming ``where``."""
    shape = (shape,) if isinstance(shape, int) else tuple(shape)
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"PymunkWorld.{where} must be numbers of shape {shape}, got {value!r}") from None
    if a.shape != shape:
        raise ValueError(f"PymunkWorld.{where} must have shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"PymunkWorld.{where} must be finite, got {a.tolist()}")
    return a
