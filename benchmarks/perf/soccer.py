"""How fast soccer games go: one 10-minute game on one CPU as a multiple of real time, and a round robin on 2 workers.

Run from the repository root::

    python benchmarks/perf/soccer.py --only game                  # (a): two 10-minute games, about half a minute
    python benchmarks/perf/soccer.py --only tournament            # (b): 100 10-minute games on 2 workers, minutes
    python benchmarks/perf/soccer.py                              # both
    python benchmarks/perf/soccer.py --only game --games ekm-schema,deliberation-samba --minutes 2
    python benchmarks/perf/soccer.py --only tournament --players ekm,schema,schema:push=0.15 --seeds 4 --json

**(a) One game** (``--games``, default ``ekm-schema,schema-schema``: side 0's player, a hyphen, side 1's, each in
``ekm match``'s spelling): :func:`evaluation.match.play_match` for ``--minutes`` (10) of game time, seed 0, rule
``centre``, in this process pinned to one CPU before JAX starts (:mod:`evaluation.pinning`, as ``ekm match``
and every worker of a round robin run; ``--no-pin`` leaves it free). First a one-tick game of the same pairing
builds both players and compiles their jitted steps: its wall time is the *compile* column (of which XLA's
trace, lowering and compilation, from ``jax.monitoring``'s events). Then the timed game: *× real time* is
game seconds per wall second (target: at least 100); *× CPU time* is game seconds per second of this process's
CPU time (``time.process_time``), about what × real time would be on a CPU of its own (on a loaded machine
the two differ). The game's wall time is split, without touching the package, by ``time.perf_counter``
accumulators round (1) ``Game.step`` — the 8 pymunk sub-steps of a 0.128 s tick for both robots and the ball,
the motors and the referee; (2) ``RobotBody.sense`` — both IR rings; (3) the players' jitted steps, blocking on
their output; (4) the rest of the runner (each player's frame, the records). *compiles* counts XLA
compilations during the timed game (should be 0).

**(b) A round robin** (``--players``, default ``ekm,schema,deliberation,samba``): every pairing including self-play,
``--seeds`` (10) seeds each, ``--minutes`` (10) per game — with 4 players 10 pairings × 10 seeds = 100 games —
through :func:`evaluation.compare.compare` on ``evaluation.workers.workers_for(play_job, --workers, None)``
(2 spawned local workers, each pinned to a CPU of its own and compiling each player once). The wall time is
from the first job submitted to the last record, worker start-up included (target: under 5 minutes); the
summary gives the games per minute, the game seconds per wall second of all workers together, the failed
games, and the standings and cross table (:func:`evaluation.match.standings`, :func:`~evaluation.match.cross_table`).

Wall-clock numbers move with whatever else runs on the machine: the header prints the 1-minute load average
before and after.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

GAMES = "ekm-schema,schema-schema"
TARGET_X = 100.0  # (a): game seconds per wall second
TARGET_S = 300.0  # (b): wall seconds for the round robin


PLAYERS = "ekm,schema,deliberation,samba"


# --------------------------------------------------------------------------------------------- (a) one game
class Split:
    """Wall seconds spent in each timed part of a game, and the XLA compilations seen (jax.monitoring)."""

    def __init__(self):
        self.parts = {"physics": 0.0, "sensing": 0.0, "players": 0.0}
        self.events: list[tuple[str, float]] = []

    def timed(self, part: str, fn, block: bool = False):
        import jax

        def run(*args, **kwargs):
            t0 = time.perf_counter()
            out = fn(*args, **kwargs)
            if block:
                jax.block_until_ready(out)
            self.parts[part] += time.perf_counter() - t0
            return out

        return run

    def reset(self) -> None:
        self.parts = dict.fromkeys(self.parts, 0.0)
        self.events.clear()

    def compile_s(self) -> dict:
        names = {"trace": "/jax/core/compile/jaxpr_trace_duration",
                 "lower": "/jax/core/compile/jaxpr_to_mlir_module_duration",
                 "compile": "/jax/core/compile/backend_compile_duration"}
        out = {k: sum(s for n, s in self.events if n == v) for k, v in names.items()}
        out["compiles"] = sum(n == names["compile"] for n, _ in self.events)
        return out


def instrument(split: Split) -> None:
    """Wrap Game.step, RobotBody.sense and every built player's step in ``split``'s timers (this process only)."""
    import dataclasses

    from jax import monitoring

    from robots.body import RobotBody
    from robots.soccer.game import Game
    from robots.soccer.roster import PlayerSpec

    monitoring.register_event_duration_secs_listener(lambda name, secs, **_: split.events.append((name, secs)))
    Game.step = split.timed("physics", Game.step)
    RobotBody.sense = split.timed("sensing", RobotBody.sense)
    build = PlayerSpec.build

    def timed_build(self, field, robot):
        c = build(self, field, robot)
        return dataclasses.replace(c, step=split.timed("players", c.step, block=True))

    PlayerSpec.build = timed_build


def one_game(pairing: str, minutes: float, split: Split) -> dict:
    from evaluation.match import play_match
    from robots.params import KHEPERA

    first, sep, second = pairing.partition("-")
    if not sep or not second:
        raise SystemExit(f"--games: {pairing!r} is not FIRST-SECOND")
    split.reset()
    t0 = time.perf_counter()
    play_match(first, second, minutes=KHEPERA.avoid_period / 60.0, seed=0)  # one tick: build and compile
    warm_s = time.perf_counter() - t0
    warm = split.compile_s()
    split.reset()
    t0, c0 = time.perf_counter(), time.process_time()
    rec = play_match(first, second, minutes=minutes, seed=0)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    game_s = float(rec.times[-1])
    ticks = len(rec.times) - 1
    parts = dict(split.parts)
    parts["rest"] = max(0.0, wall - sum(parts.values()))
    return {"pairing": f"{rec.players[0]} - {rec.players[1]}", "game_s": game_s, "wall_s": wall,
            "x_real_time": game_s / wall, "cpu_s": cpu, "x_cpu_time": game_s / cpu, "ticks_per_s": ticks / wall, "ms_per_tick": 1e3 * wall / ticks,
            "parts_s": parts, "compile_s": warm_s, "xla": warm, "compiles_in_game": split.compile_s()["compiles"],
            "goals": list(rec.goals), "restarts": len(rec.restarts)}


def games(pairings: list[str], minutes: float, pin: bool) -> tuple[list[dict], int | None]:
    from evaluation.pinning import pin_to_one_cpu

    cpu = pin_to_one_cpu() if pin else None  # before the JAX backend starts (the first player's build)
    split = Split()
    instrument(split)
    return [one_game(p, minutes, split) for p in pairings], cpu


# ----------------------------------------------------------------------------------------- (b) round robin
def tournament(players: str, seeds: int, minutes: float, workers: int, rule: str) -> dict:
    from evaluation.compare import compare
    from evaluation.match import cross_table, game_failed, play_job, standings, tournament_jobs
    from evaluation.workers import workers_for
    from robots.soccer.roster import parse_players

    specs = parse_players(players)
    labels = [s.label for s in specs]
    jobs = tournament_jobs(specs, range(seeds), minutes, rule)
    pool = workers_for(play_job, workers, None)
    done = [0]

    def progress(i, record):
        done[0] += 1
        flag = " FAILED: " + record["failed"] if "failed" in record else ""
        print(f"\r  {done[0]}/{len(jobs)} games, {time.perf_counter() - t0:.0f} s{flag}", end="\n" if flag else "",
              file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    try:
        records = compare(jobs, pool, progress, failed=game_failed)
    finally:
        pool.close()
    wall = time.perf_counter() - t0
    print(file=sys.stderr)
    played = [r for r in records if "failed" not in r]
    return {"players": labels, "pairings": len({j.pair for j in jobs}), "seeds": seeds, "games": len(jobs),
            "minutes": minutes, "workers": workers, "where": pool.where, "wall_s": wall,
            "games_per_min": 60.0 * len(jobs) / wall, "x_real_time_all": 60.0 * minutes * len(played) / wall,
            "x_real_time_per_worker": 60.0 * minutes * len(played) / wall / workers,
            "failed": [r["failed"] for r in records if "failed" in r], "goals": sum(sum(r["goals"]) for r in played),
            "standings": standings(records, labels),
            "cross_table": {f"{labels[i]} vs {labels[j]}": v for (i, j), v in cross_table(records, labels).items()}}


# ------------------------------------------------------------------------------------------------- output
def print_games(rows: list[dict], cpu, minutes: float) -> None:
    print(f"\n(a) one {minutes:g}-minute game, seed 0, rule centre, "
          + ("not pinned" if cpu is None else f"pinned to CPU {cpu}") + f"; target >= {TARGET_X:.0f}× real time")
    print("(compile: the first one-tick game of the pairing; a player built before compiles nothing new)")
    print("\n| side 0 - side 1 | × real time | wall s | × CPU time | ms per tick | physics | IR | players | rest | "
          "compile s (XLA trace / lower / compile) | compiles in game | goals |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        p, x = r["parts_s"], r["xla"]
        share = {k: f"{100 * v / r['wall_s']:.0f} %" for k, v in p.items()}
        print(f"| {r['pairing']} | {r['x_real_time']:.0f} | {r['wall_s']:.1f} | {r['x_cpu_time']:.0f} | "
              f"{r['ms_per_tick']:.2f} | "
              f"{share['physics']} | {share['sensing']} | {share['players']} | {share['rest']} | "
              f"{r['compile_s']:.1f} ({x['trace']:.2f} / {x['lower']:.2f} / {x['compile']:.2f}) | "
              f"{r['compiles_in_game']} | {r['goals'][0]}:{r['goals'][1]} |")
    worst = min(rows, key=lambda r: r["x_real_time"])
    print(f"\nslowest: {worst['pairing']} at {worst['x_real_time']:.0f}× real time — target "
          + ("met" if worst["x_real_time"] >= TARGET_X else "NOT met"))


def print_tournament(t: dict) -> None:
    print(f"\n(b) round robin: {len(t['players'])} players ({', '.join(t['players'])}), {t['pairings']} pairings × "
          f"{t['seeds']} seeds = {t['games']} games of {t['minutes']:g} min on {t['where']}; "
          f"target < {TARGET_S:.0f} s")
    print(f"\nwall {t['wall_s']:.0f} s ({t['wall_s'] / 60:.1f} min) — target "
          + ("met" if t["wall_s"] < TARGET_S else "NOT met")
          + f"; {t['games_per_min']:.1f} games/min; {t['x_real_time_all']:.0f}× real time for all workers together "
            f"({t['x_real_time_per_worker']:.0f}× per worker); {len(t['failed'])} failed; {t['goals']} goals")
    for reason in sorted(set(t["failed"])):
        print(f"  failed ({t['failed'].count(reason)}): {reason}")
    print("\n| player | games | won | drawn | lost | goals | goal difference per game (95 %) | win rate (95 %) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in t["standings"]:
        gd = "–" if r["goal_difference"] is None else f"{r['goal_difference']:+.2f} ({r['gd_ci95'][0]:+.2f} … {r['gd_ci95'][1]:+.2f})"
        wr = "–" if r["win_rate"] is None else f"{r['win_rate']:.2f} ({r['win_ci95'][0]:.2f} … {r['win_ci95'][1]:.2f})"
        print(f"| {r['player']} | {r['games']} | {r['won']} | {r['drawn']} | {r['lost']} | "
              f"{r['goals_for']}:{r['goals_against']} | {gd} | {wr} |")
    print("\n| pairing (row player first) | goals | games |")
    print("|---|---:|---:|")
    for pair, (a, b, n) in t["cross_table"].items():
        print(f"| {pair} | {a}:{b} | {n} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=("game", "tournament"), help="run one part only")
    ap.add_argument("--games", default=GAMES, help=f"(a): pairings FIRST-SECOND, comma-separated (default {GAMES})")
    ap.add_argument("--players", default=None, help="(b): players in ekm match's spelling, comma-separated "
                                                    "(default ekm,schema,deliberation,samba where they import)")
    ap.add_argument("--minutes", type=float, default=10.0, help="game time of every game (default 10)")
    ap.add_argument("--seeds", type=int, default=10, help="(b): seeds per pairing (default 10)")
    ap.add_argument("--workers", type=int, default=2, help="(b): local worker processes (default 2)")
    ap.add_argument("--rule", default="centre", choices=("centre", "sahota"), help="(b): restart rule")
    ap.add_argument("--no-pin", action="store_true", help="(a): leave this process free to use every CPU")
    ap.add_argument("--json", action="store_true", help="print the numbers as JSON")
    args = ap.parse_args(argv)
    if not (math.isfinite(args.minutes) and args.minutes > 0) or args.seeds < 1 or args.workers < 1:
        ap.error("--minutes, --seeds and --workers must be positive")
    load = os.getloadavg()[0]
    out: dict = {}
    if args.only in (None, "tournament"):  # first: its workers are spawned before this process is pinned
        out["tournament"] = tournament(args.players or PLAYERS, args.seeds, args.minutes, args.workers,
                                       args.rule)
    if args.only in (None, "game"):
        rows, cpu = games([g.strip() for g in args.games.split(",") if g.strip()], args.minutes, not args.no_pin)
        out["game"], out["pinned_cpu"] = rows, cpu
    out["load_average_1min"] = [load, os.getloadavg()[0]]
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{os.cpu_count()} cores; 1-min load average {load:.1f} before, {os.getloadavg()[0]:.1f} after "
          "(more than 0 means other work shared the CPU)")
    if "game" in out:
        print_games(out["game"], out["pinned_cpu"], args.minutes)
    if "tournament" in out:
        print_tournament(out["tournament"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
