"""Where a comparison's runs go (evaluation.workers): a Dask cluster gives the runs local processes give,
and a worker killed mid-comparison — local or on Dask — costs nothing: the records are an undisturbed
comparison's."""

import pytest

from evaluation.batch import run_jobs
from evaluation.compare import failed_run, jobs, run_job
from evaluation.scenario import ScenarioConfig
from evaluation.workers import DaskWorkers, InProcess, LocalPool
from robots.controllers.spec import parse_architectures

QUICK = ScenarioConfig(time_limit=20.0)


QUICK_SAMBA = ScenarioConfig(time_limit=5.0)


def test_a_dask_local_cluster_gives_the_same_runs_as_local_processes_even_when_a_worker_is_killed():
    """The same runs on a Dask LocalCluster as in this process; then again with one nanny's worker process
    killed after the first result: Dask runs its tasks again, and the records are still the same."""
    distributed = pytest.importorskip("distributed")
    import os
    import signal

    job_list = jobs(["open-arena", "three-rooms-static"], parse_architectures("fusion,fields"), 2, 0, QUICK)
    here = run_jobs(job_list, InProcess(run_job), failed_run)
    killed = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        def kill_one(i, record):
            if not killed:
                nanny = next(iter(cluster.workers.values()))
                os.kill(nanny.process.process.pid, signal.SIGKILL)
                killed.append(True)

        workers = DaskWorkers(run_job, cluster.scheduler_address)
        try:
            on_dask = run_jobs(job_list, workers, failed_run)
            disturbed = run_jobs(job_list, workers, failed_run, kill_one)
        finally:
            workers.close()
    assert on_dask == here and killed and disturbed == here  # run for run


def test_a_local_worker_killed_mid_comparison_costs_nothing():
    """Two local workers; the first finished run kills a worker (as the out-of-memory killer would): the
    runs in flight are run again and the records are those of an undisturbed comparison."""
    import os
    import signal

    job_list = jobs(["open-arena"], parse_architectures("samba"), 4, 0, QUICK_SAMBA)
    pool = LocalPool(run_job, 2)
    killed = []

    def kill_one(i, record):
        if not killed:
            process = next(iter(pool._pool._processes.values()))
            os.kill(process.pid, signal.SIGKILL)
            killed.append(process.pid)

    try:
        disturbed = run_jobs(job_list, pool, failed_run, kill_one)
    finally:
        pool.close()
    assert killed and disturbed == run_jobs(job_list, InProcess(run_job), failed_run)
