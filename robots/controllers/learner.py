"""Learning while driving: the indirect EKM that drives a controller goes on learning during the run
(thesis ch. 4.3; docs/design.md §10).

:func:`learning` wraps a controller that drives a map — command fusion, the neural fields — so that its
map is part of its state and learns, tick by tick, from what the robot did. The robot is assumed to know
its pose (the localisation that already turns the planner's checkpoints into u_p,
:class:`~robots.controllers.base.Observation`); nothing else is sensed for learning.

The map's displacements w_i are what a command held for one training period (``robot.target_period``,
1.024 s, ch. 6.1) does; the architectures command every tick (0.128 s, ch. 6.2.2). A command held for a
tick moves the robot along the first eighth of the arc the map predicts for it, so the learner extends the
motion the robot sensed over the tick to the map's period (:func:`robots.kinematics.repeated`: the same
motion again and again, each turned by the tick's heading change — what a differential drive holding its
wheel speeds does) and learns from that displacement v and the tick's command c, as it was sent (clipped to
c*, rounded to the speed unit): one step of :func:`ekm.learning.adapt` (Eq. 4.7–4.9). A tick teaches only
when its command was the one before it, within ``steady`` m/s on each wheel (the wheels were at speed, not
catching up with a new command through the motor lag), and the IR saw nothing nearer than ``clear`` m at its
start and its end (nothing touched or pushed the robot); a tick on which the runner took the wheels (the turn
of a recovery) teaches nothing. The error rule's rates follow the error beyond the robot's noise
(:func:`ekm.learning.adapt_beyond_noise`): two consecutive ticks that teach with the same command differ in
their prediction errors by the slip alone.

With rates 0 the map never changes and the run is the frozen run, bit for bit (the learner's updates are
selected away, not added as zeros).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp

from ekm.config import EKMConfig
from ekm.errors import InputError
from ekm.learning import Adaptation, Noise, Trace, adapt_beyond_noise, fresh_noise, fresh_trace
from robots.controllers.base import Controller, Observation
from robots.kinematics import quantize_command, repeated
from robots.params import RobotParams


@dataclass(frozen=True)
class LearnParams:
    """When a tick of driving teaches the map (see the module docstring) and at what rates."""

    rule: Adaptation = field(default_factory=Adaptation)
    steady: float = 0.008  # m/s: each wheel's command within this of the tick before's (one Khepera speed unit)
    clear: float = 0.02  # m: no IR reading below this at the tick's start or end (nothing touched the robot)

    def __post_init__(self):
        if not (self.steady >= 0 and self.clear >= 0):
            raise ValueError(f"steady and clear must be >= 0, got {self.steady}, {self.clear}")


class Tick(NamedTuple):
    """The last tick, as the learner remembers it: the pose it started from ``(3,)``, the command sent ``(2,)``,
    whether that command was the one before it (``steady``) and the IR saw nothing near (``clear``), its time,
    whether the command was exactly the one before it (``same``) and the tick before it taught (``taught``)."""

    pose: jax.Array
    command: jax.Array
    steady: jax.Array
    clear: jax.Array
    t: jax.Array
    same: jax.Array
    taught: jax.Array


class Learner(NamedTuple):
    """A learning controller's state: the controller's own ``inner`` state, the ``ekm`` that drives, its
    :class:`~ekm.learning.Trace`, the last :class:`Tick` and the robot's :class:`~ekm.learning.Noise`."""

    inner: Any
    ekm: Any
    trace: Trace
    last: Tick
    noise: Noise


def learning(controller: Controller, ekm, cfg: EKMConfig, params: LearnParams = LearnParams()) -> Controller:
    """``controller`` with its map ``ekm`` learning as it drives (see the module docstring).

    The controller's step must take its map as the keyword ``ekm`` (a ``functools.partial`` of a jitted step,
    as command fusion's and the neural fields' are); any other is refused with one line."""
    step = controller.step
    if not (isinstance(step, functools.partial) and "ekm" in step.keywords and not step.args):
        raise InputError(f"architecture {controller.name}: cannot learn while driving (its step does not take the "
                         f"map it drives as the keyword ekm)")
    robot = controller.robot
    arrays = {k: v for k, v in step.keywords.items() if k != "ekm" and _is_arrays(v)}
    static = tuple(sorted((k, v) for k, v in step.keywords.items() if k != "ekm" and k not in arrays))
    ticks = robot.substeps(robot.target_period) // robot.substeps(robot.avoid_period)
    run = functools.partial(learning_step, arrays=arrays, func=step.func, static=static, cfg=cfg, params=params,
                            robot=robot, ticks=ticks)
    init = functools.partial(_init, controller.init, ekm)
    return Controller(name=controller.name, spec=controller.spec, sensors=controller.sensors, init=init, step=run,
                      params=controller.params, robot=robot)


def _init(inner_init, ekm) -> Learner:
    last = Tick(jnp.zeros(3, jnp.float32), jnp.zeros(2, jnp.float32), jnp.asarray(False), jnp.asarray(False),
                jnp.asarray(-jnp.inf, jnp.float32), jnp.asarray(False), jnp.asarray(False))
    return Learner(inner_init(), ekm, fresh_trace(), last, fresh_noise())


