"""Soccer games and the round robin (evaluation.match): a game is a pure function of its seed, its record adds up,
the two sides are mirror images of each other, the round robin's pairings and sides, the standings and the
cross table of hand-made records, and a game that cannot be played is a record, never an exception.

Besides the real players (``schema``, ``ekm``) the tests register tiny fake players (robots.registry) for the
length of a test: ``t_constant`` always sends the same wheel command, ``t_seek`` drives to a point of its own
frame and stops there. With slip-free robots (actuator_noise 0) their games are worked out by hand."""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pytest

from evaluation.match import (GameJob, cross_table, play_job, play_match, robot_seeds, standings,
                              tournament_jobs)
from robots.controllers.base import Controller
from robots.params import KHEPERA
from robots.soccer.field import Field
from robots.soccer.roster import PLAYERS, PlayerSpec, Player, parse_players

C = KHEPERA.max_wheel_speed
QUIET = dataclasses.replace(KHEPERA, actuator_noise=0.0)  # no slip: both sides' paths are exact
SMOOTH = dataclasses.replace(QUIET, speed_unit=0.0)  # nor any rounding of the commands to 8 mm/s
F = Field()  # 1.2 m × 0.8 m, mouth y in [0.28, 0.52]


# -------------------------------------------------------------------------------------------- fake players

@dataclass(frozen=True)
class ConstantParams:
    left: float = 0.064
    right: float = 0.096


def build_constant(params, field=F, robot=KHEPERA, spec="t_constant"):
    command = np.array([params.left, params.right])
    return Controller(name="t_constant", spec=spec, sensors=robot.long_range, init=lambda: 0,
                      step=lambda state, play: (state, command), params=params, robot=robot)


@dataclass(frozen=True)
class SeekParams:
    x: float = 0.45
    y: float = 0.6


def build_seek(params, field=F, robot=KHEPERA, spec="t_seek"):
    """Turn towards (x, y) of the player's own frame while driving at 0.08 m/s; stop within 2 cm of it."""
    def step(state, play):
        x, y, theta = (float(v) for v in play.pose)
        dx, dy = params.x - x, params.y - y
        if math.hypot(dx, dy) < 0.02:
            return state, np.zeros(2)
        error = math.remainder(math.atan2(dy, dx) - theta, 2 * math.pi)
        turn = max(-0.06, min(0.06, 0.1 * error))
        return state, np.array([0.08 - turn, 0.08 + turn])

    return Controller(name="t_seek", spec=spec, sensors=robot.long_range, init=lambda: 0, step=step,
                      params=params, robot=robot)


FAKES = {"t_constant": Player("t_constant", ConstantParams, build_constant, "the same command, always"),
         "t_seek": Player("t_seek", SeekParams, build_seek, "to a point of its own frame")}


@pytest.fixture
def fakes(registries):
    """The players' registry with the fake players added, for this test only."""
    for player in FAKES.values():
        PLAYERS.register(player)


def constant(left, right) -> PlayerSpec:
    return PlayerSpec("t_constant", ConstantParams(left, right))


# ------------------------------------------------------------------------------------------------ one game

