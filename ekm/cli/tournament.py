"""``ekm tournament``: the LCI Cup's round robin (Sahota 1993, ch. 4.3, Table 5) — every pair of players, each
against itself too, over seeds, in parallel — with its cross table and standings (:func:`ekm.tournament`)."""

from __future__ import annotations

from ekm.cli.args import (add_batch_options, command, in_this_process, nonneg_int, positive_float, positive_int,
                          print_columns, print_json, show_progress)
from ekm.cli.match import add_field_option


def add_parser(sub) -> None:
    p = command(sub, "tournament", "play every pair of soccer players over seeds (a round robin, in parallel) and "
                "rank them with 95 % intervals",
                ["ekm tournament deliberation,deliberation:level=half,deliberation:level=none --seeds 10",
                 "ekm tournament samba,ekm,schema --minutes 5 --seeds 20 --out cup.jsonl --plot cup.png",
                 "ekm tournament deliberation,samba --rule sahota --scheduler tcp://head:8786 --json",
                 "ekm tournament deliberation,deliberation --robot khepera --robot worn-wheel --seeds 4"],
                more="The players and their parameters: ekm players. In a pairing the player given first plays "
                     "side 0 on even seeds and side 1 on odd ones. docs/guide/soccer.md explains the table.")
    p.add_argument("players", metavar="A,B,...",
                   help="the players, NAME[:k=v,...] separated by commas; a k=v after a comma continues the player "
                        "before it (deliberation:level=half,max_s=2,samba); ekm players lists them")
    add_field_option(p)
    p.add_argument("--minutes", type=positive_float, default=10.0, help="game time of every game in minutes (default 10)")
    p.add_argument("--seeds", type=positive_int, default=10, help="games per pairing (default 10)")
    p.add_argument("--seed", type=nonneg_int, default=0,
                   help="game k of every pairing is played with seed SEED + k (default 0)")
    add_batch_options(p, "game", "finish the tournament of this results file (same players and settings): its games "
                                 "are kept, the missing ones played and appended")
    p.add_argument("--plot", metavar="PNG|SVG|PDF",
                   help="each player's goal difference and win rate with their intervals")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Play the round robin (:func:`ekm.tournament`); print the cross table and the standings, or the JSON; draw."""
    from ekm.api.soccer import tournament
    from ekm.cli.args import plot_path, print_written

    plot = plot_path(args.plot, "--plot") if args.plot else None
    in_this_process(args)
    result = tournament(args.players, field=args.field, minutes=args.minutes, seeds=args.seeds, seed=args.seed,
                        rule=args.rule, workers=args.workers, scheduler=args.scheduler, out=args.out,
                        resume=args.resume, robot=args.robot, progress=show_progress(args))
    if plot:
        result.save_plot(plot)
    if args.json:
        print_json(result.to_dict())
        return
    print_cross_table(result)
    print()
    print_standings(result.standings)
    print()
    failed = sum("failed" in r for r in result.records)
    pairings = len(result.cross_table)
    print(f"{len(result.records)} games ({pairings} pairings x {result.seeds} seeds, seeds {result.seed}.."
          f"{result.seed + result.seeds - 1}, {result.minutes:g} min each, rule {result.rule}, field {result.field}) "
          f"in {result.seconds:.0f} s on {result.workers}"
          + (f"; {failed} failed (the reasons: --json, or the results file)" if failed else ""))
    print_written(args, plot)


def print_cross_table(result) -> None:
    """Sahota's Table 5: row player against column player, "a - b" the row's goals and the column's summed over the
    seeds; self-play on the diagonal (side 0's goals first); the upper triangle only."""
    labels = list(result.labels)
    cells = {(r["row"], r["column"]): r for r in result.cross_table}
    short = False
    lines = [("goals (row - column)",) + tuple(labels)]
    for i, row in enumerate(labels):
        line = [row]
        for j, col in enumerate(labels):
            cell = cells.get((row, col)) if j >= i else None
            if cell is None:
                line.append("")
            elif cell["goals"] is None:
                line.append("failed")
                short = True
            else:
                mark = "*" if cell["games"] < result.seeds else ""
                short = short or bool(mark)
                line.append(f"{cell['goals'][0]} - {cell['goals'][1]}{mark}")
        lines.append(tuple(line))
    print_columns(lines)
    if short:
        print("* a game of this pairing could not be played: its sums leave it out")


def print_standings(rows) -> None:
    """Each player over its games against the others, best first: games, won-drawn-lost, goals for-against, mean
    goal difference per game with its 95 % interval, win rate (a draw is half) with its Wilson interval."""
    head = ("player", "games", "W-D-L", "goals", "GD/game", "95 % interval", "win rate", "95 % interval")
    lines = [head]
    for r in rows:
        if not r["games"]:
            lines.append((r["player"], "0", "", "", "", "", "", ""))
            continue
        (glo, ghi), (wlo, whi) = r["gd_ci95"], r["win_ci95"]
        lines.append((r["player"], str(r["games"]), f"{r['won']}-{r['drawn']}-{r['lost']}",
                      f"{r['goals_for']}-{r['goals_against']}", f"{r['goal_difference']:+.2f}",
                      f"{glo:+.2f} .. {ghi:+.2f}", f"{r['win_rate']:.2f}", f"{wlo:.2f}-{whi:.2f}"))
    print_columns(lines)
