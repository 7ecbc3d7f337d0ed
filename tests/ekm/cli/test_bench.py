"""``ekm bench`` from the command line (docs/design.md §6)."""

import json

import pytest




def test_bench_reports_jax_and_numpy_throughput(cli):
    code, stdout, _ = cli("bench", "--json")
    assert code == 0
    r = json.loads(stdout)
    assert r["jax_trial_steps_per_s"] > 0 and r["numpy_trial_steps_per_s"] > 0
    assert r["ratio"] == pytest.approx(r["jax_trial_steps_per_s"] / r["numpy_trial_steps_per_s"], rel=0.01)