def test_a_game_is_a_pure_function_of_its_seed():
    a = play_match("ekm", "schema", minutes=0.1, seed=3)  # 47 ticks, 6 s
    b = play_match("ekm", "schema", minutes=0.1, seed=3)
    c = play_match("ekm", "schema", minutes=0.1, seed=4)
    assert a.poses.shape == (48, 2, 3) and a.ball.shape == (48, 2) and a.times.shape == (48,)  # + the start
    for name in ("poses", "ball", "times"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.outcome() == b.outcome()
    assert not np.array_equal(a.poses, c.poses)  # another seed: other slip, another game
    assert robot_seeds(3) == robot_seeds(3) and len(set(robot_seeds(3) + robot_seeds(4))) == 4


def test_the_outcome_holds_every_key_and_each_goal_once(fakes):
    # side 0 drives straight at full speed from its kick-off (0.3, 0.4, 0) through the ball on the centre spot
    # into side 1's goal; side 1 stands aside at (0.9, 0.15). Each push sends the ball off at 0.262 m/s; rolling
    # friction (0.15 m/s²) brings it back to the robot within 2 × 0.102 / 0.15 = 1.36 s, at most 0.035 m ahead
    # of its nose. So the ball crosses x = 1.2 when the robot's centre is at 1.2 − 0.045 − [0, 0.035], after
    # (0.82 … 0.855) / 0.16 s plus the lag's 0.03 s, plus up to a sub-step (the crossing is seen after the
    # step) and 3 ms for the 0.5 mm the pushed ball rides into the robot's nose: t1 in [5.15, 5.40] s.
    # Then the kick-off puts everything back as it was at t = 0, at rest, at the end of the goal's period,
    # P = ceil(t1 / 0.128) × 0.128: the game repeats itself, goal k at t1 + (k − 1) P. In 30 s: 5 goals.
    record = play_match(constant(C, C), constant(0.0, 0.0), minutes=0.5, seed=0, robot=QUIET,
                        kickoff=[(0.3, 0.4, 0.0), (0.9, 0.15, math.pi)])
    out = record.outcome()
    assert set(out) == {"players", "specs", "seed", "minutes", "rule", "goals", "winner", "goal_times",
                        "collisions", "ball_in_half_s", "restarts", "robots", "robot_fingerprints"}
    assert out["robots"] == ["khepera", "khepera"]  # QUIET is the Khepera without noise, under its name
    assert out["players"] == ["t_constant:left=0.16,right=0.16", "t_constant:left=0,right=0"]  # labels, side 0 first
    assert (out["seed"], out["minutes"], out["rule"], out["winner"]) == (0, 0.5, "centre", 0)
    assert out["restarts"] == 0  # no dead ball: the goals' kick-offs are not restarts
    times = [t for t, _ in out["goal_times"]]
    assert out["goals"] == [len(times), 0] == [5, 0]
    assert [s for _, s in out["goal_times"]] == [0] * 5
    t1 = times[0]
    assert 5.15 <= t1 <= 5.40  # measured 5.392
    period = math.ceil(t1 / 0.128) * 0.128
    assert times == pytest.approx([t1 + k * period for k in range(5)], abs=1e-9)
    # the ball was in side 1's half from the first push to each goal, in side 0's half never
    assert out["ball_in_half_s"][0] == 0.0 and out["ball_in_half_s"][1] > 5 * (t1 - 1.7)


@pytest.mark.parametrize("spec, robot", [(constant(0.064, 0.096), QUIET), (PlayerSpec("t_seek", SeekParams()), SMOOTH)],
                         ids=["same-command", "seek-a-point"])
def test_side_1_plays_the_mirror_image_of_side_0(fakes, spec, robot):
    # Both robots start from their kick-offs, (0.3, 0.4, 0) and its image (0.9, 0.4, π), and both get the same
    # player. "same-command": an arc to the left of radius 0.08 / (0.032 / 0.053) = 0.1325 m, within x 0.17 …
    # 0.43 m and y 0.4 … 0.67 m of its own half (side 1's mirrored). "seek-a-point": to (0.45, 0.6) of its own
    # frame, side 1's is (0.75, 0.2) on the field. Neither meets the ball, a wall or the other. 12 s: short of
    # the 15 s of a dead ball.
    record = play_match(spec, spec, minutes=0.2, seed=1, robot=robot)
    zero, one = record.poses[:, 0], record.poses[:, 1]
    # the image of (x, y, θ) is (1.2 − x, 0.8 − y, θ + π); float32 observations leave 1e-6 m room
    np.testing.assert_allclose(one[:, 0], 1.2 - zero[:, 0], rtol=0, atol=1e-6)
    np.testing.assert_allclose(one[:, 1], 0.8 - zero[:, 1], rtol=0, atol=1e-6)
    assert np.abs(np.remainder(one[:, 2] - zero[:, 2], 2 * math.pi) - math.pi).max() < 1e-5  # θ1 − θ0 = π
    assert np.ptp(zero[:, 1]) > 0.15  # it really went somewhere (0.265 m across the arc; 0.2 m up to the point)
    if spec.name == "t_seek":
        np.testing.assert_allclose(zero[-1, :2], [0.45, 0.6], atol=0.02)
    np.testing.assert_array_equal(record.ball[-1], [0.6, 0.4])
    assert record.goals == (0, 0) and record.collisions == (0, 0)


# ------------------------------------------------------------------------------------------ the round robin

def test_the_round_robin_pairs_everyone_with_everyone_and_themselves_and_alternates_sides():
    specs = parse_players("ekm,schema,schema:push=0.15")
    labels = ["ekm", "schema", "schema:push=0.15"]
    assert [s.label for s in specs] == labels
    jobs = tournament_jobs(specs, [0, 1, 2], minutes=2.0, rule="sahota")
    pairs = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]  # 6 pairings of 3 players, self-play included
    assert [j.pair for j in jobs] == [p for p in pairs for _ in range(3)]
    assert [j.seed for j in jobs] == [0, 1, 2] * 6
    assert all(j.minutes == 2.0 and j.rule == "sahota" and j.field_path is None for j in jobs)
    for j in jobs:
        row, col = j.pair
        swap = row != col and j.seed % 2 == 1  # the row player takes side 1 on odd seeds
        first, second = (col, row) if swap else (row, col)
        assert (j.first, j.second) == (str(specs[first]), str(specs[second]))
        assert j.labels == (labels[first], labels[second])
    # e.g. ekm against schema on seed 1: schema kicks off from side 0
    assert jobs[4].labels == ("schema", "ekm") and jobs[3].labels == jobs[5].labels == ("ekm", "schema")


