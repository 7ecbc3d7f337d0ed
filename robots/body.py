"""One robot's body in a pymunk space: its motors and their noise, its contacts, its IR ring (docs/design.md §2).

The part of the simulation that belongs to *a* robot, so that one space can hold several — the single robot of
:class:`robots.world.PymunkWorld` and the players of a soccer game (:mod:`robots.soccer.game`). The space and
its clock belong to the owner, who, each physics sub-step, calls :meth:`RobotBody.drive` on every robot, steps
the space once, then calls :meth:`RobotBody.settle`.

How the robot moves
-------------------
The motors are the kinematics' own: :func:`~robots.kinematics.quantize_command` (clip to c*, speed unit),
:func:`~robots.kinematics.motor_twist` (first-order lag, then 10 % Webots slip noise). Before each physics
sub-step the body's velocity is *set* from that speed and turn rate — velocity control — and ``space.step(dt)``
moves it by explicit Euler, exactly the integration of :func:`robots.kinematics.advance`. In free space both
simulators therefore trace the same path (to floating-point rounding).

Contact: the body is a dynamic circle of radius 25 mm without friction or bounce. While it touches something,
the part of its commanded velocity that would push into the contact (relative to the other body, so a moving
obstacle — or another robot — shoves it) is removed before the sub-step: the wheels keep turning and the robot
slides along walls instead of being driven through them. Without this the solver's gentle position correction
lets a velocity-controlled body sink about a body radius into a wall. Overlaps stay within one sub-step of
travel (about 2.6 mm at full speed) and decay to the 0.1 mm slop. A kinematic mover (infinite mass) that
shoves the robot against a wall would squeeze it through: there the wall wins (:meth:`RobotBody.unsqueeze`).

*Pushed* shapes (``pushes``: collision types, the soccer ball) are the exception: the robot drives into them
unhindered, the solver moves them, and touching one is not a collision.

Sensing: each robot has its own collision category bit; its IR rays skip its own body and every category in
``unseen`` (the soccer ball), and see everything else — walls, obstacles, movers, the other robots.

Randomness: one seed → two independent streams (``numpy`` ``Generator.spawn``), one for actuator noise and
one for sensor noise, so how often a controller reads its sensors does not change the motor noise it gets.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from ekm.angles import wrap
from robots import kinematics
from robots.kinematics import RobotState
from robots.params import KHEPERA, RobotParams, SensorSet
from robots.sensors import ir_readings, sensor_rays

ROBOT_CATEGORY = 0b1
"""Collision category bit of robot 0's body (robot i has bit ``ROBOT_CATEGORY << i``): its IR rays skip it."""
ROBOT_COLLISION_TYPE = 1
"""Collision type of robot 0's body; robot i has ``ROBOT_COLLISION_TYPE + 16 i``."""
MAX_ROBOTS = 16
"""Robots one space can hold: one category bit each, below the bits other shapes may use."""

_ROBOT_MASS = 0.07  # kg, Khepera I (K-Team manual). Walls are static and movers kinematic; only a ball feels it.
SLOP = 1e-4  # m of overlap pymunk tolerates before it pushes shapes apart (its default, 0.1, is in pixels)

#: s without contact after which a new contact is a new collision: shorter breaks are the same episode
#: (a robot pressed against a jamb makes and breaks contact every few 16 ms sub-steps).
REJOIN_S = 0.5


