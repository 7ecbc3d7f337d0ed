"""``ekm match``, ``ekm tournament`` and ``ekm players`` from the command line (and the API under them): a short
game prints its score, goals and rule and its JSON has every key; a round robin of two players over two seeds is
3 pairings x 2 = 6 games with its cross table and standings; every bad input is one line and exit status 2 before
any game starts; a player of one's own — the example package ``examples/chaser``, through its entry point — plays
in ``ekm tournament``.

The games here use the ``schema`` and ``ekm`` players (their steps compile once in this test file's process)."""

import json
import os
import re
import subprocess
import sys

import pytest

from evaluation.match import GameJob
from robots.soccer.fieldfile import SoccerField, save_field

MATCH_KEYS = {"players", "specs", "seed", "minutes", "rule", "goals", "winner", "goal_times", "collisions",
              "ball_in_half_s", "field", "robots", "robot_fingerprints", "ekm_version"}
TOURNAMENT = ["tournament", "schema,ekm", "--seeds", "2", "--minutes", "0.1", "--workers", "1"]


def test_a_short_match_prints_the_score_line_the_goals_and_the_rule(cli):
    code, out, err = cli("match", "schema", "ekm", "--minutes", "0.2")
    lines = out.splitlines()
    assert code == 0 and err == ""
    assert re.fullmatch(r"schema \d+ - \d+ ekm +\(lci-cup, 0\.2 min, seed 0; schema plays side 0, defending x = 0\)",
                        lines[0])
    assert lines[1].startswith("  goals: ")
    assert lines[2].startswith("  rule centre: after every goal the ball goes back on the centre spot")


def test_the_match_json_has_every_key_and_the_rule_can_be_sahota(cli):
    code, out, _ = cli("match", "schema", "ekm", "--minutes", "0.2", "--rule", "sahota", "--seed", "3", "--json")
    doc = json.loads(out)
    assert code == 0 and MATCH_KEYS <= set(doc)
    assert doc["players"] == ["schema", "ekm"] and doc["rule"] == "sahota" and doc["seed"] == 3
    assert doc["minutes"] == 0.2 and doc["field"] == "lci-cup" and len(doc["goals"]) == 2
    assert doc["winner"] == (None if doc["goals"][0] == doc["goals"][1] else int(doc["goals"][1] > doc["goals"][0]))


def test_a_match_draws_its_plot_and_its_gif(cli, tmp_path):
    plot, gif = tmp_path / "out" / "m.png", tmp_path / "m.gif"
    plot.parent.mkdir()  # an output's directory must exist (issue 34: --out never makes directories)
    code, out, _ = cli("match", "ekm", "schema", "--minutes", "0.1", "--plot", plot, "--gif", gif)
    assert code == 0 and f"written to {plot}" in out and f"written to {gif}" in out
    assert plot.read_bytes()[:4] == b"\x89PNG" and gif.read_bytes()[:3] == b"GIF"
    assert sorted(p.name for p in tmp_path.rglob("*") if p.is_file()) == ["m.gif", "m.png"]  # no temporary files


def test_a_field_file_sets_the_kick_off_and_the_rule(tmp_path):
    import ekm

    path = save_field(SoccerField(name="wide", kickoff=((0.2, 0.2, 0.0), (1.0, 0.6, 3.0)), rule="sahota"),
                      tmp_path / "wide.json")
    m = ekm.match("schema", "ekm", field=path, minutes=0.01)
    assert m.record.poses[0].ravel().tolist() == pytest.approx([0.2, 0.2, 0.0, 1.0, 0.6, 3.0])
    assert m.to_dict()["rule"] == "sahota" and m.to_dict()["field"] == "wide"
    assert ekm.match("schema", "ekm", field=path, minutes=0.01, rule="centre").record.rule == "centre"