def record(pair, seed, goals):
    """A game's record as play_job returns it, cut to what the summaries read (goals: side 0 first)."""
    return {"pair": list(pair), "seed": seed, "goals": goals}


# Players A, B, C (0, 1, 2). Goals side 0 first; the row player of (i, j) is side 0 on even seeds, side 1 on odd.
RECORDS = [
    record((0, 1), 0, [2, 1]),  # A 2 : 1 B      (A side 0)
    record((0, 1), 1, [3, 0]),  # B 3 : 0 A      (A side 1)
    record((0, 1), 2, [1, 1]),  # A 1 : 1 B
    record((0, 2), 0, [0, 2]),  # A 0 : 2 C
    record((0, 2), 1, [0, 1]),  # C 0 : 1 A      (A side 1)
    record((1, 2), 0, None) | {"failed": "no such field"},  # left out everywhere
    record((1, 2), 1, [4, 2]),  # C 4 : 2 B      (B side 1)
    record((0, 0), 0, [5, 0]),  # A against A: in the cross table only
    record((1, 1), 1, [1, 2]),  # B against B, odd seed: still side 0 first
]


def test_standings_of_hand_made_records():
    rows = {r["player"]: r for r in standings(RECORDS, ["A", "B", "C"])}
    # A: 2:1, 0:3, 1:1, 0:2, 1:0 → differences +1 −3 0 −2 +1, mean −0.6, sample sd 1.8166, half-width
    # 1.96 × 1.8166 / √5 = 1.5923; won 2 drawn 1 lost 2: (2 + ½) / 5 = 0.5, Wilson of 2.5 / 5: 0.5 ± 0.3296
    assert {k: rows["A"][k] for k in ("games", "won", "drawn", "lost", "goals_for", "goals_against")} == \
        {"games": 5, "won": 2, "drawn": 1, "lost": 2, "goals_for": 4, "goals_against": 7}
    assert rows["A"]["goal_difference"] == -0.6 and rows["A"]["gd_ci95"] == [-2.192, 0.992]
    assert rows["A"]["win_rate"] == 0.5 and rows["A"]["win_ci95"] == [0.17, 0.83]
    # B: 1:2, 3:0, 1:1, 2:4 → −1 +3 0 −2, mean 0, sd 2.1602, half 1.96 × 2.1602 / 2 = 2.1170;
    # 1 won, 1 drawn: 1.5 / 4 = 0.375; Wilson of 1.5 / 4: centre 0.4362, half 0.3443
    assert (rows["B"]["games"], rows["B"]["won"], rows["B"]["drawn"], rows["B"]["lost"]) == (4, 1, 1, 2)
    assert (rows["B"]["goals_for"], rows["B"]["goals_against"]) == (7, 7)
    assert rows["B"]["goal_difference"] == 0.0 and rows["B"]["gd_ci95"] == [-2.117, 2.117]
    assert rows["B"]["win_rate"] == 0.375 and rows["B"]["win_ci95"] == [0.092, 0.781]
    # C: 2:0, 0:1, 4:2 → +2 −1 +2, mean 1, sd √3, half 1.96 × √3 / √3 = 1.96; 2 of 3: Wilson 0.5731 ± 0.3654
    assert (rows["C"]["games"], rows["C"]["won"], rows["C"]["drawn"], rows["C"]["lost"]) == (3, 2, 0, 1)
    assert (rows["C"]["goals_for"], rows["C"]["goals_against"]) == (6, 3)
    assert rows["C"]["goal_difference"] == 1.0 and rows["C"]["gd_ci95"] == [-0.96, 2.96]
    assert rows["C"]["win_rate"] == 0.667 and rows["C"]["win_ci95"] == [0.208, 0.939]
    assert [r["player"] for r in standings(RECORDS, ["A", "B", "C"])] == ["C", "B", "A"]  # best first
    # every game counted twice, once from each side: the goal differences sum to zero
    assert sum(r["goal_difference"] * r["games"] for r in rows.values()) == pytest.approx(0.0)


