"""Soccer games and the round robin: two players on a pitch, refereed; every pairing over seeds (imperative shell).

:func:`play_match` is one game: two players (:mod:`robots.soccer.roster`) on a :class:`robots.soccer.game.Game`.
Every 0.128 s tick each robot senses (its IR ring), each player is handed the game in its own frame
(:class:`robots.soccer.play.Play`, :func:`~robots.soccer.play.own_frame`: it always attacks the goal at
x = length) and returns its wheel speeds, and the game steps both robots and the ball one period, refereeing
every 16 ms sub-step. The player named first plays side 0 (defends x = 0). A game is a pure function of
(players, field, ball, minutes, rule, seed): the seed gives each robot its own motor and sensor noise streams
(``SeedSequence(seed).spawn``), the players are pure, and nothing else is random.

:func:`tournament_jobs` lays out a round robin as the LCI Cup played it (Sahota ch. 4.3, Table 5): every pair
of players once per seed, each player against itself too; in a pairing of two different players the first
plays side 0 on even seeds and side 1 on odd ones, so neither keeps a side. :func:`play_job` plays one game
in a worker (:mod:`evaluation.workers`: this process, local processes or Dask) and never raises: a game that
cannot be played is a record with ``failed``. :func:`standings` and :func:`cross_table` summarise: per player
its mean goal difference per game with a 95 % interval over its games, and its win rate with a Wilson
interval; per pairing the goals summed over seeds in Table 5's form.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as _f

import numpy as np

from evaluation.batch import Batch
from robots.params import KHEPERA
from robots.soccer.ball import BallParams
from robots.soccer.field import Field


@dataclass
class MatchRecord:
    """One game: who played (``players``: the two labels, side 0 first; ``specs``: their full spellings), the
    settings, the goals and when they fell, and the traces the plots draw (one row per 0.128 s tick: ``times``
    ``(T,)``, ``poses`` ``(T, 2, 3)``, ``ball`` ``(T, 2)``)."""

    players: tuple[str, str]
    specs: tuple[str, str]
    seed: int
    minutes: float
    rule: str
    field: Field = _f(default_factory=Field)
    goals: tuple[int, int] = (0, 0)
    goal_log: list = _f(default_factory=list)  # (t, side) of every counted goal
    collisions: tuple[int, int] = (0, 0)
    ball_in_half_s: tuple[float, float] = (0.0, 0.0)  # s the ball spent in side 0's and side 1's half
    restarts: list = _f(default_factory=list)  # t of every dead-ball restart (robots.soccer.game)
    times: np.ndarray = _f(default_factory=lambda: np.zeros(0))
    poses: np.ndarray = _f(default_factory=lambda: np.zeros((0, 2, 3)))
    ball: np.ndarray = _f(default_factory=lambda: np.zeros((0, 2)))
    robots: tuple[str, str] = ("khepera", "khepera")  # the robot each side played on (robots.robotfile)
    robot_fingerprints: tuple[str, str] = (KHEPERA.fingerprint, KHEPERA.fingerprint)

    def outcome(self) -> dict:
        """The ``ekm match --json`` record: ``players`` (side 0 first), ``specs``, ``seed``, ``minutes``, ``rule``,
        ``goals`` ``[side 0, side 1]``, ``winner`` (0, 1 or None for a draw), ``goal_times`` ``[[t, side], …]``,
        ``collisions`` (contact episodes of each robot with walls or the other robot), ``ball_in_half_s``
        (s the ball spent in each side's own half: a large share in your half is pressure on your goal) and
        ``restarts`` (dead-ball restarts, :mod:`robots.soccer.game`), ``robots`` and ``robot_fingerprints`` (what
        each side played on)."""
        a, b = self.goals
        return {"players": list(self.players), "specs": list(self.specs), "seed": self.seed, "minutes": self.minutes,
                "rule": self.rule, "goals": [a, b], "winner": 0 if a > b else 1 if b > a else None,
                "goal_times": [[round(t, 3), s] for t, s in self.goal_log], "collisions": list(self.collisions),
                "ball_in_half_s": [round(s, 3) for s in self.ball_in_half_s], "restarts": len(self.restarts),
                "robots": list(self.robots), "robot_fingerprints": list(self.robot_fingerprints)}


def robot_seeds(seed: int) -> list[int]:
    """The two robots' noise seeds of game ``seed``: independent streams (``numpy.random.SeedSequence.spawn``)."""
    return [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(int(seed)).spawn(2)]


def play_match(first, second, *, field: Field = Field(), ball: BallParams = BallParams(), minutes: float = 10.0,
               seed: int = 0, rule: str = "centre", robot=KHEPERA, on_tick=None, kickoff=None) -> MatchRecord:
    """Play ``first`` (side 0) against ``second`` (side 1) for ``minutes`` of game time (module docstring).

    ``first``, ``second``: :class:`robots.soccer.roster.PlayerSpec` (or their spellings, ``"deliberation:level=half"``).
    ``robot``: the :class:`~robots.params.RobotParams` both play on, or a pair, side 0's first
    (:func:`robots.soccer.game.robot_list`). ``on_tick(t)`` is called after every tick (progress bars). Bad input
    raises :class:`ekm.errors.InputError`.
    """
    from ekm.errors import InputError
    from robots.soccer.game import Game, robot_list
    from robots.soccer.play import Play, own_frame
    from robots.soccer.roster import parse_player

    specs = [parse_player(p) if isinstance(p, str) else p for p in (first, second)]
    if not (isinstance(minutes, (int, float)) and math.isfinite(minutes) and minutes > 0):
        raise InputError(f"match: minutes must be a positive number, got {minutes!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"match: seed must be a non-negative integer, got {seed!r}")
    robots = robot_list(robot, 2)
    controllers = [s.build(field, r) for s, r in zip(specs, robots)]
    game = Game(field, ball, 2, robot_seeds(seed), robots, kickoff=kickoff, rule=rule)
    states = [c.init() for c in controllers]
    period, dt = robots[0].avoid_period, robots[0].dt
    ticks = max(1, round(minutes * 60.0 / period))
    f32 = np.float32
    times = np.empty(ticks + 1)
    poses = np.empty((ticks + 1, 2, 3))
    balls = np.empty((ticks + 1, 2))
    in_half = [0.0, 0.0]
    mid = 0.5 * field.length
    for k in range(ticks + 1):
        now = [r.pose for r in game.robots]
        times[k], poses[k], balls[k] = game.t, now, game.pitch.ball_position
        if k == ticks:
            break
        vel = [tuple(r.body.velocity) for r in game.robots]
        b = np.concatenate([game.pitch.ball_position, game.pitch.ball_velocity])
        commands = []
        for i, (c, r) in enumerate(zip(controllers, game.robots)):
            j = 1 - i
            other = np.array([now[j][0], now[j][1], now[j][2], vel[j][0], vel[j][1]])
            pose, v, bb, opp = own_frame(i, field, now[i], vel[i], b, other)
            play = Play(t=f32(game.t), ir=r.sense(c.sensors).astype(f32), pose=pose.astype(f32),
                        velocity=v.astype(f32), ball=bb.astype(f32), opponent=opp.astype(f32))
            states[i], command = c.step(states[i], play)
            commands.append(np.asarray(command, dtype=float))
        game.step(commands, period)
        bx = game.ball_trace[:, 0]
        in_half[0] += float(np.count_nonzero(bx < mid)) * dt
        in_half[1] += float(np.count_nonzero(bx > mid)) * dt
        if on_tick is not None:
            on_tick(game.t)
    return MatchRecord(players=(specs[0].label, specs[1].label), specs=(str(specs[0]), str(specs[1])), seed=int(seed),
                       minutes=float(minutes), rule=rule, field=field, goals=game.score.goals,
                       goal_log=list(game.goals), collisions=tuple(r.collisions for r in game.robots),
                       ball_in_half_s=(in_half[0], in_half[1]), restarts=list(game.restarts), times=times, poses=poses,
                       ball=balls, robots=tuple(r.name for r in robots),
                       robot_fingerprints=tuple(r.fingerprint for r in robots))


# --------------------------------------------------------------------------------------------- the round robin
@dataclass(frozen=True)
class GameJob:
    """One game of a round robin, as plain values (it pickles to any process or machine): the two players'
    spellings and labels (side 0 first), which pairing (``pair``: indices into the players, row first) and
    settings; ``field_path``: a field file, or None for the default field; ``added``: what was registered in the
    parent process (:func:`robots.registry.added_here`: a player of a script), for the worker to register too;
    ``robots``: each side's robot as its file's text (:func:`robots.robotfile.robot_json`), None for the Khepera."""

    first: str
    second: str
    labels: tuple[str, str]
    pair: tuple[int, int]
    seed: int
    minutes: float
    rule: str
    field_path: str | None = None
    added: tuple = ()
    robots: tuple = (None, None)

    def identity(self) -> dict:
        """The game as its results-file line names it (:mod:`evaluation.results`)."""
        from ekm import __version__
        from robots.robotfile import robot_from_json

        return {"first": self.first, "second": self.second, "labels": list(self.labels), "pair": list(self.pair),
                "seed": self.seed, "minutes": self.minutes, "rule": self.rule, "field_path": self.field_path,
                "robots": [robot_from_json(r).name for r in self.robots], "ekm_version": __version__}


def tournament_jobs(specs, seeds, minutes: float, rule: str = "centre", field_path: str | None = None,
                    robots=None, labels=None) -> list[GameJob]:
    """Every pairing ``(i, j)``, ``i <= j`` (self-play included), once per seed in ``seeds``; for ``i < j`` player i
    plays side 0 on even seeds and side 1 on odd ones. ``robots``: each player's
    :class:`~robots.params.RobotParams` (None: all on the Khepera); ``labels``: the players' labels (default
    their spellings')."""
    from robots.registry import added_here
    from robots.robotfile import robot_json

    added = added_here()
    labels = [s.label for s in specs] if labels is None else list(labels)
    texts = [None] * len(specs) if robots is None else [robot_json(r) for r in robots]
    jobs = []
    for i, a in enumerate(specs):
        for j in range(i, len(specs)):
            for s in seeds:
                swap = i != j and s % 2 == 1
                one, two = (j, i) if swap else (i, j)
                jobs.append(GameJob(str(specs[one]), str(specs[two]), (labels[one], labels[two]), (i, j), int(s),
                                    float(minutes), rule, field_path, added, (texts[one], texts[two])))
    return jobs


def play_job(job: GameJob) -> dict:
    """Play one game of a round robin: its :meth:`MatchRecord.outcome` plus ``pair``; never raises — a game that
    cannot be played is a record with ``failed`` (the reason in one line) and no goals."""
    from ekm.errors import InputError
    from robots.registry import adopt
    from robots.robotfile import robot_from_json

    try:
        adopt(job.added)
        field, ball, kickoff = (Field(), BallParams(), None) if job.field_path is None else _field(job.field_path)
        rec = play_match(job.first, job.second, field=field, ball=ball, minutes=job.minutes, seed=job.seed,
                         rule=job.rule, kickoff=kickoff, robot=[robot_from_json(r) for r in job.robots])
        out = rec.outcome()
    except Exception as exc:
        text = str(exc).splitlines()[0] if str(exc) else ""
        reason = text if isinstance(exc, InputError) else f"{type(exc).__name__}: {text}".rstrip(": ")
        out = game_failed(job, reason)
    out["players"] = list(job.labels)
    out["pair"] = list(job.pair)
    return out


def game_key(record: dict) -> tuple[int, int, int]:
    """A game's place in its round robin, from its record: the pairing (row, column) and the seed."""
    i, j = record["pair"]
    return (int(i), int(j), int(record["seed"]))


def job_key(job: GameJob) -> tuple[int, int, int]:
    """The :func:`game_key` the record of ``job`` will have."""
    return (job.pair[0], job.pair[1], job.seed)


def game_failed(job: GameJob, reason: str) -> dict:
    """The record of a game that could not be played."""
    return {"players": list(job.labels), "specs": [job.first, job.second], "seed": job.seed, "minutes": job.minutes,
            "rule": job.rule, "goals": None, "winner": None, "goal_times": [], "collisions": None,
            "ball_in_half_s": None, "restarts": None, "pair": list(job.pair), "failed": reason}


#: How the batch runner (:mod:`evaluation.batch`) names, keys and fails a tournament's games.
TOURNAMENT = Batch("tournament", "game", "playing", job_key=job_key, record_key=game_key, identity=GameJob.identity,
                   failed=game_failed)


def _field(path: str):
    """The pitch, the ball and the kick-off poses of a field file or named field (robots.soccer.fieldfile)."""
    from robots.soccer.fieldfile import load_field

    f = load_field(path)
    return f.field, f.ball, f.kickoff


def _for(label_index: int, r: dict) -> tuple[int, int] | None:
    """(goals for, goals against) of the player with index ``label_index`` in record ``r`` (None: not in it,
    or self-play, or failed)."""
    i, j = r["pair"]
    if r.get("goals") is None or i == j or label_index not in (i, j):
        return None
    first_is_i = _side_of_row(r) == 0
    row_goals = r["goals"][0] if first_is_i else r["goals"][1]
    col_goals = r["goals"][1] if first_is_i else r["goals"][0]
    return (row_goals, col_goals) if label_index == i else (col_goals, row_goals)


def _side_of_row(r: dict) -> int:
    """Which side the pairing's row player played in ``r``: 0 on even seeds, 1 on odd (:func:`tournament_jobs`)."""
    return r["seed"] % 2


def standings(records: list[dict], labels: list[str]) -> list[dict]:
    """Per player, over its games against the others (self-play left out): ``games``, ``won``, ``drawn``,
    ``lost``, ``goals_for``, ``goals_against``, ``goal_difference`` (mean per game) with ``gd_ci95`` (its 95 %
    interval, normal approximation), ``win_rate`` (a draw is half a win) with ``win_ci95`` (Wilson, on the
    wins plus half the draws), sorted best first by mean goal difference."""
    from evaluation.compare import wilson

    rows = []
    for k, label in enumerate(labels):
        games = [g for g in (_for(k, r) for r in records) if g is not None]
        diffs = np.array([a - b for a, b in games], float)
        won, drawn = sum(a > b for a, b in games), sum(a == b for a, b in games)
        n = len(games)
        mean = float(diffs.mean()) if n else None
        half = 1.959964 * float(diffs.std(ddof=1)) / math.sqrt(n) if n > 1 else 0.0
        points = won + 0.5 * drawn
        lo, hi = wilson(points, n) if n else (None, None)  # a draw is half a success, as in win_rate
        rows.append({"player": label, "games": n, "won": won, "drawn": drawn, "lost": n - won - drawn,
                     "goals_for": sum(a for a, _ in games), "goals_against": sum(b for _, b in games),
                     "goal_difference": None if mean is None else round(mean, 3),
                     "gd_ci95": None if mean is None else [round(mean - half, 3), round(mean + half, 3)],
                     "win_rate": round(points / n, 3) if n else None,
                     "win_ci95": None if lo is None else [round(lo, 3), round(hi, 3)]})
    return sorted(rows, key=lambda r: -math.inf if r["goal_difference"] is None else -r["goal_difference"])


def cross_table(records: list[dict], labels: list[str]) -> dict:
    """Table 5's form: ``{(i, j): (goals of i, goals of j, games)}`` summed over seeds for every pairing
    ``i <= j`` (for i == j, side 0's goals first)."""
    out = {}
    for r in records:
        if r.get("goals") is None:
            continue
        i, j = r["pair"]
        a, b = r["goals"] if i == j or _side_of_row(r) == 0 else r["goals"][::-1]
        ga, gb, n = out.get((i, j), (0, 0, 0))
        out[(i, j)] = (ga + a, gb + b, n + 1)
    return out
