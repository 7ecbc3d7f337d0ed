from dataclasses import dataclass, field

import jax.numpy as jnp

import ekm
from robots.controllers.base import Controller
from robots.params import KHEPERA


@dataclass(frozen=True)
class WanderParams:
    speed: float = field(default=0.08, metadata={"help": "cruising wheel speed, m/s"})
    near: float = field(default=0.04, metadata={"help": "m: an IR reading below this turns the robot away"})


def build(p, ekm_map=None, cfg=None, spec="wander", robot=KHEPERA):
    angles = jnp.asarray(robot.long_range.angles)           # the IR sensors' directions, rad (+ = left)

    def step(state, obs):
        alpha, d = obs.target[0], obs.target[1]               # the checkpoint: bearing (rad), distance (m)
        near = jnp.where(obs.ir < p.near, 1.0, 0.0)           # the sensors that see something near
        turn = jnp.clip(2.0 * alpha - 4.0 * jnp.sum(near * jnp.sin(angles)), -1.0, 1.0)
        blocked = jnp.sum(near * (jnp.cos(angles) > 0.7)) > 0   # something ahead: turn on the spot
        speed = jnp.where(blocked | (obs.final & (d < 0.004)), 0.0, p.speed * jnp.clip(d / 0.05, 0.0, 1.0))
        return state, jnp.stack([speed - 0.05 * turn, speed + 0.05 * turn])   # (left, right) wheels, m/s

    return Controller(name="wander", spec=spec, sensors=robot.long_range, init=lambda: jnp.zeros(()),
                      step=step, params=p, robot=robot)


WANDER = ekm.Architecture("wander", WanderParams, build, "wander-and-avoid: head for the checkpoint, turn away "
                          "from what is near (Brooks)")   # the entry point; in a script: ekm.register_architecture(WANDER)
