"""Parameters of a differential-drive robot, in one frozen dataclass (docs/design.md §2), and the Khepera.

Every number of :data:`KHEPERA` names its source. SI units throughout: metres, seconds, radians. Other
robots are data: robot files (:mod:`robots.robotfile`) hold every field, and ``ekm robots`` lists the
named ones.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

#: Khepera I short-range IR sensor directions (rad, robot frame, 0 = ahead, + = left): about ±85°, ±45°,
#: ±10° in front and two at the back (thesis Fig. 4.3; K-Team Khepera user manual, sensor layout).
KHEPERA_IR_ANGLES = tuple(math.radians(a) for a in (85.0, 45.0, 10.0, -10.0, -45.0, -85.0, -160.0, 160.0))

#: 12 long-range sensors evenly around the body (thesis ch. 6.2.2: "12 directed long-range sensors were
#: modelled around the robot's body"); the first one looks straight ahead.
LONG_RANGE_IR_ANGLES = tuple(2.0 * math.pi * k / 12.0 - (2.0 * math.pi if k > 6 else 0.0) for k in range(12))


@dataclass(frozen=True)
class SensorSet:
    """A ring of directed IR range sensors on the body's rim.

    ``range_m`` is measured from the body surface: the long-range set (17.5 cm) sees obstacles up to
    20 cm from the robot's centre (thesis ch. 6.2.2).
    """

    angles: tuple[float, ...]
    range_m: float
    resolution_m: float = 0.005  # tau = 0.5 cm (thesis ch. 6.2.2)
    noise: float = 0.10  # 10 % sensor noise (thesis ch. 6.1, Webots)


SHORT_RANGE = SensorSet(angles=KHEPERA_IR_ANGLES, range_m=0.05)  # 5 cm (thesis ch. 6.2.1)
LONG_RANGE = SensorSet(angles=LONG_RANGE_IR_ANGLES, range_m=0.175)  # 17.5 cm (thesis ch. 6.2.2)


@dataclass(frozen=True)
class RobotParams:
    """The differential-drive robot shared by the JAX kinematics and the pymunk world.

    Wheel commands ``c = (v_l, v_r)`` are in m/s. Before they reach the motors they are clipped to
    ``±max_wheel_speed`` (c*) and rounded to the Khepera's speed unit; each wheel then follows its
    command with a first-order lag, and its speed slips by up to ±10 %.

    The 10 % noise of thesis ch. 6.1 is Webots' ``DifferentialWheels.slipNoise`` (default 0.1): "a noise
    component of +/- 10 percent is added to the command for each simulation step ... different for each
    wheel ... uniform distribution" (Webots Reference Manual, DifferentialWheels). So each wheel's speed is
    multiplied by ``1 + σ ξ``, ``ξ ~ U(-1, 1)``, redrawn every ``noise_period`` (Webots' default
    ``basicTimeStep`` of 32 ms, of which 1.024 s and 0.128 s are 32 and 4). ``noise_period =
    target_period`` gives the harsher model of one draw per target-reaching command.

    ``wheel_gain`` is what a real robot varies in: each wheel's speed is its motor's times its gain, so a
    wheel 10 % smaller than the controller assumes is 0.9, a motor that delivers 80 % of its command 0.8.
    The controller does not know it; a learning map finds it out (docs/design.md §10).
    """

    name: str = "khepera"  # what ``--robot`` calls it; recorded in every result
    radius: float = 0.025  # body radius 25 mm (thesis ch. 6.1 and 6.2.2)
    wheel_base: float = 0.053  # distance between the wheels, 53 mm (K-Team Khepera I manual; Webots khepera)
    wheel_gain: tuple[float, float] = (1.0, 1.0)  # (left, right): a wheel's speed over its motor's (1 = as commanded)
    max_wheel_speed: float = 0.16  # c*: one 1.024 s step moves at most ~0.16 m (thesis ch. 6.1)
    speed_unit: float = 0.008  # Khepera speed commands are integers of 8 mm/s (K-Team manual); 0 = exact
    motor_tau: float = 0.02  # first-order motor lag (s): the non-linearity of Eq. 4.1's discussion
    actuator_noise: float = 0.10  # σ: wheel speeds slip by U(-σ, σ) (thesis ch. 6.1: 10 %; Webots slipNoise)
    noise_period: float = 0.032  # slip redrawn every Webots simulation step (basicTimeStep 32 ms)
    target_period: float = 1.024  # target-reaching control period (thesis ch. 6.1)
    avoid_period: float = 0.128  # obstacle-avoidance control period (thesis ch. 6.2.1)
    dt: float = 0.016  # physics sub-step: 64 per target-reaching step, 8 per avoidance step
    short_range: SensorSet = field(default=SHORT_RANGE)
    long_range: SensorSet = field(default=LONG_RANGE)
    about: str = "the thesis's Khepera: 25 mm radius, 53 mm wheel base, 0.16 m/s, 10 % slip and IR noise"

    @property
    def summary(self) -> str:
        """:attr:`about`: the one line ``ekm robots`` shows (:mod:`robots.registry`)."""
        return self.about

    @property
    def gained(self) -> bool:
        """Whether a wheel's speed differs from its motor's (``wheel_gain`` other than 1, 1)."""
        return tuple(self.wheel_gain) != (1.0, 1.0)

    def substeps(self, period: float) -> int:
        """Number of physics sub-steps in one control period (which must be a multiple of ``dt``)."""
        n = round(period / self.dt)
        if n < 1 or abs(n * self.dt - period) > 1e-9:
            raise ValueError(f"control period {period} s is not a whole number of {self.dt} s sub-steps")
        return n

    def noise_shape(self, period: float) -> tuple[int, int]:
        """Shape ``(K, 2)`` of the slip draws ξ for one control period: K = period / ``noise_period`` per wheel."""
        n, m = self.substeps(period), self.substeps(self.noise_period)
        if n % m:
            raise ValueError(f"control period {period} s is not a whole number of {self.noise_period} s noise periods")
        return (n // m, 2)

    def to_dict(self) -> dict:
        """Every parameter, for the metadata of saved maps."""
        return asdict(self)

    def physics(self) -> dict:
        """Every parameter that changes how the robot moves or senses: :meth:`to_dict` without ``name`` and
        ``about`` (two robots with the same physics are the same robot to a map)."""
        d = self.to_dict()
        del d["name"], d["about"]
        return d

    @property
    def fingerprint(self) -> str:
        """12 hex digits of the SHA-256 of :meth:`physics` as canonical JSON: which robot a result or a map was
        made on, whatever it was called."""
        import hashlib
        import json

        text = json.dumps(self.physics(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:12]

    @property
    def max_step_distance(self) -> float:
        """Furthest the centre moves in one target-reaching period at full speed (~0.16 m)."""
        return self.max_wheel_speed * self.target_period


KHEPERA = RobotParams()