def test_a_player_without_games_has_no_rates():
    (row,) = standings([], ["A"])
    assert row["games"] == 0 and row["goal_difference"] is None and row["win_rate"] is None
    assert row["gd_ci95"] is None and row["win_ci95"] is None


def test_cross_table_of_hand_made_records():
    table = cross_table(RECORDS, ["A", "B", "C"])
    # (A, B): 2+0+1 = 3 for A, 1+3+1 = 5 for B in 3 games; (A, C): 0+1 : 2+0 in 2; (B, C): 2 : 4 in 1 (one
    # failed); self-play side 0 first
    assert table == {(0, 1): (3, 5, 3), (0, 2): (1, 2, 2), (1, 2): (2, 4, 1), (0, 0): (5, 0, 1), (1, 1): (1, 2, 1)}
    # every goal of every game that was played is in the table once: 3+3+2+2+1+6+5+3 = 25
    assert sum(a + b for a, b, _ in table.values()) == sum(sum(r["goals"]) for r in RECORDS if r["goals"]) == 25


def test_a_played_job_is_its_games_outcome_with_its_pair():
    job = GameJob("schema", "schema", ("schema", "schema"), (1, 1), 2, 0.05, "centre")
    out = play_job(job)
    assert "failed" not in out and out["pair"] == [1, 1] and out["players"] == ["schema", "schema"]
    assert out == {**play_match("schema", "schema", minutes=0.05, seed=2).outcome(), "pair": [1, 1]}


@pytest.mark.parametrize("first, minutes, rule, field_path, reason", [
    ("schema:pace=3", 1.0, "centre", None, "pace"),  # a parameter schema does not have
    ("nobody", 1.0, "centre", None, "nobody"),
    ("schema", -1.0, "centre", None, "minutes"),
    ("schema", 1.0, "offside", None, "rule"),
    ("schema", 1.0, "centre", "/nonexistent/field.json", ""),
])
def test_a_job_that_cannot_be_played_is_a_failed_record_not_an_exception(first, minutes, rule, field_path, reason):
    job = GameJob(first, "schema", ("x", "schema"), (0, 1), 3, minutes, rule, field_path)
    out = play_job(job)
    assert reason in out["failed"] and "\n" not in out["failed"]
    assert out["goals"] is None and out["winner"] is None and out["pair"] == [0, 1]
    assert out["players"] == ["x", "schema"] and out["seed"] == 3
    assert standings([out], ["x", "schema"])[0]["games"] == 0 and cross_table([out], ["x", "schema"]) == {}
