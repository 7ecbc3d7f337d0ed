"""How fast scenario runs go (docs/design.md §5, §6; thesis ch. 6.2), and where the time of a 0.128 s tick goes.

Run from the repository root (about four minutes on 2 cores with the defaults)::

    python benchmarks/perf/bench_scenarios.py                          # markdown tables
    python benchmarks/perf/bench_scenarios.py --architectures fusion,fields:form=thesis --worlds concave-obstacle
    python benchmarks/perf/bench_scenarios.py --json                   # the numbers

(options: ``--architectures`` in ``ekm run``'s spelling, comma-separated, default
``fusion,fields,samba,schema`` (the README's compare table) — any architecture :mod:`robots.controllers.spec`
knows works; ``--worlds`` comma-separated named worlds, default all eight;
``--seeds 3`` runs per world; ``--calls 300`` / ``--repeat 5`` for the tight loops, best block kept;
``--no-pin`` leaves the process free to use every CPU instead of one, as ``ekm run`` and ``ekm compare``'s
workers use, :mod:`evaluation.pinning`.)

The first table is the summary: real-time factor (simulated s per wall s, all timed runs of the cell
together) per architecture and world, and the slowest cell of each architecture. Each architecture drives its shipped map (:func:`ekm.data.load_default_map`, trial ``seed % trials`` as
:func:`evaluation.scenario.run_architecture` picks it) through :func:`evaluation.scenario.run_scenario`
with the default :class:`~evaluation.scenario.ScenarioConfig`. Per architecture and world:

1. **Warm-up**: one run with the first seed, not counted. Its first controller call is the *first call*
   (tracing, lowering to MLIR and XLA compilation, split by ``jax.monitoring``'s compile events); a world
   whose observation shapes the architecture has already seen (same number of moving objects) compiles
   nothing new.
2. **Runs**: ``--seeds`` runs (seeds 0, 1, …) timed end to end: wall seconds per run, real-time factor
   (simulated s per wall s) and control ticks per wall s. A tick is split, without touching the package,
   by ``time.perf_counter`` accumulators around (a) ``PymunkWorld.step`` — pymunk physics, 8 sub-steps of
   16 ms, motor model; (b) ``PymunkWorld.sense`` — the IR ray casts and sensor noise; (c) the controller's
   jitted ``step`` including dispatch, with ``jax.block_until_ready`` on its output so asynchronous
   dispatch cannot hide it (the runner reads the command at once anyway); (d) the planner (``plan``,
   ``replan``, ``map_changed`` as the runner calls them) and (e) the rest of the runner (observation
   building, trace bookkeeping, the trap monitor, building the pymunk world). *compiles after warm-up*
   counts XLA compilations during these runs (should be 0).
3. **Controller step alone**, on observations recorded in the warm-up run: *loop* — µs per call of
   ``step(state, obs)`` in a tight Python loop on one fixed observation (the mid-run tick), blocking on
   each output; *trivial* — the same for a jitted function called exactly the same way (same state and
   observation, the same bound map arrays and static parameters) that returns fresh arrays of the same
   shapes and computes next to nothing: the floor of JAX's per-call dispatch (argument handling,
   host-to-device copies of the observation, the static-argument cache lookup, launch, output buffers);
   *scan* — µs per step inside one ``lax.scan`` that replays the recorded observation sequence: the
   step's compute without any per-call cost; *overhead %* = (loop − scan) / loop, floored at 0, the
   share of a call that is not the step's own compute — JAX dispatch (at least *trivial*) plus launching
   the step's XLA executable. A scan body is compiled and scheduled differently from a standalone call,
   so *scan* can come out above *loop* for a heavy step: overhead 0 % then reads as compute-bound.

The last line names what bounds the speed, computed from the numbers. Wall-clock numbers move with
whatever else runs on the machine: the header prints the 1-minute load average before and after.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import json
import math
import os
import sys
import time

import jax
import jax.numpy as jnp
import numpy as np
from jax import monitoring

import evaluation.scenario as scenario
from ekm.data import load_default_map
from ekm.errors import InputError
from evaluation.pinning import pin_to_one_cpu
from evaluation.scenario import ScenarioConfig, run_scenario
from robots.controllers.spec import parse_architectures
from robots.world import PymunkWorld
from robots.worldnames import load_world

DEFAULT_ARCHITECTURES = "fusion,fields,samba,schema"  # the four of the README's compare table
DEFAULT_WORLDS = ("three-rooms-static,three-rooms-moving,three-rooms-changed,extended-obstacle,concave-obstacle,"
                  "three-rooms,open-arena,moving-target")  # every named world
PARTS = ("physics", "sensing", "controller", "planner", "rest")
PART_LABEL = {"physics": "pymunk physics", "sensing": "IR sensing", "controller": "controller step",
              "planner": "planner", "rest": "rest of the runner"}
_TRACE, _LOWER, _COMPILE = ("/jax/core/compile/jaxpr_trace_duration", "/jax/core/compile/jaxpr_to_mlir_module_duration",
                            "/jax/core/compile/backend_compile_duration")

# ---------------------------------------------------------------------------------------- timing hooks
EVENTS: list[tuple[str, float]] = []  # every JAX compile-stage event of the process: (name, seconds)
monitoring.register_event_duration_secs_listener(lambda name, secs, **_: EVENTS.append((name, secs)))


def compile_split(events) -> dict:
    """Seconds of tracing, lowering and XLA compilation among ``events``, and how many XLA compilations."""
    total = {k: sum(s for n, s in events if n == e) for k, e in (("trace", _TRACE), ("lower", _LOWER),
                                                                  ("compile", _COMPILE))}
    return {**total, "compiles": sum(n == _COMPILE for n, _ in events)}


class Accumulator:
    """Seconds spent in each instrumented part, and the controller calls (their durations, and — when
    ``record`` — their inputs, for the step-alone measurements)."""

    def __init__(self, record: bool = False):
        self.seconds = dict.fromkeys(PARTS[:-1], 0.0)
        self.calls: list[float] = []
        self.inputs: list = []  # (state, obs) of every controller call when recording
        self.first_events: list = []  # compile events of the first controller call
        self.record = record

    def timed(self, part: str, fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                self.seconds[part] += time.perf_counter() - t0
        return wrapper


@contextlib.contextmanager
def instrumented(acc: Accumulator):
    """Patch ``PymunkWorld.step/sense`` and the runner's planner calls with ``acc``'s timers; restore on exit."""
    patches = [(PymunkWorld, "step", "physics"), (PymunkWorld, "sense", "sensing")]
    patches += [(scenario, name, "planner") for name in ("plan", "replan", "map_changed") if hasattr(scenario, name)]
    saved = [(owner, name, getattr(owner, name)) for owner, name, _ in patches]
    try:
        for (owner, name, part), (_, _, orig) in zip(patches, saved):
            setattr(owner, name, acc.timed(part, orig))
        yield acc
    finally:
        for owner, name, orig in saved:
            setattr(owner, name, orig)


def timed_controller(ctl, acc: Accumulator):
    """``ctl`` whose ``step`` is timed into ``acc`` (blocking on its output) and optionally recorded. The step
    is called the way the runner calls it (:func:`evaluation.scenario._in_one_loop`, when present)."""
    inner = getattr(scenario, "_in_one_loop", lambda step: step)(ctl.step)

    def step(state, obs):
        n = len(EVENTS)
        t0 = time.perf_counter()
        out = jax.block_until_ready(inner(state, obs))
        dt = time.perf_counter() - t0
        if not acc.calls:
            acc.first_events = EVENTS[n:]
        acc.calls.append(dt)
        acc.seconds["controller"] += dt
        if acc.record:
            acc.inputs.append((state, obs))
        return out

    return dataclasses.replace(ctl, step=step)


# ---------------------------------------------------------------------------------------- measurements
def one_run(world, ctl, seed: int, config: ScenarioConfig, record: bool = False) -> dict:
    """One timed, instrumented run: wall, simulated seconds, ticks and the split of the wall time."""
    acc = Accumulator(record)
    n_events = len(EVENTS)
    with instrumented(acc):
        t0 = time.perf_counter()
        rec = run_scenario(world, timed_controller(ctl, acc), seed=seed, config=config)
        wall = time.perf_counter() - t0
    parts = dict(acc.seconds, rest=wall - sum(acc.seconds.values()))
    return {"seed": seed, "wall_s": wall, "sim_s": rec.time_s, "ticks": len(acc.calls), "parts_s": parts,
            "reached": bool(rec.outcome()["reached"]), "ended": rec.ended,
            "compiles": compile_split(EVENTS[n_events:])["compiles"],
            "first_call_s": acc.calls[0] if acc.calls else float("nan"),
            "first_call": compile_split(acc.first_events), "calls": acc.calls, "inputs": acc.inputs}


def best_per_call(fn, calls: int, repeat: int) -> float:
    """Best mean seconds per call of ``fn()`` over ``repeat`` blocks of ``calls`` calls."""
    fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best


def trivial_twin(step):
    """A jitted function called the way ``step`` is — the same state and observation and, when ``step`` is
    a ``functools.partial`` of a jitted function (as every architecture builds it), the same bound map
    arrays and static parameters (hashed on every call) — returning fresh arrays of the state's shapes
    and a ``(2,)`` command, and computing next to nothing: the floor of one call's dispatch."""

    def touch(a):
        return ~a if a.dtype == jnp.bool_ else -a

    def trivial(state, obs, **_):
        return jax.tree.map(lambda a: touch(jnp.asarray(a)), state), obs.target * 0.5

    if not isinstance(step, functools.partial) or step.args:
        return jax.jit(trivial)

    def is_arrays(v):
        leaves = jax.tree.leaves(v)
        return bool(leaves) and all(isinstance(a, (jax.Array, np.ndarray)) for a in leaves)

    static = [k for k, v in step.keywords.items() if not is_arrays(v)]
    return functools.partial(jax.jit(trivial, static_argnames=static), **step.keywords)