def test_a_tournament_of_two_players_over_two_seeds_is_six_games_and_resumes_to_the_same(cli, tmp_path):
    """Six games written to --out; the file cut after three games and half a line (a crash); --resume plays
    the three missing games and gives the uninterrupted tournament's JSON."""
    results, plot = tmp_path / "cup.jsonl", tmp_path / "cup.png"
    code, out, err = cli(*TOURNAMENT, "--json", "--out", results, "--plot", plot)
    doc = json.loads(out)
    assert code == 0 and err == ""
    assert doc["games"] == 6 and len(doc["records"]) == 6 and doc["players"] == ["schema", "ekm"]
    assert [(r["pair"], r["seed"], r["players"]) for r in doc["records"]] == [
        ([0, 0], 0, ["schema", "schema"]), ([0, 0], 1, ["schema", "schema"]),
        ([0, 1], 0, ["schema", "ekm"]), ([0, 1], 1, ["ekm", "schema"]),  # the row player changes side each seed
        ([1, 1], 0, ["ekm", "ekm"]), ([1, 1], 1, ["ekm", "ekm"])]
    assert [(c["row"], c["column"], c["games"]) for c in doc["cross_table"]] == [
        ("schema", "schema", 2), ("schema", "ekm", 2), ("ekm", "ekm", 2)]
    cross = doc["cross_table"][1]["goals"]
    mixed = doc["records"][2:4]
    assert cross == [mixed[0]["goals"][0] + mixed[1]["goals"][1], mixed[0]["goals"][1] + mixed[1]["goals"][0]]
    assert {r["player"]: r["games"] for r in doc["standings"]} == {"schema": 2, "ekm": 2}  # self-play left out
    assert {"seeds", "seed", "minutes", "rule", "field", "seconds", "workers", "ekm_version"} <= set(doc)
    lines = results.read_text().splitlines()
    assert len(lines) == 1 + 6 and json.loads(lines[0])["settings"]["labels"] == ["schema", "ekm"]
    assert sorted(json.loads(line)["outcome"]["seed"] for line in lines[1:]) == [0, 0, 0, 1, 1, 1]
    assert plot.read_bytes()[:4] == b"\x89PNG"
    whole = results.read_text().splitlines(keepends=True)
    results.write_text("".join(whole[:4]) + whole[4][:40])
    code, out, _ = cli(*TOURNAMENT, "--json", "--resume", results)
    again = json.loads(out)
    assert code == 0 and len(results.read_text().splitlines()) == 1 + 6
    for key in ("seconds", "workers"):
        doc.pop(key), again.pop(key)
    assert again == doc


def test_the_tournament_table_is_sahota_s_table_5_then_the_standings(cli):
    code, out, _ = cli(*TOURNAMENT)
    lines = out.splitlines()
    assert code == 0
    assert lines[0].split() == ["goals", "(row", "-", "column)", "schema", "ekm"]
    assert re.fullmatch(r"schema +\d+ - \d+ +\d+ - \d+", lines[1])
    assert re.fullmatch(r"ekm +\d+ - \d+", lines[2])  # the upper triangle only: ekm's row starts on the diagonal
    assert lines[2].index("-") > lines[1].index("-")  # ... under ekm's column
    assert lines[4].split() == ["player", "games", "W-D-L", "goals", "GD/game", "95", "%", "interval", "win", "rate",
                                "95", "%", "interval"]
    assert {lines[5].split()[0], lines[6].split()[0]} == {"schema", "ekm"}
    assert all(line.split()[1] == "2" for line in lines[5:7])
    assert re.fullmatch(r"6 games \(3 pairings x 2 seeds, seeds 0\.\.1, 0\.1 min each, rule centre, field lci-cup\) "
                        r"in \d+ s on 1 local worker \(this process\)", lines[-1])


def test_players_lists_every_player_with_its_parameters(cli):
    code, out, _ = cli("players")
    assert code == 0
    for name in ("deliberation", "samba", "ekm", "schema"):
        assert re.search(rf"^{name} \(built in\)$", out, flags=re.M)
    assert re.search(r"^    level += full \[full\|half\|none\]", out, flags=re.M)
    code, out, _ = cli("players", "schema", "--json")
    (row,) = json.loads(out)["players"]
    assert code == 0 and row["name"] == "schema" and {"drive", "push"} <= {p["name"] for p in row["parameters"]}


