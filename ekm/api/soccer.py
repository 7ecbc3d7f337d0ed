"""Robot soccer in Python: :func:`match` (``ekm match``), :func:`tournament` (``ekm tournament``) and
:func:`soccer_field` (field files), with their results (the players: :func:`ekm.players`, :mod:`ekm.api.catalogue`).

A game is one-on-one Khepera soccer on a field of :mod:`robots.soccer.fieldfile` (default the named field
``lci-cup``), refereed by :mod:`robots.soccer.referee`, played by :func:`evaluation.match.play_match`; a tournament
is the round robin of the LCI Cup (Sahota 1993, ch. 4.3, Table 5): every pair of players, each player against
itself too, once per seed, sent to workers as ``ekm compare`` sends its runs (the batch runner,
:mod:`evaluation.batch`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from ekm.api.checks import choice, number, whole
from ekm.api.result import Result
from ekm.errors import InputError, Interrupted

__all__ = ["DEFAULT_PLAYERS", "MatchResult", "TournamentResult", "match", "soccer_field", "tournament"]

_MATCH = "ekm match"
_TOURNAMENT = "ekm tournament"

#: The players of :func:`tournament` when none are given: every player, reactive deliberation at its three levels.
DEFAULT_PLAYERS = "deliberation,deliberation:level=half,deliberation:level=none,samba,ekm,schema"

#: What each restart rule means, as ``ekm match`` prints it (:mod:`robots.soccer.referee`).
RULE_TEXT = {
    "centre": "after every goal the ball goes back on the centre spot and both robots to their kick-off poses",
    "sahota": "play goes on after a goal (the LCI Cup's rule, Sahota 4.3): the side scored upon must clear the ball "
              "from its half before another goal counts",
}


def soccer_field(name_or_path="lci-cup"):
    """The :class:`robots.soccer.fieldfile.SoccerField` of a named field (``lci-cup``) or a field file, every key
    checked; :func:`robots.soccer.fieldfile.save_field` writes one."""
    from robots.soccer.fieldfile import load_field

    return load_field(name_or_path)


def _spec(player, option: str):
    """A :class:`robots.soccer.roster.PlayerSpec` from one spelling (``"deliberation:level=half"``) or a spec."""
    from robots.soccer.roster import PlayerSpec, parse_player

    if isinstance(player, PlayerSpec):
        return player
    if not isinstance(player, str):
        raise InputError(f"{option}: a player is spelt NAME[:k=v,...], got {player!r}")
    return parse_player(player)


def _rule(rule, soccer, prog: str) -> str:
    """``rule``, or the field's own when None."""
    from robots.soccer.referee import RULES

    return soccer.rule if rule is None else choice(rule, RULES, "--rule", prog)


def _robots(robot, players: int, prog: str) -> list:
    """``robot`` — None (the Khepera), one robot for every player, or one per player in order; each a named robot,
    a robot file or a :class:`~robots.params.RobotParams` — as one RobotParams per player."""
    from robots.robotfile import load_robot

    if robot is None or isinstance(robot, (str, Path)) or not hasattr(robot, "__len__"):
        return [load_robot(robot)] * players
    robots = [load_robot(r) for r in robot]
    if len(robots) == 1:
        return robots * players
    if len(robots) != players:
        raise InputError(f"{prog}: --robot: give one robot for every player or one per player ({players}), got "
                         f"{len(robots)}")
    return robots


# ------------------------------------------------------------------------------------------------- one game

@dataclass(frozen=True)
class MatchResult(Result):
    """One game (``ekm match``): ``record``, the :class:`evaluation.match.MatchRecord` (the goals and when they fell,
    the traces of both robots and the ball every 0.128 s), and ``field``, the
    :class:`~robots.soccer.fieldfile.SoccerField` it was played on. ``to_dict()`` is ``ekm match --json``: the
    record's :meth:`~evaluation.match.MatchRecord.outcome` — ``players`` (side 0 first: it defends x = 0),
    ``specs``, ``seed``, ``minutes``, ``rule``, ``goals`` ``[side 0, side 1]``, ``winner`` (0, 1 or None),
    ``goal_times`` ``[[t, side], …]``, ``collisions``, ``ball_in_half_s`` — and ``field`` (its name), with the
    package's version. ``save_plot`` draws the whole game, ``save_animation`` plays it as a GIF.
    """

    record: object = field(repr=False)
    field: object = field(repr=False)

    @property
    def goals(self) -> tuple[int, int]:
        """Goals of (side 0, side 1)."""
        return tuple(self.record.goals)

    @property
    def players(self) -> tuple[str, str]:
        """The two players' labels, side 0 first."""
        return tuple(self.record.players)

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        return {**self.record.outcome(), "field": self.field.name, **provenance()}

    def save_plot(self, path) -> Path:
        """The field, both robots' paths, the ball's and a star at every goal, to a PNG, SVG or PDF (by its suffix)
        at ``path`` (atomically);
        returns the path."""
        from ekm.api.checks import plot_path
        from evaluation.match_plot import save_match

        return save_match(self.record, plot_path(path, "--plot"))

    def save_animation(self, path, progress: bool = False) -> Path:
        """The game as a GIF at ``path`` (atomically); returns the path. ``progress``: a bar of the frames on stderr
        (a ten-minute game's GIF takes about a minute)."""
        from ekm.api.checks import output_path
        from evaluation.match_plot import save_match_animation

        return save_match_animation(self.record, output_path(path, "--gif", ".gif"), progress=progress)


