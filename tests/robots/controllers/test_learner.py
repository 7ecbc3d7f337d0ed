"""Learning while driving (robots.controllers.learner): rate 0 is the frozen run bit for bit, which ticks teach,
and a learning map changes."""

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ekm.data import load_default_map
from ekm.errors import InputError
from ekm.learning import Adaptation
from robots.controllers.base import Controller, Observation
from robots.controllers.learner import LearnParams, learning, parse_learning, spell_learning
from robots.params import KHEPERA

RATE_0 = LearnParams(rule=Adaptation(rule="constant", eta=0.0))


@pytest.mark.parametrize("architecture, world", [("fields", "three-rooms-static"), ("fusion", "three-rooms")])
def test_at_rate_0_a_learning_run_is_the_frozen_run_bit_for_bit(architecture, world):
    from evaluation.scenario import run_architecture
    from robots.controllers.spec import parse_architecture
    from robots.worldnames import load_world

    w, spec = load_world(world), parse_architecture(architecture)
    frozen = run_architecture(w, spec, seed=3)
    learned = run_architecture(w, spec, seed=3, learn=RATE_0)
    np.testing.assert_array_equal(learned.poses, frozen.poses)
    assert learned.commands == frozen.commands and frozen.reached
    assert learned.updates == 0 and frozen.updates is None


def test_with_a_rate_the_map_learns_and_can_drive_a_later_run():
    import ekm

    out = ekm.run("open-arena", "fields", seed=1, robot="weak-motor", learn="constant:eta=0.1,sigma=1")
    assert out.updates > 10 and out.to_dict()["learn"] == "constant:eta=0.1,sigma=1"
    learned = out.learned
    shipped = load_default_map("signed")
    assert learned.trials == 1 and not np.array_equal(np.asarray(learned.ekm.M[0]), np.asarray(shipped.ekm.M[1]))
    assert learned.meta["robot"]["name"] == "weak-motor" and learned.meta["learned"][0]["updates"] == out.updates
    again = ekm.run("open-arena", "fields", seed=1, robot="weak-motor", maps=learned[0])
    assert again.map_robot == "weak-motor"


@partial(jax.jit, static_argnames=())
def _constant(state, obs, *, ekm, c):
    return state, c


def _ticks(learner, poses, irs, times, command):
    state = learner.init()
    for pose, ir, t in zip(poses, irs, times):
        obs = Observation(t=np.float32(t), ir=np.asarray(ir, np.float32), target=np.zeros(2, np.float32),
                          target_id=np.int32(0), final=np.bool_(False), pose=np.asarray(pose, np.float32),
                          target_velocity=np.zeros(2, np.float32), markers=np.zeros((0, 5), np.float32))
        state, _ = learner.step(state, obs)
    return state


def test_a_tick_teaches_when_its_command_was_the_one_before_and_nothing_was_near():
    """Ten ticks of one command: the first is sent after the zero command of the start and does not teach; the
    second is the first steady one, learned from at the third tick — 8 updates. An IR reading of 1 cm at tick 5
    spoils the tick that ends there and the one that starts there (6); a tick the runner took (a gap in time
    between ticks 7 and 8) spoils the tick that ends at 8 and, its command not known to follow another, the next."""
    maps = load_default_map("signed")
    ekm = jax.tree.map(lambda a: a[0], maps.ekm)
    c = jnp.asarray([0.08, 0.08], jnp.float32)
    inner = Controller(name="stub", spec="stub", sensors=KHEPERA.long_range, init=lambda: jnp.zeros(()),
                       step=partial(_constant, ekm=ekm, c=c), robot=KHEPERA)
    learner = learning(inner, ekm, maps.cfg, LearnParams(rule=Adaptation(rule="constant", eta=0.01)))
    poses = [(0.2 + 0.01024 * i, 0.5, 0.0) for i in range(10)]
    clear = [np.full(12, np.inf)] * 10
    times = [0.128 * i for i in range(10)]
    assert int(_ticks(learner, poses, clear, times, c).trace.updates) == 8
    near = list(clear)
    near[5] = np.where(np.arange(12) == 3, 0.01, np.inf)
    assert int(_ticks(learner, poses, near, times, c).trace.updates) == 6
    gap = times[:8] + [t + 0.128 for t in times[8:]]
    assert int(_ticks(learner, poses, clear, gap, c).trace.updates) == 6


def test_only_a_controller_that_takes_its_map_can_learn_and_rules_are_spelt_back():
    plain = Controller(name="plain", spec="plain", sensors=KHEPERA.long_range, init=lambda: 0,
                       step=lambda s, o: (s, jnp.zeros(2)), robot=KHEPERA)
    with pytest.raises(InputError, match="architecture plain: cannot learn while driving"):
        learning(plain, None, load_default_map("signed").cfg)
    for text in ("error", "constant:eta=0.1,sigma=1", "error:eta_max=0.05,clear=0.03", "0"):
        assert parse_learning(spell_learning(parse_learning(text))) == parse_learning(text)
    with pytest.raises(InputError, match="learning rule constant: unknown parameter 'zz' \\(known: eta, sigma"):
        parse_learning("constant:zz=1")
