"""``ekm match``: one game of robot soccer between two players, refereed, with its score line, the goal times and
the rule (:func:`ekm.match`)."""

from __future__ import annotations

from ekm.cli.args import command, nonneg_int, one_of, output_path, plot_path, positive_float, print_json, show_progress


def add_field_option(p) -> None:
    """``--field``, ``--rule`` and ``--robot``, shared with ``ekm tournament``."""
    from robots.soccer.referee import RULES

    p.add_argument("--robot", action="append", metavar="NAME|FILE",
                   help="the robot the players play on: a named robot or a robot file (default khepera; ekm robots "
                        "lists them); once for every player, or once per player in their order")

    p.add_argument("--field", default="lci-cup", metavar="NAME|FILE",
                   help="a named field or a field file: pitch, ball, kick-off poses and rule (default lci-cup; "
                        "docs/guide/soccer.md shows how to write one)")
    p.add_argument("--rule", type=one_of(RULES), metavar="{" + ",".join(RULES) + "}",
                   help="after a goal: centre (ball to the centre spot, robots to their kick-off poses) or sahota "
                        "(play on; the side scored upon must clear the ball from its half before a goal counts); "
                        "default the field's")


def add_parser(sub) -> None:
    p = command(sub, "match", "play one game of robot soccer between two players and print the score",
                ["ekm match deliberation deliberation:level=half",
                 "ekm match ekm schema --minutes 2 --seed 3 --plot match.png --gif match.gif",
                 "ekm match samba deliberation --rule sahota --field my-pitch.json --json",
                 "ekm match deliberation deliberation --robot khepera --robot worn-wheel"],
                more="The players and their parameters: ekm players. The first player plays side 0 and defends the "
                     "goal at x = 0. Field files and the rules: docs/guide/soccer.md.")
    p.add_argument("first", metavar="A", help="the player of side 0, NAME[:k=v,...] (ekm players lists them)")
    p.add_argument("second", metavar="B", help="the player of side 1, NAME[:k=v,...]")
    add_field_option(p)
    p.add_argument("--minutes", type=positive_float, default=10.0, help="game time in minutes (default 10)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="the robots' motor and sensor noise (default 0)")
    p.add_argument("--plot", metavar="PNG|SVG|PDF",
                   help="draw the whole game: both robots' paths, the ball's, the goals")
    p.add_argument("--gif", metavar="GIF", help="play the game as an animated GIF")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Play the game (:func:`ekm.match`); print the score line, the goals and the rule, or the JSON; draw."""
    from ekm.api.soccer import RULE_TEXT, match
    from evaluation.pinning import pin_to_one_cpu

    plot = plot_path(args.plot, "--plot") if args.plot else None
    gif = output_path(args.gif, "--gif", ".gif") if args.gif else None
    pin_to_one_cpu()  # one game, one thread of work: one CPU for it (evaluation.pinning)
    result = match(args.first, args.second, field=args.field, minutes=args.minutes, seed=args.seed, rule=args.rule,
                   robot=args.robot, progress=show_progress(args))
    if plot:
        result.save_plot(plot)
    if gif:
        result.save_animation(gif, progress=show_progress(args))
    if args.json:
        print_json(result.to_dict())
        return
    out = result.to_dict()
    (a, b), (p0, p1) = out["goals"], out["players"]
    print(f"{p0} {a} - {b} {p1}    ({out['field']}, {out['minutes']:g} min, seed {out['seed']}; {p0} plays side 0, "
          f"defending x = 0)")
    score = [0, 0]
    goals = []
    for t, side in out["goal_times"]:
        score[side] += 1
        goals.append(f"{t:.1f} s {out['players'][side]} ({score[0]}-{score[1]})")
    print("  goals: " + (", ".join(goals) if goals else "none"))
    print(f"  rule {out['rule']}: {RULE_TEXT[out['rule']]}")
    if out["robots"] != ["khepera", "khepera"]:
        print(f"  robots: {p0} on {out['robots'][0]}, {p1} on {out['robots'][1]}")
    extra = f"; dead-ball restarts {out['restarts']}" if out.get("restarts") is not None else ""
    print(f"  collisions {out['collisions'][0]}, {out['collisions'][1]}; the ball {out['ball_in_half_s'][0]:.1f} s in "
          f"side 0's half, {out['ball_in_half_s'][1]:.1f} s in side 1's{extra}")
    for path in (plot, gif):
        if path:
            print(f"  written to {path}")