def test_the_example_package_s_player_is_listed_and_plays_in_a_tournament(installed):
    """As a user runs it after ``pip install ./examples/chaser``: the console script, its entry point read in the
    command's process (the worker processes of ``ekm compare`` read theirs in tests/ekm/cli/test_architectures.py)."""
    path = installed("chaser")
    env = {**os.environ, "PYTHONPATH": str(path)}

    def ekm(*argv):
        proc = subprocess.run([sys.executable, "-m", "ekm", *argv], capture_output=True, text=True, env=env, cwd=path)
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout)

    (row,) = ekm("players", "chaser", "--json")["players"]
    assert row["origin"] == "entry point" and [p["name"] for p in row["parameters"]] == ["speed", "gain"]
    doc = ekm("tournament", "chaser,schema", "--seeds", "2", "--minutes", "0.1", "--workers", "1", "--json")
    assert doc["players"] == ["chaser", "schema"] and doc["games"] == 6 and "failures" not in doc
    assert sorted(r["player"] for r in doc["standings"]) == ["chaser", "schema"]


@pytest.fixture
def no_games(monkeypatch):
    """Any game that starts fails the test."""
    import evaluation.match as match

    monkeypatch.setattr(match, "play_match", lambda *a, **k: pytest.fail("a game started"))
    monkeypatch.setattr(match, "play_job", lambda job: pytest.fail("a game started"))


@pytest.mark.parametrize("argv, message", [
    (["match", "schema", "striker"], "player 'striker': unknown (choose from deliberation, samba, ekm, schema"),
    (["match", "schema:speed=2", "ekm"], "player schema: unknown parameter 'speed'"),
    (["match", "deliberation:level=quarter", "ekm"], "level: must be one of full, half, none, got 'quarter'"),
    (["match", "schema"], "the following arguments are required: B"),
    (["match", "schema", "ekm", "--minutes", "0"], "argument --minutes: must be > 0, got 0"),
    (["match", "schema", "ekm", "--minutes", "ten"], "argument --minutes: must be a number, got 'ten'"),
    (["match", "schema", "ekm", "--seed", "-1"], "argument --seed: must be >= 0, got -1"),
    (["match", "schema", "ekm", "--rule", "offside"], "argument --rule: invalid choice: 'offside'"),
    (["match", "schema", "ekm", "--field", "nowhere.json"], "nowhere.json: no such field file or named field"),
    (["match", "schema", "ekm", "--plot", "m.jpg"], "--plot m.jpg: expected a file name ending in .png, .svg or .pdf"),
    (["match", "schema", "ekm", "--plot", "/proc/no/m.png"],
     "--plot /proc/no/m.png: no such directory /proc/no (make it first)"),
    (["match", "schema", "ekm", "--gif", "m.png"], "--gif m.png: expected a file name ending in .gif"),
    (["tournament", "schema,striker"], "player 'striker': unknown"),
    (["tournament", "schema,,ekm"], "player 'schema,,ekm': empty item between commas"),
    (["match", "deliberation:level=half,level=none", "ekm"], "player deliberation: parameter 'level' given twice"),
    (["tournament", "schema"], "players 'schema': a tournament needs at least two players"),
    (["tournament", "schema,ekm,schema"], "players 'schema,ekm,schema': player 'schema' is named twice"),
    (["tournament", "schema,ekm", "--seeds", "0"], "argument --seeds: must be > 0, got 0"),
    (["tournament", "schema,ekm", "--minutes", "-1"], "argument --minutes: must be > 0, got -1"),
    (["tournament", "schema,ekm", "--workers", "0"], "argument --workers: must be > 0, got 0"),
    (["tournament", "schema,ekm", "--plot", "cup.jpg"], "--plot cup.jpg: expected a file name ending in .png, .svg"),
    (["players", "striker"], "player 'striker': unknown (choose from deliberation, samba, ekm, schema)"),
    (["match", "schema", "ekm", "--robot", "tank"], "tank: no such robot file or named robot"),
    (["tournament", "schema,ekm,samba", "--robot", "khepera", "--robot", "e-puck"],
     "ekm tournament: --robot: give one robot for every player or one per player (3), got 2"),
])
def test_bad_input_is_one_line_and_exit_2_before_any_game(cli, no_games, argv, message):
    code, out, err = cli(*argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1 and err.startswith("error: ")


def test_a_bad_field_file_or_an_existing_results_file_is_refused_before_any_game(cli, no_games, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"soccer": {"goal_mouth": 0.9}}))
    for command in (["match", "schema", "ekm"], ["tournament", "schema,ekm"]):
        code, out, err = cli(*command, "--field", bad)
        assert code == 2 and err == (f"error: {bad}: soccer.goal_mouth: must be narrower than the field's width "
                                     f"0.8 m, got 0.9\n")
    results = tmp_path / "cup.jsonl"
    results.write_text("someone's results\n")
    code, out, err = cli("tournament", "schema,ekm", "--out", results)
    assert code == 2 and err.count("\n") == 1 and f"--out {results}: exists; continue it with --resume" in err
    assert results.read_text() == "someone's results\n"
    code, out, err = cli("tournament", "schema,ekm", "--resume", results)
    assert code == 2 and err == (f"error: {results}: not an ekm results file (ekm compare or tournament --out; its "
                                 f"first line is not the header of format 1)\n")
    code, out, err = cli("tournament", "schema,ekm", "--resume", results, "--out", tmp_path / "new.jsonl")
    assert code == 2 and err == "error: --out and --resume: give one (--resume PATH appends to PATH)\n"


