"""Throughput of online training: the jitted JAX loop against the plain NumPy reference (docs/design.md §7).

Used by ``ekm bench`` (a quick check) and ``benchmarks/perf/bench_training.py`` (the full study). Times are
wall-clock seconds of already-compiled code; compilation is timed separately.
"""

from __future__ import annotations

import time

import jax
import numpy as np

from ekm.config import EKMConfig
from training import reference
from training.online import TrainConfig, draw_noise, start
from training.run import chunk, trial_layout


def jax_trial_steps_per_s(cfg: EKMConfig, *, trials: int = 5, steps: int = 5000, repeats: int = 5,
                          devices=None) -> dict:
    """Trial-steps per second of ``train_chunk`` (one ``lax.scan`` of ``steps``, ``vmap`` over ``trials``),
    with the trials spread over ``devices`` (default: every JAX device present) as :func:`training.run.train`
    spreads them (:func:`training.run.trial_layout`; a padding trial is not counted). The best of
    ``repeats`` chunks, and their median: a chunk's time varies from one to the next, so one chunk is not
    a measurement."""
    tcfg = TrainConfig(steps=100_000, trials=trials)
    padded, sharding = trial_layout(trials, devices)
    keys = jax.random.split(jax.random.PRNGKey(0), padded)
    s = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    if sharding is not None:
        s, keys = jax.device_put((s, keys), sharding)
    t0 = time.perf_counter()
    jax.block_until_ready(chunk(s, keys, 0.0, length=steps, cfg=cfg, tcfg=tcfg, sharding=sharding))
    compile_s = time.perf_counter() - t0
    times = []
    for r in range(repeats):
        t0 = time.perf_counter()
        s = jax.block_until_ready(chunk(s, keys, float(r * steps), length=steps, cfg=cfg, tcfg=tcfg,
                                             sharding=sharding))
        times.append(time.perf_counter() - t0)
    return {"trial_steps_per_s": trials * steps / min(times),
            "median_trial_steps_per_s": trials * steps / float(np.median(times)), "first_call_s": compile_s,
            "devices": 1 if sharding is None else len(sharding.device_set)}


def numpy_trial_steps_per_s(cfg: EKMConfig, *, steps: int = 200) -> float:
    """Trial-steps per second of :func:`training.reference.train_step` (one trial, float64)."""
    tcfg = TrainConfig(steps=100_000, trials=1)
    s = start(jax.random.PRNGKey(0), cfg, tcfg)
    state = [np.asarray(a, float) for a in (s.ekm.w, s.ekm[1], s.robot.pose, s.robot.wheels, s.target)] + [0]
    draws = [np.asarray(d, float) for d in draw_noise(jax.random.PRNGKey(0), steps)]
    t0 = time.perf_counter()
    for t in range(steps):
        state = list(reference.train_step(cfg.mapping, *state, tuple(d[t] for d in draws), float(t), cfg, tcfg))
    return steps / (time.perf_counter() - t0)


def quick(mapping: str = "indirect") -> dict:
    """The ``ekm bench`` numbers: JAX vs NumPy trial-steps/s for the 15×15 map and 5 trials."""
    cfg = EKMConfig(mapping=mapping)
    j = jax_trial_steps_per_s(cfg)
    n = numpy_trial_steps_per_s(cfg)
    return {"mapping": mapping, "neurons": cfg.neurons, "trials": 5,
            "jax_trial_steps_per_s": round(j["trial_steps_per_s"], 1),
            "jax_median_trial_steps_per_s": round(j["median_trial_steps_per_s"], 1), "numpy_trial_steps_per_s": round(n, 1),
            "ratio": round(j["trial_steps_per_s"] / n, 1), "jax_first_call_s": round(j["first_call_s"], 2),
            "protocol_estimate_s": round(5 * 100_000 / j["trial_steps_per_s"], 1),
            "jax_version": jax.__version__, "devices": [str(d) for d in jax.devices()], "devices_used": j["devices"]}
