"""Where one controller step's time goes, kernel by kernel: XLA's own trace of the step as the runner calls it.

Run from the repository root (about 20 s)::

    python benchmarks/perf/profile_step.py                                   # fields on three-rooms-static
    python benchmarks/perf/profile_step.py --architecture samba --world concave-obstacle --top 20
    python benchmarks/perf/profile_step.py --training indirect        # one training step (5 trials), in its scan

Drives one run of the architecture's shipped map (seed 0) to record its observations, takes the state and
observation two thirds of the way through, and calls the step the way :func:`evaluation.scenario.run_scenario`
calls it (``_in_one_loop``) ``--calls`` times under ``jax.profiler`` with XLA's per-kernel trace events on
(``--xla_cpu_enable_xprof_traceme``). Prints, per call, the time of each named event: JAX's dispatch
(``PjitFunction``, ``DevicePut`` of the observation's arrays, ``ParseArguments``), XLA's executor
(``ThunkExecutor::Execute``) and every fused kernel of the step by its HLO name. Tracing slows everything
down, so read the rows against each other, not as wall time. ``--hlo`` also prints the operation each of
the top kernels comes from (the ``op_name`` of its HLO instruction), to find it in the code.

``--training MAPPING`` traces ``training.online.train_chunk`` instead (15×15 map, 5 trials, one chunk of
``--calls`` steps) and prints µs per training step: the kernels of the scan's body, each once a step.

This is how the reductions over trailing axes of length 2 (``ynn_fusion`` kernels) and the sines and
cosines recomputed inside a (points × rays) loop were found (``docs/speed.md``).
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import functools
import glob
import gzip
import json
import os
import re
import sys
import tempfile

os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " --xla_cpu_enable_xprof_traceme=true").strip()

import jax  # noqa: E402
import numpy as np  # noqa: E402

import evaluation.scenario as scenario  # noqa: E402
from ekm.data import load_default_map  # noqa: E402
from robots.controllers.spec import parse_architectures  # noqa: E402
from robots.worldnames import load_world  # noqa: E402


def recorded(spec, world, seed: int = 0):
    """The controller and the (state, observation) of every tick of one run."""
    if spec.uses_map:
        maps = load_default_map(spec.default_chart)
        ctl = spec.build(jax.tree.map(lambda a: a[0], maps.ekm), maps.cfg)
    else:
        ctl = spec.build()
    ticks = []

    def step(state, obs):
        ticks.append((state, obs))
        return ctl.step(state, obs)

    scenario.run_scenario(world, dataclasses.replace(ctl, step=step), seed=seed)
    return ctl, ticks


def kernel_times(call, calls: int) -> tuple[collections.Counter, collections.Counter]:
    """Total µs and count of every trace event over ``calls`` calls of ``call()``."""
    for _ in range(20):
        call()
    with tempfile.TemporaryDirectory() as where:
        jax.profiler.start_trace(where, create_perfetto_trace=True)
        for _ in range(calls):
            call()
        jax.profiler.stop_trace()
        trace = sorted(glob.glob(f"{where}/**/*.trace.json.gz", recursive=True))[-1]
        events = json.load(gzip.open(trace))["traceEvents"]
    total, count = collections.Counter(), collections.Counter()
    for e in events:
        if e.get("ph") == "X":
            total[e["name"]] += e["dur"]
            count[e["name"]] += 1
    return total, count


def profile_training(mapping: str, steps: int, top: int, show_hlo: bool = False) -> int:
    """Print µs per step of one traced chunk of ``steps`` training steps (5 trials, ``vmap``)."""
    from ekm.config import EKMConfig
    from training.online import TrainConfig, start, train_chunk

    cfg, tcfg = EKMConfig(mapping=mapping), TrainConfig(steps=100_000, trials=5)
    keys = jax.random.split(jax.random.PRNGKey(0), tcfg.trials)
    trainees = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    total, count = kernel_times(lambda: jax.block_until_ready(
        train_chunk(trainees, keys, 0.0, length=steps, cfg=cfg, tcfg=tcfg)), 1)
    hlo = train_chunk.lower(trainees, keys, 0.0, length=steps, cfg=cfg, tcfg=tcfg).compile().as_text() if show_hlo else ""
    print(f"training, {mapping}, 5 trials: µs per step (traced) and events per step, over one chunk of {steps} steps:")
    for name, us in total.most_common(top):
        if not (name.startswith("$") or "stop_trace" in name):
            print(f"{us / steps:9.2f}  {count[name] / steps:5.2f}  {name[:70]}{_origin(name, hlo)}")
    return 0


def _origin(kernel: str, hlo: str) -> str:
    """`` <- operation`` behind ``kernel`` in the compiled ``hlo`` text (its ``op_name``), or ``""``."""
    m = re.search(r"\n\s*(?:ROOT )?%" + re.escape(kernel) + r" = [^\n]*op_name=\"([^\"]*)\"", hlo) if hlo else None
    return f"   <- {m.group(1).split('/')[-1]}" if m else ""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--architecture", default="fields", help="as ekm run spells it (default fields)")
    ap.add_argument("--world", default="three-rooms-static", help="named world or world file")
    ap.add_argument("--calls", type=int, default=200, help="traced calls (default 200)")
    ap.add_argument("--top", type=int, default=30, help="events to print (default 30)")
    ap.add_argument("--hlo", action="store_true", help="name the operation behind each top kernel")
    ap.add_argument("--training", choices=("indirect", "direct"), help="trace a training step instead")
    args = ap.parse_args(argv)
    if args.training:
        return profile_training(args.training, args.calls, args.top, args.hlo)
    spec = parse_architectures(args.architecture)[0]
    ctl, ticks = recorded(spec, load_world(args.world))
    state, obs = ticks[len(ticks) * 2 // 3]
    step = scenario._in_one_loop(ctl.step)
    total, count = kernel_times(lambda: np.asarray(step(state, obs)[1]), args.calls)
    hlo = ""
    if args.hlo and isinstance(ctl.step, functools.partial):  # the runner's looped step (scenario._in_one_loop)
        arrays = {k: v for k, v in ctl.step.keywords.items() if scenario._is_arrays(v)}
        static = tuple(sorted((k, v) for k, v in ctl.step.keywords.items() if k not in arrays))
        hlo = scenario._looped(ctl.step.func, static).lower(state, obs, arrays).compile().as_text()
    print(f"{args.architecture} on {args.world}, tick {len(ticks) * 2 // 3} "
          f"of {len(ticks)}; µs per call (traced) and events per call:")
    for name, us in total.most_common(args.top):
        if name.startswith("$profiler") or "stop_trace" in name:
            continue
        print(f"{us / args.calls:9.1f}  {count[name] / args.calls:5.1f}  {name[:70]}{_origin(name, hlo)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
