"""The training driver: trials, chunks, progress, the periodic ch. 6.1 test and checkpoints (imperative shell).

:func:`train` runs ``tcfg.steps`` steps for ``tcfg.trials`` independent trials, in jitted chunks
(``training.online.train_chunk``), and after every ``eval_every`` steps calls ``on_eval(step, maps)``
— the ch. 6.1 test in practice — so a caller can record the learning curve, then
``on_checkpoint(step, trainees, key_run)`` so it can save a :mod:`training.checkpoint`. Trials get
independent PRNG keys split from one ``seed``: the same seed gives the same maps. A run resumed from
a checkpoint (``resume=(step, trainees, key_run)``) continues exactly as the uninterrupted run: each
chunk's noise comes from ``fold_in(key_run, step)`` and the chunks after an evaluation are the same.
"""

from __future__ import annotations

from functools import partial

import jax

from ekm import interrupts
from ekm.config import EKMConfig
from robots.params import KHEPERA, RobotParams
from training.online import TrainConfig, start, train_chunk

#: Longest chunk of one jitted scan; shorter chunks only cost more dispatches, longer ones hold the
#: progress bar still.
MAX_CHUNK = 5000


def fresh(cfg: EKMConfig, tcfg: TrainConfig, seed: int, init=None):
    """The carry of every trial at step 0 and the run's key: ``(trainees, key_run)``. The maps are untrained, or
    ``init`` (stacked maps, one per trial) to go on training."""
    key_init, key_run = jax.random.split(jax.random.PRNGKey(seed))
    keys = jax.random.split(key_init, tcfg.trials)
    if init is None:
        return jax.vmap(lambda k: start(k, cfg, tcfg))(keys), key_run
    return jax.vmap(lambda k, m: start(k, cfg, tcfg, m))(keys, init), key_run


