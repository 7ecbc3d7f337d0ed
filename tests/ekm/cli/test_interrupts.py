"""Ctrl-C and SIGTERM at any moment of ``ekm train``, ``ekm compare`` and ``ekm run``: one line, exit 130
(143 for SIGTERM), no partial output file — from the first second, while JAX starts, on.

Each command runs as a user runs it (the console script, in a directory of its own) and gets the signal
at the moments of the issue's list — 0.5, 1, 2, 5 and 20 s — each command's moments in a seeded shuffle,
all of them side by side to keep the test short. A command that ended before its signal would be a
failed test (the jobs are long enough not to).
"""

import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

EKM = [sys.executable, "-m", "ekm"]
MOMENTS = [0.5, 1.0, 2.0, 5.0, 20.0]
COMMANDS = {
    "train": ["train", "--mapping", "indirect", "--steps", "1000000", "--trials", "2", "--out", "m.npz",
              "--checkpoint", "m.checkpoint.npz"],
    "compare": ["compare", "--worlds", "concave-obstacle,extended-obstacle", "--architectures", "fusion,samba",
                "--trials", "20", "--workers", "2", "--out", "r.jsonl"],  # about a minute on 2 idle cores
}


def catches_signals(pid: int) -> bool:
    """Whether process ``pid`` has the package's handlers yet (Linux's /proc; elsewhere, True at once): it catches
    SIGTERM, which the interpreter leaves alone (its own SIGINT handler is there before ``site`` is imported)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True
    caught = next((line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), None)
    return caught is None or bool(int(caught, 16) & (1 << (signal.SIGTERM - 1)))


def stopped(cases, tmp_path, sig=signal.SIGINT, group=False):
    """Start every ``(name, argv, moment)`` of ``cases``; send ``sig`` to each at its moment (to its whole
    process group with ``group``, as a terminal's Ctrl-C does); ``{(name, moment): (status, stderr, dir)}``.

    A moment counts from when the command handles signals — its first statement (:func:`ekm.__main__.console`)
    — not from the process's start: before it, the interpreter is still starting (its ``site`` imports), which on
    a loaded machine takes more than the first moment, and a signal there is Python's own, not the package's."""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    running = []
    for name, argv, moment in cases:
        d = tmp_path / f"{name}-{moment}"
        d.mkdir()
        p = subprocess.Popen(EKM + argv, cwd=d, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             text=True, start_new_session=group)
        running.append([name, moment, d, p, None])
    while any(r[4] is None for r in running):  # each one's clock starts when it handles signals
        for r in running:
            if r[4] is None and catches_signals(r[3].pid):
                r[4] = time.monotonic() + r[1]
            assert r[3].poll() is None, "the command ended before it handled signals"
        time.sleep(0.01)
    for _, _, _, p, at in sorted(running, key=lambda r: r[4]):
        time.sleep(max(0.0, at - time.monotonic()))
        assert p.poll() is None, "the command ended before its signal: make it longer"
        os.killpg(p.pid, sig) if group else p.send_signal(sig)
    out = {}
    for name, moment, d, p, _ in running:
        _, err = p.communicate(timeout=120)
        out[(name, moment)] = (p.returncode, err, d)
    return out


def assert_nothing_partial(d: Path):
    """What a stopped command leaves is whole: a results file of whole JSON lines, a loadable checkpoint."""
    for f in d.iterdir():
        if f.name == "r.jsonl":
            text = f.read_text()
            assert text.endswith("\n") and all(json.loads(line) for line in text.splitlines())
        elif f.name == "m.checkpoint.npz":
            np.load(f).close()
        else:
            pytest.fail(f"{f.name} left behind")


def test_ctrl_c_at_any_moment_stops_train_and_compare_with_one_line_and_130(tmp_path):
    rng = random.Random(23)
    cases = [(name, argv, m) for name, argv in COMMANDS.items() for m in rng.sample(MOMENTS, len(MOMENTS))]
    for (name, moment), (status, err, d) in stopped(cases, tmp_path).items():
        assert status == 130 and err.count("\n") == 1 and err.startswith("interrupted: "), (name, moment, err)
        assert_nothing_partial(d)
        if name == "compare":  # --out was given: at every moment the line names the file and how to resume
            assert (d / "r.jsonl").exists() and "runs are in r.jsonl" in err and "--resume r.jsonl" in err, err


def test_a_signal_before_the_results_file_exists_still_ends_with_the_file_and_how_to_resume(tmp_path):
    """Issue 34, item 2, without timing: the signal is sent before anything of ekm compare has run (the moment
    that said "no results file was written"). The console script holds it until the results file exists, so the
    line is the one of every other moment, and the file is there to resume."""
    code = ("import os, signal, sys\n"
            "from ekm import interrupts\n"
            "interrupts.install(hold=True)\n"
            "os.kill(os.getpid(), signal.SIGINT)\n"
            "from ekm.cli import main\n"
            "status = main(sys.argv[1:])\n"
            "sys.stdout.flush(); sys.stderr.flush(); os._exit(status)\n")
    argv = ["compare", "--worlds", "open-arena", "--architectures", "fusion,samba", "--trials", "3", "--workers", "2",
            "--out", "r.jsonl"]
    done = subprocess.run([sys.executable, "-c", code, *argv], cwd=tmp_path, capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg"}, timeout=300)
    assert done.returncode == 130, done.stderr
    assert done.stderr == ("interrupted: comparison stopped; 0 of 6 runs are in r.jsonl; run the same command with "
                           "--resume r.jsonl to finish it\n")
    (header,) = (tmp_path / "r.jsonl").read_text().splitlines()
    assert json.loads(header)["settings"]["worlds"] == ["open-arena"]


def test_sigterm_stops_with_143_and_a_terminal_ctrl_c_reaches_no_worker(tmp_path):
    """SIGTERM to ``ekm train`` and ``ekm run``; Ctrl-C to the whole process group of ``ekm compare`` (its
    workers too, as a terminal sends it): still one line — no worker prints a traceback."""
    run = ["run", "--world", "three-rooms-static", "--architecture", "fields", "--json"]
    term = stopped([("train", COMMANDS["train"], 2.0), ("run", run, 2.0)], tmp_path, signal.SIGTERM)
    for (name, _), (status, err, d) in term.items():
        assert status == 143 and err.count("\n") == 1 and err.startswith("interrupted: "), (name, err)
        assert_nothing_partial(d)
    ((status, err, d),) = stopped([("group", COMMANDS["compare"], 8.0)], tmp_path, group=True).values()
    assert status == 130 and err.count("\n") == 1 and "runs are in r.jsonl" in err, err
    assert_nothing_partial(d)
