"""The soccer API without playing a game: ``ekm.tournament``'s jobs and its field, the parallel driver's record
of a game that could not be played, the standings' intervals, the exports. (Games: tests/ekm/cli/test_soccer.py.)"""

from concurrent.futures import Future

import pytest

import ekm
import evaluation.match as match
from evaluation.batch import run_jobs
from evaluation.match import GameJob, game_failed, play_job, standings
from evaluation.workers import InProcess
from robots.soccer.fieldfile import SoccerField, load_field, save_field

JOB = GameJob("schema", "ekm", ("schema", "ekm"), (0, 1), 0, 0.1, "centre", None)


def test_the_soccer_functions_are_exported_like_compare():
    for name in ("match", "MatchResult", "tournament", "TournamentResult", "soccer_field"):
        assert name in ekm.__all__ and getattr(ekm, name).__module__ == "ekm.api.soccer"
    assert ekm.soccer_field() == SoccerField()


def test_the_driver_records_a_game_that_raised_with_the_failed_callable():
    def boom(job):
        raise RuntimeError("boom\nsecond line")

    (record,) = run_jobs([JOB], InProcess(boom), game_failed)
    assert record["failed"] == "RuntimeError: boom" and record["goals"] is None and record["pair"] == [0, 1]


class _Dying:
    """Workers whose every run dies with its worker."""

    window, breaks_whole, where = 1, False, "nowhere"

    def __init__(self):
        self.submitted = 0

    def submit(self, job):
        self.submitted += 1
        future = Future()
        future.set_exception(OSError("worker gone"))
        return future

    def lost(self, exc):
        return True

    def renew(self):
        pass


def test_a_game_whose_worker_keeps_dying_is_tried_again_then_recorded_as_failed():
    workers = _Dying()
    (record,) = run_jobs([JOB], workers, game_failed, retries=2)
    assert workers.submitted == 3 and record["failed"] == "its worker died 3 times (OSError)"
    assert record["players"] == ["schema", "ekm"]


def test_a_game_of_a_field_file_starts_from_the_file_s_kick_off(monkeypatch, tmp_path):
    path = save_field(SoccerField(kickoff=((0.2, 0.2, 0.0), (1.0, 0.6, 3.0)), rule="sahota"), tmp_path / "f.json")
    seen = {}

    def fake(first, second, **kw):
        seen.update(kw)
        raise RuntimeError("not played")

    monkeypatch.setattr(match, "play_match", fake)
    record = play_job(GameJob("schema", "ekm", ("schema", "ekm"), (0, 1), 0, 0.1, "centre", str(path)))
    assert seen["kickoff"] == ((0.2, 0.2, 0.0), (1.0, 0.6, 3.0)) and seen["rule"] == "centre"
    assert record["failed"] == "RuntimeError: not played"


def test_a_draw_is_half_a_win_in_the_interval_too():
    """Three draws: win rate 0.5 and a Wilson interval symmetric about it (1.5 successes of 3, not 2)."""
    records = [{"pair": [0, 1], "seed": s, "goals": [1, 1]} for s in range(3)]
    rows = {r["player"]: r for r in standings(records, ["a", "b"])}
    lo, hi = rows["a"]["win_ci95"]
    assert rows["a"]["win_rate"] == 0.5 and rows["a"]["drawn"] == 3 and lo + hi == pytest.approx(1.0, abs=2e-3)


def test_a_tournament_sends_the_workers_the_field_file_and_refuses_a_field_without_one(monkeypatch, tmp_path):
    path = save_field(SoccerField(name="mine", rule="sahota"), tmp_path / "mine.json")
    jobs = []
    monkeypatch.setattr(match, "play_job", lambda job: jobs.append(job) or game_failed(job, "not played"))
    t = ekm.tournament("schema,ekm", field=load_field(path), seeds=1, workers=1)
    assert {j.field_path for j in jobs} == {str(path)} and {j.rule for j in jobs} == {"sahota"}
    assert t.field == "mine" and len(t.records) == 3 and all(c["goals"] is None for c in t.cross_table)
    assert [f["reason"] for f in t.to_dict()["failures"]] == ["not played"] * 3
    with pytest.raises(ekm.InputError, match="save the field first"):
        ekm.tournament("schema,ekm", field=SoccerField(rule="sahota"))