def trial_layout(trials: int, devices=None):
    """How to spread ``trials`` over the JAX devices present: ``(padded, sharding)``.

    The trials are independent (``vmap``), so each device trains its own share and nothing is exchanged;
    a multi-GPU host, or ``XLA_FLAGS=--xla_force_host_platform_device_count=K`` (``JAX_NUM_CPU_DEVICES=K``)
    on a CPU, shares the work. The fewest devices that give the smallest share are used; when they do
    not divide ``trials``, the trial axis is padded to ``padded`` (a multiple of them) with copies of
    the last trial, whose results are dropped — 5 trials on 2 devices run as 3 + 3. ``sharding`` is a
    :class:`jax.sharding.NamedSharding` splitting axis 0 over those devices, or None when that is one
    device (then ``padded == trials``).
    """
    devices = list(jax.devices() if devices is None else devices)
    share = min(-(-trials // d) for d in range(1, len(devices) + 1))
    used = min(d for d in range(1, len(devices) + 1) if -(-trials // d) == share)
    if used == 1:
        return trials, None
    from jax.sharding import Mesh, NamedSharding, PartitionSpec

    import numpy as np

    return share * used, NamedSharding(Mesh(np.asarray(devices[:used]), ("trials",)), PartitionSpec("trials"))


def trial_sharding(trials: int, devices=None):
    """The sharding of :func:`trial_layout` (None: one device)."""
    return trial_layout(trials, devices)[1]


def chunk(trainees, keys, t0, *, length: int, cfg: EKMConfig, tcfg: TrainConfig, sharding=None,
          params: RobotParams = KHEPERA):
    """:func:`training.online.train_chunk` on the trial layout of ``sharding`` (:func:`trial_layout`; None:
    one device). Each device runs ``train_chunk`` on its own trials (``shard_map``): left to sharding
    propagation, XLA gathered every trial onto both devices for the winner search's ``top_k`` at every step.
    """
    if sharding is None:
        return train_chunk(trainees, keys, t0, length=length, cfg=cfg, tcfg=tcfg, params=params)
    return _sharded_chunk(trainees, keys, t0, length=length, cfg=cfg, tcfg=tcfg, params=params, mesh=sharding.mesh)


@partial(jax.jit, static_argnames=("length", "cfg", "tcfg", "params", "mesh"))
def _sharded_chunk(trainees, keys, t0, *, length, cfg, tcfg, params, mesh):
    from jax.sharding import PartitionSpec

    local = partial(train_chunk, length=length, cfg=cfg, tcfg=tcfg, params=params)
    trials = PartitionSpec(mesh.axis_names[0])
    return jax.shard_map(local, mesh=mesh, in_specs=(trials, trials, PartitionSpec()), out_specs=trials)(
        trainees, keys, t0)


def _pad(tree, padded: int):
    """``tree`` with its leading (trial) axis padded to ``padded`` by repeating the last entry."""
    def pad(a):
        extra = padded - a.shape[0]
        return a if extra == 0 else jax.numpy.concatenate([a, jax.numpy.repeat(a[-1:], extra, axis=0)])
    return jax.tree.map(pad, tree)


def _unpad(tree, trials: int, device=None):
    """The first ``trials`` entries of ``tree``'s leading axis; on ``device`` when given (so that what the
    callbacks compute runs on one device exactly as without sharding)."""
    tree = jax.tree.map(lambda a: a if a.shape[0] == trials else a[:trials], tree)
    return tree if device is None else jax.device_put(tree, device)


def train(cfg: EKMConfig, tcfg: TrainConfig, *, seed: int = 0, eval_every: int | None = None, on_eval=None,
          on_checkpoint=None, resume=None, progress: bool = False, params: RobotParams = KHEPERA, init=None,
          until: int | None = None):
    """Train ``tcfg.trials`` maps online on the robot ``params``; returns the stacked maps (leading trial axis).
    ``init``: stacked maps to go on training from (``ekm train --init``), one per trial; None: from scratch.
    ``until``: stop after this many steps of the ``tcfg.steps``-step run (its schedules unchanged): the maps of
    an early step of a long run, as the adaptation experiment needs them.

    ``on_eval(step, maps)`` is called at step 0, after every ``eval_every`` steps and at the end, each
    time followed by ``on_checkpoint(step, trainees, key_run)`` (not at step 0). ``resume``:
    ``(step, trainees, key_run)`` of a checkpoint taken after an evaluation; training continues from
    there and step 0 is not evaluated again.
    """
    trainees, key_run = fresh(cfg, tcfg, seed, init)
    done = 0
    if resume is not None:
        done, trainees, key_run = resume
    padded, sharding = trial_layout(tcfg.trials)
    one = None if sharding is None else jax.devices()[0]  # where the callbacks see the maps
    if sharding is not None:
        trainees = jax.device_put(_pad(trainees, padded), sharding)
    every = eval_every or tcfg.steps
    last = tcfg.steps if until is None else min(until, tcfg.steps)
    bar = None
    if progress:
        from tqdm import tqdm

        verb = "training" if tcfg.adapt is None else "fine-tuning"
        bar = tqdm(total=last, initial=done, unit="step", desc=f"{verb} {cfg.mapping} ({tcfg.trials} trials)",
                   dynamic_ncols=True)
    if on_eval and done == 0:
        on_eval(0, _unpad(trainees.ekm, tcfg.trials, one))
    while done < last:
        target = min(last, (done // every + 1) * every)
        while done < target:
            length = min(MAX_CHUNK, target - done)
            keys = jax.random.split(jax.random.fold_in(key_run, done), tcfg.trials)
            if sharding is not None:
                keys = jax.device_put(_pad(keys, padded), sharding)
            trainees = chunk(trainees, keys, float(done), length=length, cfg=cfg, tcfg=tcfg, sharding=sharding,
                             params=params)
            done += length
            interrupts.check()  # a Ctrl-C lost in a JAX callback stops training here
            if bar is not None:
                jax.block_until_ready(trainees)
                bar.update(length)
        if on_eval:
            on_eval(done, _unpad(trainees.ekm, tcfg.trials, one))
        if on_checkpoint:
            on_checkpoint(done, _unpad(trainees, tcfg.trials, one), key_run)
    if bar is not None:
        bar.close()
    return _unpad(trainees.ekm, tcfg.trials)