def match(first, second, *, field="lci-cup", minutes: float = 10.0, seed: int = 0, rule: str | None = None,
          robot=None, progress: bool = False) -> MatchResult:
    """Play ``first`` against ``second`` for ``minutes`` of game time on ``field``.

    Parameters
    ----------
    first, second : str or PlayerSpec
        The players, spelt ``NAME[:k=v,...]`` (:func:`ekm.players` lists them): ``"deliberation:level=half"``.
        ``first`` plays side 0 (defends the goal at x = 0); a player may meet itself.
    field : str, path or SoccerField, default "lci-cup"
        A named field or a field file (:mod:`robots.soccer.fieldfile`): the pitch, the ball, the kick-off poses
        and the default rule.
    minutes : float, default 10
        Game time, > 0.
    seed : int, default 0
        The robots' motor and sensor noise (:func:`evaluation.match.robot_seeds`); a game is a pure function of
        its players, field, minutes, rule and seed.
    rule : {"centre", "sahota"}, optional
        The restart after a goal (:data:`RULE_TEXT`); default the field's.
    robot : str, path, RobotParams or a pair of them, optional
        The robot both players play on (a named robot, ``ekm robots``, or a robot file), or one per player,
        ``first``'s first; default the Khepera. Robots of one game share the control period and sub-step.
    progress : bool, default False
        Show a progress bar in game seconds on stderr.

    Returns
    -------
    MatchResult

    Raises
    ------
    ekm.InputError
        An unknown player or parameter, a bad field file, minutes or seed, in one line.
    ekm.Interrupted
        On Ctrl-C in the console script; nothing is written.

    Examples
    --------
    ::

        m = ekm.match("deliberation", "deliberation:level=half", minutes=2, seed=3)
        m.goals, m.to_dict()["goal_times"]
        m.save_plot("match.png")
    """
    from ekm import interrupts
    from evaluation.match import play_match
    from robots.soccer.fieldfile import load_field

    specs = [_spec(first, "first"), _spec(second, "second")]
    minutes = number(minutes, "--minutes", _MATCH, strict=True)
    seed = whole(seed, "--seed", _MATCH, strict=False)
    soccer = load_field(field)
    rule = _rule(rule, soccer, _MATCH)
    robots = _robots(robot, 2, _MATCH)
    period = robots[0].avoid_period  # the game's tick (evaluation.match.play_match): it ends on a whole tick
    total = round(max(1, round(60.0 * minutes / period)) * period, 3)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, unit="game s", desc=f"{specs[0].label} v {specs[1].label}", dynamic_ncols=True,
                   bar_format="{l_bar}{bar}| {n:.1f}/{total:.0f} game s [{elapsed}<{remaining}]")
    now = [0.0]

    def on_tick(t):
        now[0] = t
        interrupts.check()  # a Ctrl-C lost in a JAX callback stops the game at the next tick
        if bar is not None:
            bar.update(min(round(t, 3), total) - bar.n)

    try:
        rec = play_match(specs[0], specs[1], field=soccer.field, ball=soccer.ball, minutes=minutes, seed=seed,
                         rule=rule, kickoff=soccer.kickoff, on_tick=on_tick, robot=robots)
    except KeyboardInterrupt:
        raise Interrupted(f"match stopped at {now[0]:.1f} s of {60.0 * minutes:g} s of game time; nothing was "
                          f"written") from None
    finally:
        if bar is not None:
            bar.close()
    return MatchResult(record=rec, field=soccer)


# ------------------------------------------------------------------------------------------------- round robin

