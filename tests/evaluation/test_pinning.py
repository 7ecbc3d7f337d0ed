"""Pinning a process to one CPU (evaluation.pinning)."""

import pytest


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