class RobotBody:
    """One robot's disc in ``space``, with motors, noise streams, contact bookkeeping and IR.

    Parameters
    ----------
    space : pymunk.Space
        The owner's space; the body is added to it.
    clock : callable
        ``clock() -> t`` (s), the owner's simulated time (contact episodes are timed with it).
    params : RobotParams
        The robot (body radius, motors, sub-step ``dt``, sensor sets).
    seed : int
        Seeds the actuator- and sensor-noise streams.
    index : int
        Which robot of the space (0 … :data:`MAX_ROBOTS` − 1): its category bit and collision type.
    pushes : tuple of int
        Collision types the robot pushes rather than slides along, and that are not collisions (a ball).
    unseen : int
        Category bits the IR rays skip besides the robot's own (a ball's).

    Attributes
    ----------
    wheels : ndarray ``(2,)``, current wheel speeds (m/s). ``collisions`` : int, contact episodes (see
    :class:`robots.world.PymunkWorld`). ``contact_s`` : float, s spent touching something. ``trace`` : ndarray
    ``(n, 3)``, poses after every sub-step of the last period (the start pose before the first).
    ``body`` : pymunk.Body, ``disc`` : pymunk.Circle.
    """

    def __init__(self, space: pymunk.Space, clock, params: RobotParams = KHEPERA, seed: int = 0, index: int = 0,
                 pushes: tuple = (), unseen: int = 0):
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ValueError(f"PymunkWorld: seed must be a non-negative integer, got {seed!r}")
        if not 0 <= index < MAX_ROBOTS:
            raise ValueError(f"RobotBody: index must be in 0..{MAX_ROBOTS - 1}, got {index}")
        self.space, self.params, self._clock = space, params, clock
        self._motor_rng, self._sensor_rng = np.random.default_rng(int(seed)).spawn(2)
        self.category = ROBOT_CATEGORY << index
        self.collision_type = ROBOT_COLLISION_TYPE + 16 * index
        self._pushes = frozenset(pushes)
        self.sensor_filter = pymunk.ShapeFilter(mask=pymunk.ShapeFilter.ALL_MASKS() ^ (self.category | unseen))

        self.body = pymunk.Body(_ROBOT_MASS, pymunk.moment_for_circle(_ROBOT_MASS, 0.0, params.radius))
        disc = pymunk.Circle(self.body, params.radius)
        disc.friction, disc.elasticity = 0.0, 0.0
        disc.collision_type = self.collision_type
        disc.filter = pymunk.ShapeFilter(categories=self.category)
        space.add(self.body, disc)
        self.disc = disc
        # Deepest overlap with a wall that the robot's own motion can cause: one sub-step at full speed.
        self._max_overlap = (1.0 + params.actuator_noise) * params.max_wheel_speed * params.dt
        self.collisions = 0
        self.contact_s = 0.0
        self._last_contact = -math.inf  # time of the last sub-step that ended in contact
        self.touching = 0  # contacts begun and not yet separated: without any, the robot has no arbiter
        space.on_collision(self.collision_type, None, begin=self._begin_contact, separate=self._end_contact)
        self.wheels = np.zeros(2)
        self.trace = np.zeros((1, 3))

    # ------------------------------------------------------------------------------------------ state
    @property
    def pose(self) -> np.ndarray:
        """Pose ``(3,)`` = (x, y, θ), θ wrapped to (-π, π] (as in :mod:`robots.kinematics`)."""
        x, y = self.body.position
        return np.array([x, y, wrap(self.body.angle)])

    @property
    def state(self) -> RobotState:
        """Pose and wheel speeds as the kinematics' :class:`~robots.kinematics.RobotState`."""
        return RobotState(pose=self.pose, wheels=self.wheels.copy())

    def place(self, pose) -> None:
        """Put the robot at ``pose`` = (x, y, θ), at rest (wheels stopped). Does not check for overlap."""
        x, y, theta = finite(pose, 3, "place: pose")
        self.body.position = (x, y)
        self.body.angle = theta
        self.body.velocity = (0.0, 0.0)
        self.body.angular_velocity = 0.0
        self.space.reindex_shapes_for_body(self.body)
        self.wheels = np.zeros(2)
        self.trace = self.pose[None, :]

    # ------------------------------------------------------------------------------------------ motion
    def motors(self, command, noise=None, period: float | None = None):
        """The body's speed and turn rate on each sub-step of one control period under wheel ``command``.

        ``command`` ``(2,)`` m/s is clipped to c* and rounded to the speed unit; ``noise``
        ``params.noise_shape(period)`` holds slip draws ξ in [-1, 1] (drawn from the actuator stream if
        omitted; zeros for a noise-free period); ``period`` defaults to ``params.avoid_period``. Updates
        :attr:`wheels`; returns ``(v, omega)``, two lists of one float per sub-step.
        """
        period = self.params.avoid_period if period is None else period
        n = self.params.substeps(period)
        command = finite(command, 2, "step: command")
        shape = self.params.noise_shape(period)
        noise = self._motor_rng.uniform(-1.0, 1.0, shape) if noise is None else finite(noise, shape, "step: noise")
        setpoint = kinematics.quantize_command(command, self.params)
        v, omega, self.wheels = kinematics.motor_twist(self.wheels, setpoint, noise, n, self.params)
        return v.tolist(), omega.tolist()

    def drive(self, v: float, omega: float) -> None:
        """Set the body's velocity for the next sub-step: speed ``v`` along its heading (less what would push
        into a contact, :meth:`slide`) and turn rate ``omega``."""
        body = self.body
        theta = body.angle
        velocity = (v * math.cos(theta), v * math.sin(theta))
        body.velocity = self.slide(velocity) if self.touching else velocity
        body.angular_velocity = omega

    def settle(self, unsqueeze: bool) -> None:
        """After the space's step: undo a squeeze into a wall (if ``unsqueeze``: the space has movers) and count
        the sub-step's contact time."""
        if unsqueeze and self.touching:  # an overlap after the step is a contact the step has begun
            self.unsqueeze()
        if self.touching:
            self.contact_s += self.params.dt
            self._last_contact = self._clock()

    def unsqueeze(self) -> None:
        """Move the robot out of any static shape it was pressed into deeper than its own motion can go.

        A kinematic mover has infinite mass: shoving the robot against a wall, it would squeeze it through.
        Here the wall wins — the robot is set back onto the wall's surface and the mover overlaps it
        instead (a contact already counted as a collision).
        """
        for info in self.space.shape_query(self.disc):
            points = info.contact_point_set.points
            if info.shape.body.body_type != pymunk.Body.STATIC or not points:
                continue
            depth = -min(pt.distance for pt in points)
            if depth > self._max_overlap:
                self.body.position -= info.contact_point_set.normal * (depth - SLOP)
                self.space.reindex_shapes_for_body(self.body)

    def slide(self, velocity) -> tuple[float, float]:
        """``velocity`` without the parts that push into current contacts (relative to the other body)."""
        contacts: list[tuple[float, float, float, float]] = []
        self.body.each_arbiter(self._contact, contacts)
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
        mine, other = arbiter.shapes
        if mine.body is not self.body:
            nx, ny, mine, other = -nx, -ny, other, mine
        if other.collision_type in self._pushes:
            return
        ox, oy = other.body.velocity_at_world_point(points[0].point_a)
        out.append((nx, ny, ox, oy))

    def _other(self, arbiter: pymunk.Arbiter) -> pymunk.Shape:
        a, b = arbiter.shapes
        return b if a.body is self.body else a

    def _begin_contact(self, arbiter, space, data) -> None:
        if self._other(arbiter).collision_type in self._pushes:
            return
        if not self.touching and self._clock() - self._last_contact >= REJOIN_S - 1e-9:
            self.collisions += 1  # a new episode (see ``collisions``)
        self.touching += 1

    def _end_contact(self, arbiter, space, data) -> None:
        # Chipmunk calls begin and separate in balanced pairs, and a body's arbiters are those of contacts
        # between the two: with none open, ``slide`` has nothing to remove (and its ``each_arbiter`` would
        # still cost time on every sub-step).
        if self._other(arbiter).collision_type in self._pushes:
            return
        self.touching -= 1

    # ---------------------------------------------------------------------------------------- sensors
    def ranges(self, sensors: SensorSet | None = None) -> np.ndarray:
        """True distances ``(m,)`` from the body surface along each sensor ray; ``inf`` beyond the range.

        Rays are pymunk segment queries from the rim outwards that ignore the robot's own body (and ``unseen``
        shapes); a rim already inside an obstacle (pressed against a wall) reads 0.
        """
        sensors = self.params.long_range if sensors is None else sensors
        out = np.full(len(sensors.angles), np.inf)
        # Every ray lies in the square of half-side radius + range round the centre, and a ray can hit only a
        # shape whose bounding box it crosses: when no shape's box meets the square, no ray hits anything.
        x, y = self.body.position
        reach = self.params.radius + sensors.range_m
        if not self.space.bb_query(pymunk.BB(x - reach, y - reach, x + reach, y + reach), self.sensor_filter):
            return out
        start, end = sensor_rays(self.pose, sensors, self.params.radius)
        query = self.space.segment_query_first
        for i, (a, b) in enumerate(zip(start.tolist(), end.tolist())):
            hit = query(a, b, 0.0, self.sensor_filter)
            if hit is not None:
                out[i] = hit.alpha * sensors.range_m
        return out

    def sense(self, sensors: SensorSet | None = None, noise=None) -> np.ndarray:
        """IR readings ``(m,)``: noisy, quantised distances from the body surface (:func:`robots.sensors.ir_readings`).

        ``sensors``: ``params.long_range`` (12 around, 17.5 cm; thesis ch. 6.2.2) by default, or
        ``params.short_range`` (8 Khepera sensors, 5 cm; ch. 6.2.1). ``noise`` ``(m,)`` or scalar:
        standard-normal sensor noise ξ, drawn from the sensor stream if omitted; ``noise=0`` gives noise-free
        readings (still quantised to τ = 0.5 cm). Readings are in ``[0, range]`` m, ``inf`` where nothing is
        within range.
        """
        sensors = self.params.long_range if sensors is None else sensors
        m = len(sensors.angles)
        if noise is None:
            xi = self._sensor_rng.standard_normal(m)
        else:
            xi = np.asarray(noise, dtype=float)
            xi = finite(np.full(m, xi) if xi.ndim == 0 else xi, m, "sense: noise")
        return ir_readings(self.ranges(sensors), xi, sensors)


def finite(value, shape, where: str) -> np.ndarray:
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