def step_alone(ctl, inputs, calls: int, repeat: int) -> dict:
    """The controller step outside the runner, on the recorded ``inputs`` [(state, obs), …] of one run."""
    state, obs = inputs[len(inputs) // 2]
    loop = best_per_call(lambda: jax.block_until_ready(ctl.step(state, obs)), calls, repeat)
    twin = trivial_twin(ctl.step)
    trivial = best_per_call(lambda: jax.block_until_ready(twin(state, obs)), calls, repeat)

    # Replay the recorded observations inside one lax.scan: the step's compute without per-call dispatch.
    # The carry starts from the state after the first tick (types as the step returns them); the commands
    # are summed into the carry so that XLA cannot drop them.
    seq = inputs[1:]
    xs = jax.tree.map(lambda *a: np.stack(a), *[o for _, o in seq])

    @jax.jit
    def replay(s0, xs):
        def body(carry, o):
            s, total = carry
            s, c = ctl.step(s, o)
            return (s, total + jnp.asarray(c, jnp.float32)), None
        return jax.lax.scan(body, (s0, jnp.zeros(2, jnp.float32)), xs)[0]

    try:
        per_run = best_per_call(lambda: jax.block_until_ready(replay(seq[0][0], xs)), 1, repeat)
        compute = per_run / len(seq)
    except (TypeError, ValueError) as exc:  # a carry whose type changes from tick to tick cannot be scanned
        print(f"warning: {ctl.spec}: scan replay failed ({exc.__class__.__name__}: {str(exc).splitlines()[0]})",
              file=sys.stderr)
        compute = float("nan")
    return {"loop_us": 1e6 * loop, "trivial_us": 1e6 * trivial, "scan_us": 1e6 * compute,
            "dispatch_floor_pct": 100.0 * trivial / loop,
            "overhead_pct": 100.0 * max(0.0, loop - compute) / loop if math.isfinite(compute) else math.nan,
            "replayed_ticks": len(seq)}


def summarise(runs: list[dict]) -> dict:
    """Totals and per-run / per-tick figures of a list of runs."""
    wall = sum(r["wall_s"] for r in runs)
    sim = sum(r["sim_s"] for r in runs)
    ticks = sum(r["ticks"] for r in runs)
    parts = {p: sum(r["parts_s"][p] for r in runs) for p in PARTS}
    steady = [dt for r in runs for dt in r["calls"]]
    return {"runs": len(runs), "reached": sum(r["reached"] for r in runs), "wall_s": wall, "sim_s": sim,
            "ticks": ticks, "wall_s_per_run": wall / len(runs), "sim_s_per_run": sim / len(runs),
            "ticks_per_run": ticks / len(runs), "real_time_factor": sim / wall, "ticks_per_s": ticks / wall,
            "parts_s": parts, "us_per_tick": {p: 1e6 * parts[p] / ticks for p in PARTS},
            "pct": {p: 100.0 * parts[p] / wall for p in PARTS},
            "controller_median_us": 1e6 * float(np.median(steady)) if steady else float("nan"),
            "compiles": sum(r["compiles"] for r in runs)}


def measure(spec, worlds: dict, seeds: list[int], config: ScenarioConfig, calls: int, repeat: int,
            maps_cache: dict) -> dict:
    """Warm-up, timed runs and step-alone numbers of one architecture on every world."""
    chart = spec.default_chart
    controllers = {}
    if spec.uses_map:
        if chart not in maps_cache:
            maps_cache[chart] = load_default_map(chart)
        maps = maps_cache[chart]

        def controller(seed):
            trial = seed % maps.trials
            if trial not in controllers:
                controllers[trial] = spec.build(jax.tree.map(lambda a: a[trial], maps.ekm), maps.cfg)
            return controllers[trial]
    else:  # Samba, motor schemas: no map

        def controller(seed):
            if None not in controllers:
                controllers[None] = spec.build()
            return controllers[None]

    drives = f"shipped {chart}-chart map" if spec.uses_map else "no map"
    out = {"architecture": str(spec), "label": spec.label, "map": drives, "worlds": {}}
    for name, world in worlds.items():
        warm = one_run(world, controller(seeds[0]), seeds[0], config, record=True)
        runs = [one_run(world, controller(s), s, config) for s in seeds]
        alone = step_alone(controller(seeds[0]), warm.pop("inputs"), calls, repeat)
        for r in runs:
            r.pop("inputs")
        out["worlds"][name] = {
            "warmup": {"wall_s": warm["wall_s"], "first_call_s": warm["first_call_s"], **warm["first_call"],
                       "compiles": warm["compiles"]},
            "runs": [{k: v for k, v in r.items() if k not in ("calls", "first_call", "first_call_s")} for r in runs],
            "summary": summarise(runs), "step": alone, "_runs": runs}
    every = [r for w in out["worlds"].values() for r in w.pop("_runs")]
    out["summary"] = summarise(every)
    return out


# ---------------------------------------------------------------------------------------------- output
def print_summary(results: list[dict]) -> None:
    """Real-time factor per architecture (rows) and world (columns), all runs, the slowest world and the
    slowest single run of each architecture."""
    worlds = list(results[0]["worlds"])
    print("\n| real-time × | " + " | ".join(f"`{w}`" for w in worlds) + " | all | slowest world | slowest run |")
    print("|---|" + "---:|" * (len(worlds) + 3))
    for res in results:
        rtf = {w: res["worlds"][w]["summary"]["real_time_factor"] for w in worlds}
        low = min(rtf, key=rtf.get)
        runs = [r for w in worlds for r in res["worlds"][w]["runs"]]
        slow = min(runs, key=lambda r: r["sim_s"] / r["wall_s"])
        print(f"| {res['label']} | " + " | ".join(f"{rtf[w]:.0f}" for w in worlds) +
              f" | {res['summary']['real_time_factor']:.0f} | {rtf[low]:.0f} ({low}) | "
              f"{slow['sim_s'] / slow['wall_s']:.0f} |")


def print_tables(results: list[dict]) -> None:
    print_summary(results)
    for res in results:
        print(f"\n### {res['label']}  ({res['architecture']}, {res['map']})\n")
        print("| world | runs | reached | ticks/run | sim s/run | wall s/run | real-time × | ticks/s "
              "| physics µs/tick | IR sensing µs/tick | controller µs/tick | planner µs/tick | rest µs/tick |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        rows = [(name, w["summary"]) for name, w in res["worlds"].items()] + [("**all**", res["summary"])]
        for name, s in rows:
            split = " | ".join(f"{s['us_per_tick'][p]:,.0f} ({s['pct'][p]:.0f} %)" for p in PARTS)
            print(f"| {name} | {s['runs']} | {s['reached']}/{s['runs']} | {s['ticks_per_run']:.0f} | "
                  f"{s['sim_s_per_run']:.1f} | {s['wall_s_per_run']:.3f} | {s['real_time_factor']:.0f} | "
                  f"{s['ticks_per_s']:,.0f} | {split} |")
        print("\n| world | first call s | trace / lower / XLA compile s | compiles after warm-up "
              "| in-run µs/call (median) | loop µs/call | trivial jit µs/call | scan µs/step "
              "| overhead % |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for name, w in res["worlds"].items():
            wu, st, s = w["warmup"], w["step"], w["summary"]
            print(f"| {name} | {wu['first_call_s']:.3f} | "
                  f"{wu['trace']:.3f} / {wu['lower']:.3f} / {wu['compile']:.3f} "
                  f"({wu['compiles']} compile{'' if wu['compiles'] == 1 else 's'}) | {s['compiles']} | "
                  f"{s['controller_median_us']:,.0f} | {st['loop_us']:,.0f} | {st['trivial_us']:,.0f} | "
                  f"{st['scan_us']:,.1f} | {st['overhead_pct']:.0f} |")
    print("\n" + conclusion(results))


def conclusion(results: list[dict]) -> str:
    """One line on what bounds the speed, from the measured numbers: per architecture the largest share
    of the run time, and whether its controller step is bound by per-call overhead or by compute."""
    clauses = []
    for r in results:
        pct = r["summary"]["pct"]
        top, second = sorted(PARTS, key=pct.get, reverse=True)[:2]
        steps = [w["step"] for w in r["worlds"].values()]
        loop = float(np.mean([s["loop_us"] for s in steps]))
        trivial = float(np.mean([s["trivial_us"] for s in steps]))
        scan = float(np.nanmean([s["scan_us"] for s in steps]))
        overhead = max(0.0, loop - scan) / loop if math.isfinite(scan) else trivial / loop
        clauses.append(
            f"{r['label']} ({r['summary']['real_time_factor']:.0f}× real time): {PART_LABEL[top]} {pct[top]:.0f} %, "
            f"then {PART_LABEL[second]} {pct[second]:.0f} %; its step ({pct['controller']:.0f} %) is "
            f"{'per-call-overhead' if overhead >= 0.5 else 'compute'}-bound ({loop:,.0f} µs/call, "
            f"{scan:,.0f} µs of compute in a scan, a trivial jit called the same way {trivial:,.0f} µs)")
    parts = {p: sum(r["summary"]["parts_s"][p] for r in results) for p in PARTS}
    top = max(PARTS, key=parts.get)
    first = [max(w["warmup"]["first_call_s"] for w in r["worlds"].values()) for r in results]
    runs = [f / r["summary"]["wall_s_per_run"] for f, r in zip(first, results)]

    def span(xs, fmt):
        lo, hi = f"{min(xs):{fmt}}", f"{max(xs):{fmt}}"
        return lo if lo == hi else f"{lo}–{hi}"

    return (f"bound: {'; '.join(clauses)}. Over all runs: {PART_LABEL[top]} "
            f"{100 * parts[top] / sum(parts.values()):.0f} %. First-call compilation {span(first, '.1f')} s "
            f"per architecture = {span(runs, '.0f')} steady runs.")


def finite(tree):
    """``tree`` with NaN/inf floats as None (strict JSON)."""
    if isinstance(tree, dict):
        return {k: finite(v) for k, v in tree.items()}
    if isinstance(tree, (list, tuple)):
        return [finite(v) for v in tree]
    if isinstance(tree, float) and not math.isfinite(tree):
        return None
    return tree


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--architectures", "--arch", default=DEFAULT_ARCHITECTURES, metavar="A1,A2,...",
                    help=f"architectures as ekm run spells them, comma-separated (default {DEFAULT_ARCHITECTURES})")
    ap.add_argument("--worlds", default=DEFAULT_WORLDS, metavar="W1,W2,...",
                    help=f"named worlds or world files, comma-separated (default {DEFAULT_WORLDS})")
    ap.add_argument("--seeds", type=int, default=3, help="timed runs per world, seeds 0.. (default 3)")
    ap.add_argument("--time-limit", type=float, default=ScenarioConfig().time_limit,
                    help="simulated seconds before a run is given up (default %(default)g)")
    ap.add_argument("--calls", type=int, default=300, help="controller calls per tight-loop block (default 300)")
    ap.add_argument("--repeat", type=int, default=5, help="tight-loop blocks, best kept (default 5)")
    ap.add_argument("--no-pin", action="store_true",
                    help="leave the process free to use every CPU (default: one CPU, as ekm run and ekm compare's "
                         "workers run; evaluation.pinning)")
    ap.add_argument("--json", action="store_true", help="print the numbers as JSON instead of tables")
    args = ap.parse_args(argv)
    if args.seeds < 1 or args.calls < 1 or args.repeat < 1:
        ap.error("--seeds, --calls and --repeat must be >= 1")
    cpu = None if args.no_pin else pin_to_one_cpu()  # before the JAX backend starts (below)

    try:
        specs = parse_architectures(args.architectures)
        worlds = {name: load_world(name) for name in (w.strip() for w in args.worlds.split(",")) if name}
    except InputError as exc:
        ap.error(str(exc))
    if not worlds:
        ap.error("--worlds: no world given")
    config = ScenarioConfig(time_limit=args.time_limit)
    jax.block_until_ready(jax.jit(lambda x: x + 1)(jnp.zeros(2)))  # backend start-up is nobody's compile time

    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    cache: dict = {}
    results = [measure(spec, worlds, list(range(args.seeds)), config, args.calls, args.repeat, cache)
               for spec in specs]
    total = time.perf_counter() - t0
    if args.json:
        print(json.dumps(finite({"jax": jax.__version__, "devices": [str(d) for d in jax.devices()],
                                 "seeds": args.seeds, "time_limit_s": args.time_limit, "results": results,
                                 "conclusion": conclusion(results), "benchmark_wall_s": total,
                                 "load_average_1min": [load, os.getloadavg()[0]], "pinned_cpu": cpu}), indent=2))
    else:
        print(f"jax {jax.__version__} on {jax.devices()}; {args.seeds} seeds per world, warm-up run first; "
              f"benchmark took {total:.0f} s; 1-min load average {load:.1f} before, {os.getloadavg()[0]:.1f} after "
              f"(on {os.cpu_count()} cores: more means other work shared the CPU); "
              + ("not pinned" if cpu is None else f"pinned to CPU {cpu} (evaluation.pinning)"))
        print_tables(results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
