from dataclasses import dataclass, field

import jax.numpy as jnp

import ekm
from ekm.angles import wrap
from robots.controllers.base import Controller
from robots.params import KHEPERA


@dataclass(frozen=True)
class ChaserParams:
    speed: float = field(default=0.12, metadata={"help": "wheel speed when facing the ball, m/s"})
    gain: float = field(default=2.0, metadata={"help": "turn per rad off the ball, 1/s"})


def build(p, field=None, robot=KHEPERA, spec="chaser"):
    def step(state, play):                  # play: the game turned so that the player attacks x = length
        x, y, theta = play.pose[0], play.pose[1], play.pose[2]
        off = wrap(jnp.arctan2(play.ball[1] - y, play.ball[0] - x) - theta)   # the ball's bearing, rad
        turn = 0.5 * robot.wheel_base * jnp.clip(p.gain * off, -2.0, 2.0)      # m/s either way
        ahead = p.speed * jnp.maximum(jnp.cos(off), 0.0)                      # slow while facing away
        wheels = jnp.stack([ahead - turn, ahead + turn])
        return state, jnp.clip(wheels, -robot.max_wheel_speed, robot.max_wheel_speed)

    return Controller(name="chaser", spec=spec, sensors=robot.long_range, init=lambda: jnp.zeros(()),
                      step=step, params=p, robot=robot)


CHASER = ekm.Player("chaser", ChaserParams, build, "runs at the ball wherever it is (an example package)")