def _is_arrays(value) -> bool:
    import numpy as np

    leaves = jax.tree.leaves(value)
    return bool(leaves) and all(isinstance(a, (jax.Array, np.ndarray)) for a in leaves)


@functools.partial(jax.jit, static_argnames=("func", "static", "cfg", "params", "robot", "ticks"))
def learning_step(state: Learner, obs: Observation, *, arrays, func, static, cfg: EKMConfig, params: LearnParams,
                  robot: RobotParams, ticks: int):
    """One tick: learn from the tick that ends here (see the module docstring), then the controller's own step
    with the map as it now is; remember this tick's pose and command."""
    last = state.last
    pose = jnp.asarray(obs.pose, jnp.float32)
    t = jnp.asarray(obs.t, jnp.float32)
    followed = jnp.abs(t - last.t - robot.avoid_period) < 0.25 * robot.avoid_period  # no tick taken by the runner
    clear = ~jnp.any(jnp.asarray(obs.ir) < params.clear)
    teaches = followed & last.steady & last.clear & clear & (not params.rule.frozen)
    v = repeated(last.pose, pose, ticks, jnp)  # the tick's motion over the map's period
    # the update before this one was the tick before, with this command: their errors differ by noise alone
    paired = last.taught & last.same
    learned, trace, noise = adapt_beyond_noise(state.ekm, v, last.command, state.trace, state.noise, paired,
                                               params.rule, cfg)
    ekm = jax.tree.map(lambda new, old: jnp.where(teaches, new, old), learned, state.ekm)
    trace = jax.tree.map(lambda new, old: jnp.where(teaches, new, old), trace, state.trace)
    noise = jax.tree.map(lambda new, old: jnp.where(teaches, new, old), noise, state.noise)

    inner, command = func(state.inner, obs, ekm=ekm, **arrays, **dict(static))

    sent = quantize_command(jnp.asarray(command, jnp.float32), robot, jnp)
    steady = followed & jnp.all(jnp.abs(sent - last.command) <= params.steady + 1e-6)
    same = followed & jnp.all(sent == last.command)
    return Learner(inner, ekm, trace, Tick(pose, sent, steady, clear, t, same, teaches), noise), command


def parse_learning(text) -> LearnParams:
    """A learning rule as the command line spells it: ``error`` or ``constant``, optionally with parameters of
    :class:`~ekm.learning.Adaptation` and :class:`LearnParams` — ``constant:eta=0.1,sigma=1``,
    ``error:eta_max=0.05,clear=0.03``; ``0`` is the rule at rate 0 (a frozen map, through the learner).
    A :class:`LearnParams` or an :class:`~ekm.learning.Adaptation` is taken as it is; ``True`` is the default rule.
    Raises :class:`InputError` naming what is wrong."""
    from dataclasses import fields as fields_of
    from dataclasses import replace

    from ekm.learning import RULES
    from robots.spelling import parse_named, parse_one, typed_params

    if isinstance(text, LearnParams):
        return text
    if isinstance(text, Adaptation):
        return LearnParams(rule=text)
    if text is True:
        return LearnParams()
    if str(text).strip() == "0":
        return LearnParams(rule=Adaptation(rule="constant", eta=0.0))
    rule_keys = {f.name for f in fields_of(Adaptation)} - {"rule"}

    def make(name: str, values: dict) -> LearnParams:
        if name not in RULES:
            from robots.spelling import did_you_mean

            raise InputError(f"learning rule {name!r}: unknown{did_you_mean(name, RULES)} (choose from "
                             f"{', '.join(RULES)}, or 0 for rate 0)")
        own_keys = [f.name for f in fields_of(LearnParams) if f.name != "rule"]
        known = [f.name for f in fields_of(Adaptation) if f.name != "rule"] + own_keys
        for key in values:
            if key not in known:
                raise InputError(f"learning rule {name}: unknown parameter {key!r} (known: {', '.join(known)})")
        ours = {k: v for k, v in values.items() if k not in rule_keys}
        rule = typed_params("learning rule", name, Adaptation, {k: v for k, v in values.items() if k in rule_keys})
        rule = replace(rule, rule=name)
        return replace(typed_params("learning rule", name, LearnParams, ours), rule=rule)

    return parse_one(str(text), "learning rule", lambda t: parse_named(t, "learning rule", RULES, make))


def spell_learning(params: LearnParams) -> str:
    """The spelling of ``params`` that :func:`parse_learning` reads back: the rule, then what differs from
    the defaults."""
    from dataclasses import replace

    from robots.spelling import spell

    rule = spell(params.rule.rule, replace(params.rule, rule=params.rule.rule), Adaptation(rule=params.rule.rule))
    rest = spell("", params, replace(LearnParams(), rule=params.rule)).lstrip(":")
    return rule + ("," if ":" in rule and rest else (":" if rest else "")) + rest
