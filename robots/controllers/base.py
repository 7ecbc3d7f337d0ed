"""What every controller sees and how it is called: the observation, the controller, the IR helpers.

A controller (docs/design.md §5) is a pure ``step(state, obs) -> (state, command)`` over pytrees,
jitted once and reused by every run with the same parameters; the scenario runner
(:mod:`evaluation.scenario`) is the imperative shell around it. The runner ticks at the base period (0.128 s, the obstacle-avoidance
period of ch. 6.2) and hands each controller the same :class:`Observation`; a controller with slower
modules (command fusion's 1.024 s target reaching, ch. 6.2.1) keeps its own clock in its state. The
runner never asks which architecture it runs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import Any, Callable, NamedTuple

import jax.numpy as jnp
import numpy as np

from robots.params import KHEPERA, RobotParams, SensorSet


class Observation(NamedTuple):
    """One tick's input to a controller (all arrays; shapes fixed for a run, so one compilation serves it).

    ``t``: time (s). ``ir``: ``(m,)`` IR readings from the body surface (m; ``inf`` = nothing within range,
    :func:`robots.sensors.ir_readings`). ``target``: ``(2,)`` the current checkpoint as u_p = (α, d) from
    the robot (ch. 4.1). ``target_id``: int, changes whenever the checkpoint does (reached, or replanned,
    Fig. 6.5), so modules can react at once. ``final``: the checkpoint is the goal. ``pose``: ``(3,)`` the
    robot's pose (x, y, θ) in the world — the localisation that turns the planner's checkpoints into u_p;
    controllers that remember obstacles carry them with it. ``target_velocity``: ``(2,)`` world-frame
    velocity of the checkpoint (non-zero only for a moving goal). ``markers``: ``(k, 5)`` the world's
    declared moving objects, rows (x, y, vx, vy, radius) in the world frame (Samba's object markers).
    """

    t: Any
    ir: Any
    target: Any
    target_id: Any
    final: Any
    pose: Any
    target_velocity: Any
    markers: Any


@dataclass(frozen=True)
class Controller:
    """A ready-to-run architecture: its sensors, a fresh state and the jitted step.

    ``init()`` returns the initial state pytree (each architecture caches its own: JAX arrays cannot change,
    so every run may start from the same ones instead of building them again); ``step(state, obs)``
    returns ``(state, command)`` with ``command`` ``(2,)`` wheel speeds (m/s; the motors clip and round
    them, :mod:`robots.kinematics`).
    ``spec`` is the architecture with every parameter resolved (what ``ekm run --json`` reports);
    ``describe(state)`` optionally returns named arrays for plots (e.g. the neural fields of one tick).
    """

    name: str
    spec: str
    sensors: SensorSet
    init: Callable[[], Any]
    step: Callable[[Any, Observation], tuple[Any, Any]]
    params: Any = None
    robot: RobotParams = KHEPERA


def ring(robot: RobotParams, which: str) -> SensorSet:
    """The robot's IR ring named by an architecture's ``sensors`` parameter: ``"short"`` or ``"long"``."""
    return robot.short_range if which == "short" else robot.long_range


def on_ring(name: str, spec: str, params, init, step, robot: RobotParams) -> Controller:
    """The :class:`Controller` of an architecture whose jitted ``step(state, obs, angles, *, p, robot)`` reads
    the IR ring ``params.sensors`` (its directions passed as ``angles``) and whose ``init(params)`` gives
    the fresh state — the motor schemas and the discrete architectures."""
    sensors = ring(robot, params.sensors)
    run = partial(step, angles=jnp.asarray(sensor_angles(sensors)), p=params, robot=robot)
    return Controller(name=name, spec=spec, sensors=sensors, init=partial(init, params), step=run, params=params,
                      robot=robot)


def proximity(readings, sensors: SensorSet, xp=jnp):
    """u_o of Eq. 4.10: each sensor's activation in [0, 1] — 0 when nothing is within range, rising
    linearly to 1 at contact (``1 - reading / range``), as a Khepera IR value rises when an obstacle nears."""
    r = xp.asarray(readings)
    return xp.where(xp.isfinite(r), 1.0 - xp.clip(r, 0.0, sensors.range_m) / sensors.range_m, 0.0)


def beyond_the_goal(gaps, target, final):
    """Which obstacles lie beyond the goal (bool, the shape of ``gaps``): when the checkpoint is the goal
    (``final``), those no nearer than it — ``gaps`` (m from the body surface: IR readings, remembered points;
    ``inf`` = nothing) at least its distance d of u_p = ``target``. An obstacle beyond the goal cannot stand in the
    way to it; a goal set beside a wall (the back of a niche, a corridor's end) would otherwise hold a reactive
    avoidance off it, where the push balances the pull. The rule the extended neural fields apply to their
    remembered obstacles (:mod:`robots.controllers.fields`), here at the goal only: a checkpoint on the way is
    passed, not stopped at, and what lies beyond it is the way on."""
    return jnp.asarray(final) & (jnp.asarray(gaps) >= jnp.asarray(target)[1])


#: The ``avoid`` choices of the reactive architectures: ``all`` as the books avoid, ``nearer`` nothing beyond the goal.
AVOID = ("all", "nearer")


def avoid_option(help: str):
    """The ``avoid`` parameter of a reactive architecture's parameters (a dataclass field): one of :data:`AVOID`,
    ``nearer`` by default (:func:`beyond_the_goal`); ``help`` says what it avoids."""
    return field(default="nearer", metadata={"help": help, "choices": AVOID})


def readings_to_the_goal(obs: Observation):
    """The IR readings ``(m,)`` of ``obs`` with those beyond the goal (:func:`beyond_the_goal`) read as nothing
    (``inf``): what a reactive avoidance answers with ``avoid=nearer``."""
    return jnp.where(beyond_the_goal(obs.ir, obs.target, obs.final), jnp.inf, obs.ir)


def sensor_angles(sensors: SensorSet) -> np.ndarray:
    """The sensors' directions ``(m,)`` (rad, robot frame, + = left) as an array."""
    return np.asarray(sensors.angles, dtype=np.float32)


def hit_points(pose, readings, angles, radius: float = KHEPERA.radius, xp=np):
    """World positions ``(..., m, 2)`` of what each sensor (directions ``angles``, robot frame) sees — centre +
    (radius + reading) along its ray — and a mask ``(..., m)`` of the sensors that see something, for poses
    ``(..., 3)`` and their ``readings`` ``(..., m)``."""
    r = xp.asarray(readings)
    seen = xp.isfinite(r)
    phi = pose[..., 2:3] + xp.asarray(angles)
    reach = radius + xp.where(seen, r, 0.0)
    pts = xp.stack([pose[..., 0:1] + reach * xp.cos(phi), pose[..., 1:2] + reach * xp.sin(phi)], axis=-1)
    return pts, seen


def velocity_to_wheels(direction, speed, robot: RobotParams = KHEPERA, turn_gain: float = 4.0):
    """Wheel speeds ``(2,)`` that carry the differential-drive robot along a desired velocity (``direction``
    rad in the robot frame, + = left; ``speed`` m/s) — how Samba's and the motor schemas' holonomic velocity
    commands reach a nonholonomic robot.

    The robot turns towards the direction at ``turn_gain`` × the heading error (rad/s) while driving
    forward at the velocity's component along its heading, ``speed · cos(direction)``, and not at all
    when that is negative: it cannot move sideways, so it turns on the spot first (a half turn takes
    about 0.5 s at full wheel speed). When a wheel would exceed c*, both are scaled down together, so the
    turn keeps its share. What a holonomic robot (Riekki's soccer players) does at once — step sideways,
    back away while facing the obstacle — this robot does by turning first.
    """
    direction = jnp.asarray(direction)
    v = jnp.asarray(speed) * jnp.maximum(jnp.cos(direction), 0.0)
    omega = turn_gain * direction
    wheels = jnp.stack([v - 0.5 * robot.wheel_base * omega, v + 0.5 * robot.wheel_base * omega])
    peak = jnp.max(jnp.abs(wheels))
    return wheels * jnp.minimum(1.0, robot.max_wheel_speed / jnp.maximum(peak, 1e-12))