def test_ctrl_c_stops_a_match_and_a_tournament_in_one_line_keeping_the_finished_games(cli, monkeypatch, tmp_path):
    import evaluation.match as match

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(match, "play_match", interrupted)
    code, out, err = cli("match", "schema", "ekm", "--plot", tmp_path / "m.png")
    assert code == 130 and out == "" and err.startswith("interrupted: match stopped at 0.0 s of 600 s of game time")
    assert not (tmp_path / "m.png").exists()
    games = []

    def second_stops(job: GameJob):
        if games:
            raise KeyboardInterrupt
        games.append(job)
        return match.game_failed(job, "not played")

    monkeypatch.setattr(match, "play_job", second_stops)
    results = tmp_path / "cup.jsonl"
    code, out, err = cli(*TOURNAMENT, "--out", results)
    assert code == 130 and err == (f"interrupted: tournament stopped; 1 of 6 games are in {results}; run the same "
                                   f"command with --resume {results} to finish it\n")
    assert [json.loads(line) for line in results.read_text().splitlines()][1]["outcome"]["failed"] == "not played"


def test_compare_from_a_tournaments_results_file_says_so_in_one_line(tmp_path, capsys):
    from ekm.cli import main
    from evaluation.results import ResultsFile

    path = tmp_path / "cup.jsonl"
    with ResultsFile(path, {"tournament": ["schema", "ekm"], "seeds": 2}):
        pass
    assert main(["compare", "--from", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {path}: a tournament's results file, not a comparison's (ekm compare --out writes those)"]


def test_each_player_can_play_on_its_own_robot_and_the_results_say_which(cli, tmp_path):
    """--robot once per player: the match prints and records each side's robot; in a tournament the same player
    enters twice, labelled by its robot, and the results file keeps the robots."""
    code, out, err = cli("match", "schema", "schema", "--minutes", "0.05", "--robot", "khepera", "--robot",
                         "worn-wheel")
    assert code == 0 and err == "" and "  robots: schema on khepera, schema on worn-wheel" in out.splitlines()
    results = tmp_path / "cup.jsonl"
    code, out, err = cli("tournament", "schema,schema", "--seeds", "1", "--minutes", "0.05", "--workers", "1",
                         "--robot", "khepera", "--robot", "e-puck", "--json", "--out", results)
    doc = json.loads(out)
    assert code == 0 and doc["players"] == ["schema@khepera", "schema@e-puck"]
    assert [r["robots"] for r in doc["records"]] == [["khepera", "khepera"], ["khepera", "e-puck"],
                                                     ["e-puck", "e-puck"]]
    header = json.loads(results.read_text().splitlines()[0])["settings"]
    assert [r["name"] for r in header["robots"]] == ["khepera", "e-puck"]