@dataclass(frozen=True)
class TournamentResult(Result):
    """A round robin (``ekm tournament``), the LCI Cup's form (Sahota ch. 4.3, Table 5).

    ``labels``: the players as spelt, in the order given (``specs``: every parameter spelt). ``records``: every
    game's record (:func:`evaluation.match.play_job`: the match outcome plus ``pair``, the indices of the pairing's
    row and column player; a game that could not be played has ``failed`` and no goals), in the order of
    :func:`evaluation.match.tournament_jobs`. ``standings``: per player over its games against the others
    (:func:`evaluation.match.standings`: games, won, drawn, lost, goals for and against, mean goal difference per
    game with its 95 % interval, win rate — a draw is half — with its Wilson interval), best first.
    ``cross_table``: one row per pairing ``i <= j`` (upper triangle and diagonal), ``{row, column, goals: [row's,
    column's] summed over the seeds, games}`` (on the diagonal side 0's goals first; ``goals`` None when no game of
    the pairing was played). ``seeds`` games per pairing with seeds ``seed …``; ``minutes``, ``rule``, ``field`` (its
    name); ``seconds`` the wall time and ``workers`` where the games went. ``to_dict()`` is ``ekm tournament
    --json``; ``save_plot`` draws the standings with their intervals.
    """

    labels: tuple
    specs: tuple
    records: tuple = field(repr=False)
    standings: tuple
    cross_table: tuple
    seeds: int
    seed: int
    minutes: float
    rule: str
    field: str
    seconds: float
    workers: str

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        out = {"players": list(self.labels), "specs": list(self.specs), "standings": list(self.standings),
               "cross_table": list(self.cross_table)}
        failures = [{"players": r["players"], "seed": r["seed"], "reason": r["failed"]}
                    for r in self.records if "failed" in r]
        if failures:
            out["failures"] = failures
        return {**out, "seeds": self.seeds, "seed": self.seed, "minutes": self.minutes, "rule": self.rule,
                "field": self.field, "games": len(self.records), "seconds": round(self.seconds, 2),
                "workers": self.workers, "records": list(self.records), **provenance()}

    def save_plot(self, path) -> Path:
        """Each player's mean goal difference per game and win rate with their 95 % intervals
        (:func:`evaluation.match_plot.save_standings`), to a PNG, SVG or PDF (by its suffix) at ``path``
        (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from evaluation.match_plot import save_standings

        out = plot_path(path, "--plot")
        title = (f"{len(self.records)} games: {self.seeds} seeds a pairing, {self.minutes:g} min each, "
                 f"rule {self.rule}, field {self.field}")
        return save_standings(list(self.standings), out, title=title)


def _field_spelling(given, soccer) -> str:
    """What the workers read the field from: the name or path given, or the file a SoccerField came from."""
    if isinstance(given, (str, Path)):
        return str(given)
    if not soccer.source:
        raise InputError("field: ekm.tournament sends the workers a field file; save the field first "
                         "(robots.soccer.fieldfile.save_field(field, PATH))")
    return soccer.source


def _cross_rows(records, labels) -> list[dict]:
    """Every pairing ``i <= j`` of the upper triangle and the diagonal, with its goals summed over the seeds."""
    from evaluation.match import cross_table

    cells = cross_table(list(records), list(labels))
    rows = []
    for i in range(len(labels)):
        for j in range(i, len(labels)):
            a, b, n = cells.get((i, j), (None, None, 0))
            rows.append({"row": labels[i], "column": labels[j], "goals": None if n == 0 else [a, b], "games": n})
    return rows


def tournament(players=DEFAULT_PLAYERS, *, field="lci-cup", minutes: float = 10.0, seeds: int = 10, seed: int = 0,
               rule: str | None = None, workers: int | None = None, scheduler: str | None = None, out=None,
               resume=None, robot=None, progress: bool = False) -> TournamentResult:
    """Play a round robin in parallel: every pair of ``players`` (and each player against itself) ``seeds`` times,
    and rank the players with 95 % intervals.

    Game k of a pairing runs with seed ``seed + k`` (the same noise for every pairing); in a pairing of two
    different players the one given first plays side 0 on even seeds and side 1 on odd ones, so neither keeps
    a side (:func:`evaluation.match.tournament_jobs`). A game is a pure function of its job, so the result does
    not depend on ``workers`` or ``scheduler``.

    Parameters
    ----------
    players : str or list, default :data:`DEFAULT_PLAYERS`
        ``"P1[:k=v,...],P2,..."`` as :func:`match` spells one player (a ``k=v`` after a comma continues the
        player before it), or a list of spellings or PlayerSpecs; at least two, no label twice.
    field : str, path or SoccerField, default "lci-cup"
        A named field or a field file; the workers read it (a SoccerField must come from a file).
    minutes : float, default 10
        Game time of every game, > 0.
    seeds : int, default 10
        Games per pairing, >= 1.
    seed : int, default 0
        The first game's seed.
    rule : {"centre", "sahota"}, optional
        The restart after a goal; default the field's.
    workers : int, optional
        Local worker processes (default: the machine's cores; 1 plays in this process). They are spawned, so a
        script that calls :func:`tournament` with several needs the ``if __name__ == "__main__":`` guard.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``; needs ``ekm[cluster]``) to send the games to.
    out : path, optional
        Results file (JSON Lines, :mod:`evaluation.results`: a header with the settings, then one line
        ``{"job": …, "outcome": …}`` per game, appended and flushed as it finishes). Must not exist.
    resume : path, optional
        A results file of an interrupted tournament with the same settings, instead of ``out``: its games are
        kept, the missing ones are played and appended, and the result is the uninterrupted tournament's.
    robot : str, path, RobotParams or a list of them, optional
        The robot every player plays on, or one per player in the order of ``players`` (default the Khepera).
        Where the players' robots differ, each label ends in ``@ROBOT`` (``deliberation@worn-wheel``): the same
        player may then enter on two robots.
    progress : bool, default False
        Show a progress bar (games done, failed, time left) on stderr.

    Returns
    -------
    TournamentResult
        A game that could not be played (it raised, its worker kept dying) is a record with ``failed``; it
        never ends the tournament, and the standings and the cross table leave it out.

    Raises
    ------
    ekm.InputError
        Bad players, numbers, field file or rule, an existing ``out``, a ``resume`` file of other settings,
        before any game starts.
    ekm.Interrupted
        On Ctrl-C or SIGTERM in the console script: the workers are stopped and the message says how many
        games the results file keeps and how to finish with ``resume``.

    Examples
    --------
    ::

        t = ekm.tournament("deliberation,deliberation:level=half,schema", minutes=2, seeds=4)
        [(r["player"], r["goal_difference"], r["gd_ci95"]) for r in t.standings]
    """
    import time

    from evaluation.batch import run_batch
    from evaluation.match import TOURNAMENT, play_job, standings, tournament_jobs
    from evaluation.workers import workers_for
    from robots.soccer.fieldfile import load_field
    from robots.soccer.roster import parse_players

    if isinstance(players, str):
        text = players
        specs = parse_players(text)
    else:
        specs = [_spec(p, "players") for p in players]
        text = ",".join(s.label for s in specs)
    if len(specs) < 2:
        raise InputError(f"players {text!r}: a tournament needs at least two players")
    robots = _robots(robot, len(specs), _TOURNAMENT)
    mixed = len({r.fingerprint for r in robots}) > 1 or len({r.name for r in robots}) > 1
    labels = [f"{s.label}@{r.name}" if mixed else s.label for s, r in zip(specs, robots)]
    if len(set(labels)) != len(labels):
        twice = next(x for x in labels if labels.count(x) > 1)
        raise InputError(f"players {text!r}: player {twice!r} is named twice")
    minutes = number(minutes, "--minutes", _TOURNAMENT, strict=True)
    seeds = whole(seeds, "--seeds", _TOURNAMENT, strict=True)
    seed = whole(seed, "--seed", _TOURNAMENT, strict=False)
    if workers is not None:
        workers = whole(workers, "--workers", _TOURNAMENT, strict=True)
    soccer = load_field(field)
    spelling = _field_spelling(field, soccer)
    rule = _rule(rule, soccer, _TOURNAMENT)
    job_list = tournament_jobs(specs, range(seed, seed + seeds), minutes, rule, spelling, robots, labels)
    settings = json.loads(json.dumps({  # as the results file holds them (tuples become lists)
        "tournament": [str(s) for s in specs], "labels": labels, "seeds": seeds, "seed": seed, "minutes": minutes,
        "rule": rule, "field": spelling,
        "robots": [{"name": r.name, "fingerprint": r.fingerprint} for r in robots], "ekm_version": _version()}))
    pool = workers_for(play_job, workers, scheduler)
    t0 = time.perf_counter()
    records = run_batch(TOURNAMENT, job_list, pool, settings, out=out, resume=resume, progress=progress)
    seconds = time.perf_counter() - t0
    return TournamentResult(labels=tuple(labels), specs=tuple(str(s) for s in specs), records=tuple(records),
                            standings=tuple(standings(records, labels)), cross_table=tuple(_cross_rows(records, labels)),
                            seeds=seeds, seed=seed, minutes=minutes, rule=rule, field=soccer.name, seconds=seconds,
                            workers=pool.where)


def _version() -> str:
    from ekm import __version__

    return __version__
