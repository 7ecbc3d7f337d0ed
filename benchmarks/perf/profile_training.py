"""Where one online training step's time goes (docs/design.md §7): timing ablations of ``training.online.train_step``.

Run from the repository root (about a minute on 2 cores)::

    python benchmarks/perf/profile_training.py                      # markdown table, indirect, 15×15, 5 trials
    python benchmarks/perf/profile_training.py --mapping direct
    XLA_FLAGS=--xla_force_host_platform_device_count=2 python benchmarks/perf/profile_training.py   # (one device is used)

Each row is one jitted ``lax.scan`` of ``--steps`` steps, ``vmap``-ed over ``--trials`` trials, exactly as
:func:`training.online.train_chunk` runs it (noise drawn up front inside the jitted call), with the step
cut down to some of its pieces. A piece's cost is the difference between two rows; the rows are built so
that XLA cannot drop what is kept (every piece's output feeds the carry). Pieces:

- *noise*: :func:`training.online.draw_noise` for the chunk (slip ξ 64×2 per step — 16 draws of 32 ms ×
  2 wheels —, exploration, target draws);
- *control*: u_p (egocentric), the winner search for u_p (Eq. 4.2–4.4, nearest first:
  :func:`ekm.kohonen.winner`) and Eq. 4.5;
- *kinematics*: quantise, 64 sub-steps of motor lag, slip and Euler integration (closed form, cumsums;
  the new pose only, :func:`robots.kinematics.advance_pose`);
- *learn winner*: the winner search for the displacement v;
- *neighbourhood*: G(k, i) over the N² lattice (Eq. 4.7);
- *update*: Δw (Eq. 4.7) and ΔM (Eq. 4.9) over all neurons;
- *schedules*: η, σ and the exploration std at step t.

Times are the best of ``--repeat`` calls of already-compiled code; µs per trial-step = wall / (steps ×
trials). The header prints the 1-minute load average (other work on the machine shows there).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

from ekm import maps
from ekm.config import EKMConfig
from ekm import indirect
from ekm.kohonen import neighbourhood, winner
from robots.kinematics import advance_pose, egocentric, quantize_command
from robots.params import KHEPERA
from training.online import TrainConfig, Trainee, draw_noise, start, train_chunk


def variant_step(s: Trainee, draws, t, cfg, tcfg, params, parts: frozenset):
    """``train_step`` with only ``parts`` computed; the rest replaced by cheap stand-ins that keep the
    data flow (so XLA keeps what is computed)."""
    xi_act, xi_explore, target_draw = draws
    sch = tcfg.schedules
    n = params.substeps(params.target_period)
    if "schedules" in parts:
        eta, sigma, explore = sch.eta(t, tcfg.steps), sch.sigma(t, tcfg.steps), sch.explore(t, tcfg.steps)
    else:
        eta, sigma, explore = jnp.float32(0.05), jnp.float32(1.0), jnp.float32(0.2)
    u = egocentric(s.robot.pose, s.target, jnp)
    if "control" in parts:
        c_p, _ = maps.control(s.ekm, u, cfg)
    else:
        c_p = 0.01 * u  # keeps u (and the pose) live
    c_sent = quantize_command(c_p + explore * cfg.c_max * xi_explore, params, jnp)
    if "kinematics" in parts:
        robot = advance_pose(s.robot, c_sent, xi_act, n, params, jnp)
    else:
        robot = s.robot._replace(pose=s.robot.pose + jnp.concatenate([0.001 * c_sent, xi_act[0, :1]]))
    v = egocentric(s.robot.pose, robot.pose[:2], jnp)
    ekm = s.ekm
    if "learn winner" in parts:
        k = winner(ekm.w, v, cfg)
    else:
        k = jnp.asarray(v[0] * 10, jnp.int32) % cfg.size
    if "neighbourhood" in parts:
        g = neighbourhood(cfg, k, sigma)
    else:
        g = jnp.zeros(cfg.size, jnp.float32).at[k].set(sigma)
    if "update" in parts:
        if cfg.mapping == "indirect":
            ekm = indirect.learn(ekm, v, c_p, eta, g, cfg)
        else:
            ekm = maps.update(ekm, v, c_sent, eta, sigma, cfg) if "neighbourhood" in parts else \
                jax.tree.map(lambda a: a + eta * g.sum() * 1e-9, ekm)
    else:
        ekm = jax.tree.map(lambda a: a.at[0].add(eta * g[0] * v[0]), ekm)
    done = s.age + 1 >= tcfg.patience
    tcfg_lo = jnp.asarray([tcfg.margin] * 2, jnp.float32)
    target = jnp.where(done, tcfg_lo + target_draw * 0.8, s.target)
    return Trainee(ekm, robot, target, jnp.where(done, 0, s.age + 1))


@partial(jax.jit, static_argnames=("length", "cfg", "tcfg", "parts"))
def variant_chunk(trainees, keys, t0, *, length, cfg, tcfg, parts):
    params = KHEPERA

    def one_trial(s, key):
        if "noise" in parts:
            draws = draw_noise(key, length, params)
        else:
            k = jax.random.uniform(key, (1,))[0]
            draws = (jnp.full((length,) + params.noise_shape(params.target_period), 0.1) * k,
                     jnp.full((length, 2), 0.3) * k, jnp.full((length, 2), 0.5) * k)

        def body(s, x):
            draw, t = x
            return variant_step(s, draw, t, cfg, tcfg, params, parts), None

        ts = t0 + jnp.arange(length, dtype=jnp.float32)
        return jax.lax.scan(body, s, (draws, ts))[0]

    return jax.vmap(one_trial)(trainees, keys)


ALL = ("noise", "schedules", "control", "kinematics", "learn winner", "neighbourhood", "update")


def best_time(fn, repeat: int) -> float:
    jax.block_until_ready(fn())  # compile
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mapping", default="indirect", choices=("direct", "indirect"))
    ap.add_argument("--neurons", type=int, default=15)
    ap.add_argument("--trials", type=int, default=5)
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    cfg, tcfg = EKMConfig(mapping=args.mapping, neurons=args.neurons), TrainConfig(trials=args.trials)
    keys = jax.random.split(jax.random.PRNGKey(0), args.trials)
    s0 = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    ts = args.steps * args.trials
    load = os.getloadavg()[0]

    def us(fn):
        return 1e6 * best_time(fn, args.repeat) / ts

    full = us(lambda: train_chunk(s0, keys, 0.0, length=args.steps, cfg=cfg, tcfg=tcfg))
    # Cumulative: start from nothing, add one piece at a time.
    have: list[str] = []
    cum = [("none of the pieces (scan, vmap, carry, targets)",
            us(lambda: variant_chunk(s0, keys, 0.0, length=args.steps, cfg=cfg, tcfg=tcfg, parts=frozenset())))]
    for p in ALL:
        have.append(p)
        parts = frozenset(have)
        cum.append((f"+ {p}", us(lambda parts=parts: variant_chunk(s0, keys, 0.0, length=args.steps, cfg=cfg,
                                                                     tcfg=tcfg, parts=parts))))
    # Leave-one-out from the full variant.
    loo = []
    for p in ALL:
        parts = frozenset(ALL) - {p}
        loo.append((p, us(lambda parts=parts: variant_chunk(s0, keys, 0.0, length=args.steps, cfg=cfg, tcfg=tcfg,
                                                               parts=parts))))
    every = cum[-1][1]
    print(f"jax {jax.__version__} on {jax.devices()}; {cfg.mapping}, {cfg.neurons}×{cfg.neurons}, {args.trials} trials, "
          f"{args.steps} steps per call, best of {args.repeat}; 1-min load average {load:.1f} before, "
          f"{os.getloadavg()[0]:.1f} after ({os.cpu_count()} cores)\n")
    print(f"shipped train_chunk: {full:.2f} µs per trial-step = {1e6 / full:,.0f} trial-steps/s\n")
    print("| cumulative: pieces computed | µs per trial-step | added by the piece |")
    print("|---|---:|---:|")
    prev = None
    for name, t in cum:
        print(f"| {name} | {t:.2f} | {'' if prev is None else f'{t - prev:+.2f}'} |")
        prev = t
    print("\n| leave one out (every piece but) | µs per trial-step | saved = cost of the piece | share of the step |")
    print("|---|---:|---:|---:|")
    for name, t in loo:
        print(f"| {name} | {t:.2f} | {every - t:.2f} | {100 * (every - t) / every:.0f} % |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
