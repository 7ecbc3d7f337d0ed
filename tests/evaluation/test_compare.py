"""Comparing architectures (evaluation.compare): the runs, their intervals, runs that fail and workers that die
(on fake workers); and issue 21's targets on the generated test worlds (slow)."""

import pytest

from evaluation.batch import run_jobs
from evaluation.compare import Job, by_architecture, failed_run, jobs, run_job, summarize, wilson
from evaluation.scenario import ScenarioConfig
from robots.controllers.spec import parse_architectures

QUICK = ScenarioConfig(time_limit=20.0)


def test_wilson_intervals_match_the_textbook_values():
    assert wilson(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert wilson(10, 10) == pytest.approx((0.7225, 1.0), abs=1e-4)
    assert wilson(5, 10) == pytest.approx((0.2366, 0.7634), abs=1e-4)
    assert wilson(9, 10) == pytest.approx((0.5958, 0.9821), abs=1e-4)
    assert wilson(0, 0) == (0.0, 1.0)


def test_trial_i_runs_with_seed_plus_i_for_every_architecture_and_world():
    specs = parse_architectures("fusion,fields:form=thesis")
    job_list = jobs(["open-arena", "three-rooms"], specs, 3, 7, QUICK, keep_paths=True)
    assert len(job_list) == 2 * 2 * 3
    assert [j.seed for j in job_list[:6]] == [7, 7, 8, 8, 9, 9] and {j.seed for j in job_list} == {7, 8, 9}
    assert [j.label for j in job_list[:2]] == ["fusion", "fields:form=thesis"]
    assert [j.world for j in job_list[::6]] == ["open-arena", "three-rooms"]  # world by world
    assert [j.keep_path for j in job_list[:6]] == [True, True, False, False, False, False]


def test_summary_rows_carry_design_keys_means_of_successes_and_intervals():
    records = [{"label": "a", "given": "w", "world": "w", "trial": i, "reached": i < 3, "trapped": i == 3,
                "arrived": i < 3, "ended": "x", "time_s": 10.0 + i, "path_m": 1.0, "collisions": int(i == 4),
                "contact_s": 0.25 * (i == 4)}
               for i in range(5)]
    (row,) = summarize(records, ["w"], ["a"])
    assert list(row)[:9] == ["world", "architecture", "trials", "success_rate", "success_ci95", "mean_time_s",
                             "mean_path_m", "collisions", "trapped"]
    assert row["success_rate"] == 0.6 and row["mean_time_s"] == 11.0 and row["trapped"] == 1
    assert row["collisions"] == 1 and row["success_ci95"] == pytest.approx(wilson(3, 5), abs=1e-4)
    assert row["runs_by_trial"] == "RRRTL" and row["contact_s"] == 0.25 and row["failed"] == 0


def test_runs_that_failed_are_no_runs_that_missed_and_a_row_of_failed_runs_has_no_rate():
    ok = {"label": "a", "given": "w", "world": "w", "reached": True, "trapped": False, "arrived": True, "ended": "x",
          "time_s": 10.0, "path_m": 1.0, "collisions": 0, "contact_s": 0.0}
    job = Job(world="w", architecture="a", label="a", trial=0, seed=0, config=QUICK)
    dead = [failed_run(Job(**{**job.__dict__, "trial": i, "seed": i}), "its worker died 4 times") for i in range(2)]
    records = [{**ok, "trial": 2}, {**ok, "trial": 3, "reached": False, "arrived": False, "ended": "time limit"}, *dead]
    (row,) = summarize(records, ["w"], ["a"])
    # 1 of the 2 runs made reached the goal: 0.5, Wilson (1, 2); the 2 failed runs are counted apart
    assert (row["trials"], row["success_rate"], row["failed"], row["runs_by_trial"]) == (4, 0.5, 2, "FFRL")
    assert row["success_ci95"] == pytest.approx(wilson(1, 2), abs=1e-4)
    (row,) = summarize(dead, ["w"], ["a"])
    assert (row["success_rate"], row["success_ci95"], row["failed"], row["runs_by_trial"]) == (None, None, 2, "FF")


def test_a_script_without_the_main_guard_is_named_with_the_two_lines_to_add(tmp_path):
    """The test behind issue 34's table of zeros: spawned workers import the script, which starts the comparison
    again; here, the check that names that cause, at a statement outside and inside the guard."""
    import subprocess
    import sys

    script = tmp_path / "script.py"
    script.write_text("from evaluation.workers import unguarded_script\n"
                      "print(unguarded_script())\n"
                      "if __name__ == '__main__':\n"
                      "    print(unguarded_script())\n")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True).stdout
    assert out.splitlines() == [str(script), "None"]


