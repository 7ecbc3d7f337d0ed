"""``ekm compare``: the runs, their intervals, the same results on any number of workers or on Dask, and
one-line errors before any run starts."""

import json

import pytest

from ekm.cli import main
from evaluation.compare import Job, compare, jobs, run_job, summarize, wilson
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


def test_a_job_is_a_pure_function_of_its_fields():
    job = Job(world="open-arena", architecture=str(parse_architectures("fusion")[0]), label="fusion", trial=0,
              seed=3, config=QUICK, keep_path=True)
    a, b = run_job(job), run_job(job)
    assert a == b and a["reached"] and a["seed"] == 3 and len(a["path"]) > 10


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


ARGS = ["compare", "--worlds", "open-arena,three-rooms", "--architectures", "fusion,fields:form=thesis",
        "--trials", "2", "--time-limit", "40", "--json"]


def strip(doc):
    return {k: v for k, v in doc.items() if k not in ("seconds", "workers")}


def test_one_worker_or_two_give_the_same_json(capsys):
    code1, out1, err1 = cli(capsys, *ARGS, "--workers", "1")
    code2, out2, _ = cli(capsys, *ARGS, "--workers", "2")
    assert code1 == code2 == 0 and err1 == ""
    one, two = json.loads(out1), json.loads(out2)
    assert strip(one) == strip(two)
    assert [(r["world"], r["architecture"]) for r in one["results"]] == [
        ("open-arena", "fusion"), ("three-rooms", "fusion"), ("open-arena", "fields:form=thesis"),
        ("three-rooms", "fields:form=thesis")]
    assert one["results"][0]["success_rate"] == 1.0 and one["ekm_version"] and one["trials"] == 2


def test_a_dask_local_cluster_gives_the_same_runs_as_local_processes():
    distributed = pytest.importorskip("distributed")
    specs = parse_architectures("fusion,fields")
    job_list = jobs(["open-arena", "three-rooms-static"], specs, 2, 0, QUICK)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            on_dask = compare(job_list, client.get_executor(pure=False))
    assert on_dask == compare(job_list)  # run for run


@pytest.mark.parametrize("argv, message", [
    (["--worlds", "open-arena,nowhere", "--architectures", "fusion"], "nowhere: no such world file or named world"),
    (["--worlds", "open-arena", "--architectures", "fusion,sambo"], "architecture 'sambo': unknown"),
    (["--worlds", "open-arena", "--architectures", "fusion:beta=3"], "architecture fusion: beta must be in (0, 1]"),
    (["--worlds", "open-arena", "--architectures", "fields:colour=red"], "architecture fields: unknown parameter 'colour'"),
    (["--worlds", "open-arena,open-arena", "--architectures", "fusion"], "a world is named twice"),
    (["--worlds", "open-arena", "--architectures", "fusion,fusion"], "an architecture is named twice"),
    (["--worlds", "open-arena", "--architectures", "fusion", "--trials", "0"], "--trials: must be > 0"),
    (["--worlds", "open-arena", "--architectures", "fusion", "--map", "missing.npz"], "missing.npz: no such map file"),
    (["--worlds", "open-arena", "--architectures", "fusion", "--plot", "x.jpg"], "expected a file name ending in .png"),
])
def test_bad_input_is_one_line_before_any_run(capsys, monkeypatch, argv, message):
    import evaluation.compare as comparison

    monkeypatch.setattr(comparison, "run_job", lambda job: pytest.fail("a run started"))
    code, out, err = cli(capsys, "compare", *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


def test_pinning_restricts_a_process_to_one_cpu_of_those_it_may_use():
    import os
    import subprocess
    import sys

    if not hasattr(os, "sched_setaffinity") or len(os.sched_getaffinity(0)) < 2:
        pytest.skip("needs a process that may run on two CPUs")
    code = ("import os; from evaluation.pinning import pin_to_one_cpu; cpus = sorted(os.sched_getaffinity(0)); "
            "print(pin_to_one_cpu(3) == cpus[3 % len(cpus)], os.sched_getaffinity(0) == {cpus[3 % len(cpus)]})")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["True", "True"]