@pytest.mark.slow
def test_a_comparison_whose_workers_all_die_at_start_stops_with_the_cause_not_a_table_of_zeros(tmp_path):
    """Issue 34's script: ``ekm.compare`` with two workers at a script's top level. Each spawned worker runs the
    script again and leaves; the parent stops with one line naming the script and the guard — no table, no
    worker's traceback."""
    import subprocess
    import sys

    script = tmp_path / "noguard.py"
    script.write_text("import ekm\n"
                      "t = ekm.compare(['open-arena'], 'fields,samba', trials=1, workers=2)\n"
                      "print([r['success_rate'] for r in t.rows])\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 1 and done.stdout == "" and done.stderr.count("Traceback") == 1, done.stderr
    last = done.stderr.splitlines()[-1]
    assert last.startswith(f"ekm.errors.InputError: {script}: every worker process died as it started"), last
    assert "'if __name__ == \"__main__\":' and '    main()'" in last


def test_an_architecture_s_overall_row_pools_its_runs_in_every_world():
    def run(label, world, trial, reached, change):
        return {"label": label, "given": world, "world": world, "trial": trial, "reached": reached, "trapped": False,
                "arrived": reached, "ended": "x", "time_s": 10.0, "path_m": 1.0, "collisions": 0, "contact_s": 0.0,
                "command_change_mps": change}
    records = [run("a", "w1", 0, True, 0.010), run("a", "w1", 1, True, 0.020), run("a", "w2", 0, False, 0.030),
               run("a", "w2", 1, True, 0.040), run("b", "w1", 0, True, 0.5)]
    a, b = by_architecture(records, ["a", "b"])
    assert (a["architecture"], a["worlds"], a["trials"], a["success_rate"]) == ("a", 2, 4, 0.75)
    # mean 0.025 of the four; sample sd 0.01291, half-width 1.96 · 0.01291 / 2 = 0.01265
    assert a["motion"]["command_change_mps"]["mean"] == pytest.approx(0.025)
    assert a["motion"]["command_change_mps"]["ci95"] == pytest.approx([0.01235, 0.03765], abs=1e-5)
    assert (b["worlds"], b["trials"], b["motion"]["command_change_mps"]["mean"]) == (1, 1, 0.5)


def test_a_job_is_a_pure_function_of_its_fields():
    job = Job(world="open-arena", architecture=str(parse_architectures("fusion")[0]), label="fusion", trial=0,
              seed=3, config=QUICK, keep_path=True)
    a, b = run_job(job), run_job(job)
    assert a == b and a["reached"] and a["seed"] == 3 and len(a["path"]) > 10


# ---------------------------------------------------------------------------- runs that fail, workers that die

class Lost(Exception):
    """What a fake pool raises for a run whose worker died."""


class FakeWorkers:
    """Workers whose runs are made at once in this process; job ``j`` loses its worker ``deaths[j]`` times
    before it runs. ``breaks_whole``: as a local pool, a death fails every run in flight (``window`` at a
    time)."""

    def __init__(self, deaths: dict, window: int = 2, breaks_whole: bool = True):
        self.deaths, self.window, self.breaks_whole = dict(deaths), window, breaks_whole
        self.submitted, self.renewed = [], 0

    def submit(self, job):
        from concurrent.futures import Future

        self.submitted.append(job.trial)
        future = Future()
        if self.deaths.get(job.trial, 0) > 0:
            self.deaths[job.trial] -= 1
            future.set_exception(Lost("killed"))
        elif job.world == "raises":
            future.set_exception(RuntimeError("boom\nsecond line"))
        else:
            future.set_result({"given": job.world, "label": job.label, "trial": job.trial, "reached": True})
        return future

    def lost(self, exc):
        return isinstance(exc, Lost)

    def renew(self):
        self.renewed += 1


def fake_jobs(n: int, world: str = "w") -> list[Job]:
    return [Job(world=world, architecture="a", label="a", trial=i, seed=i, config=QUICK) for i in range(n)]


def test_a_run_whose_worker_dies_is_run_again_and_the_records_keep_the_jobs_order():
    workers = FakeWorkers({1: 2, 4: 1})
    records = run_jobs(fake_jobs(6), workers, failed_run)
    assert [r["trial"] for r in records] == [0, 1, 2, 3, 4, 5] and all(r["reached"] for r in records)
    assert workers.submitted.count(1) == 3 and workers.submitted.count(4) == 2 and workers.renewed == 3


def test_a_run_whose_worker_keeps_dying_is_failed_after_the_retries_and_the_rest_finish():
    records = run_jobs(fake_jobs(3), FakeWorkers({2: 10}, window=1), failed_run, retries=3)
    assert [r["reached"] for r in records] == [True, True, False]
    assert records[2]["failed"] == "w: its worker died 4 times (Lost)" and records[2]["trial"] == 2


def test_a_run_that_raises_is_failed_with_its_exception_in_one_line_naming_the_world():
    (record,) = run_jobs(fake_jobs(1, world="raises"), FakeWorkers({}), failed_run)
    assert record["failed"] == "raises: RuntimeError: boom" and record["ended"] == "failed"


def test_a_pool_that_breaks_while_a_worker_starts_is_renewed_and_the_run_tried_again():
    class BreaksOnSubmit(FakeWorkers):
        def submit(self, job):
            if self.deaths.get(("submit", job.trial), 0) > 0:
                self.deaths[("submit", job.trial)] -= 1
                raise Lost("handle is closed")
            return super().submit(job)

    workers = BreaksOnSubmit({("submit", 1): 1})
    records = run_jobs(fake_jobs(3), workers, failed_run)
    assert [r["trial"] for r in records] == [0, 1, 2] and all(r["reached"] for r in records) and workers.renewed == 1


def test_runs_already_done_are_not_run_again():
    workers, seen = FakeWorkers({}), []
    records = run_jobs(fake_jobs(4), workers, failed_run, lambda i, r: seen.append(i),
                       done={0: {"trial": 0, "old": True}, 2: {"trial": 2, "old": True}})
    assert sorted(workers.submitted) == [1, 3] and sorted(seen) == [1, 3]
    assert records[0]["old"] and records[2]["old"] and "old" not in records[1]


def test_run_job_records_a_world_without_a_route_for_that_world(tmp_path):
    """A walled-in goal: the planner finds no route at any cell; the reason names the world file."""
    import json

    world = {"name": "walled", "size": [0.5, 0.5], "start": [0.1, 0.1, 0.0], "goal": [0.4, 0.4],
             "walls": [[0.35, 0.35, 0.45, 0.35], [0.45, 0.35, 0.45, 0.45], [0.45, 0.45, 0.35, 0.45],
                       [0.35, 0.45, 0.35, 0.35]]}
    path = tmp_path / "walled.json"
    path.write_text(json.dumps(world))
    (job,) = jobs([str(path)], parse_architectures("fusion"), 1, 0, QUICK)
    record = run_job(job)
    assert record["ended"] == "failed" and str(path) in record["failed"] and "route" in record["failed"]


# ------------------------------------------------------------------------------------ generalisation (slow)

# Issue 21's targets on the generated test worlds (seeds 1000-1019 of each family, never tuned on). The
# thresholds are the issue's, not numbers the code produced: the default neural fields reach the goal
# without a collision in at least 85 % of the 120 worlds and 70 % of every family's 20, and in every family
# the best architecture reaches at least 90 %.

FAMILIES = ("corridor", "traps", "clutter", "maze", "movers", "blocked")


@pytest.fixture(scope="module")
def table():
    import ekm

    return ekm.compare(suite=",".join(f"{f}:20" for f in FAMILIES), trials=1, workers=2)


def _fields_rows(table):
    return {r["family"]: r for r in table.families if r["architecture"] == "fields"}


@pytest.mark.slow
def test_the_default_fields_reach_85_percent_overall_and_70_percent_in_every_family(table):
    rows = _fields_rows(table)
    assert rows["all"]["success_rate"] >= 0.85, rows["all"]
    for f in FAMILIES:
        assert rows[f]["worlds"] == 20, rows[f]
        assert rows[f]["success_rate"] >= 0.70, rows[f]


@pytest.mark.slow
def test_in_every_family_the_best_architecture_reaches_90_percent(table):
    for f in FAMILIES:
        best = max(r["success_rate"] for r in table.families if r["family"] == f)
        assert best >= 0.90, f


@pytest.mark.slow
def test_no_generated_world_fails_to_start(table):
    assert all(r["failed"] == 0 for r in table.families)
