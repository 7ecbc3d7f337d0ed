"""Long training survives interruption: checkpoints at every test, Ctrl-C ends in one line (exit 130) with the
old checkpoint intact, and ``--resume`` finishes with the maps and JSON of an uninterrupted run."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import training.checkpoint as checkpoint_module
from ekm.cli import main
from ekm.mapfile import load_maps
from training.checkpoint import saved_step

SMALL = ["train", "--mapping", "indirect", "--neurons", "6", "--steps", "3000", "--trials", "2", "--eval-every", "1000",
         "--eval-targets", "4", "--json"]


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def interrupt_at_save(monkeypatch, n: int, during: bool):
    """Raise KeyboardInterrupt at the ``n``-th checkpoint save: in the middle of writing it (``during``) or
    just before it starts."""
    real_savez, calls = np.savez, {"n": 0}

    def savez(fh, **arrays):
        calls["n"] += 1
        if calls["n"] == n:
            if during:
                fh.write(b"PK\x03\x04 half a zip archive")
            raise KeyboardInterrupt
        return real_savez(fh, **arrays)

    monkeypatch.setattr(checkpoint_module.np, "savez", savez)


def test_ctrl_c_during_a_save_leaves_the_previous_checkpoint_whole_and_says_where_it_is(capsys, tmp_path,
                                                                                       monkeypatch):
    interrupt_at_save(monkeypatch, 2, during=True)
    code, out, err = cli(capsys, *SMALL, "--out", tmp_path / "maps.npz")
    ckpt = tmp_path / "maps.checkpoint.npz"
    assert code == 130 and out == ""
    assert err == (f"interrupted: training stopped; the checkpoint at step 1000 is {ckpt}; "
                   f"resume with: ekm train --resume {ckpt}\n")
    assert saved_step(ckpt) == 1000  # the first checkpoint, untouched by the save that was cut short
    assert sorted(p.name for p in tmp_path.iterdir()) == ["maps.checkpoint.npz"]  # no temporary, no map file


def test_ctrl_c_before_the_first_checkpoint_writes_nothing(capsys, tmp_path, monkeypatch):
    interrupt_at_save(monkeypatch, 1, during=False)
    code, _, err = cli(capsys, *SMALL, "--out", tmp_path / "maps.npz")
    assert code == 130 and err == "interrupted: training stopped before its first checkpoint; nothing was written\n"
    assert list(tmp_path.iterdir()) == []


def test_a_resumed_run_ends_with_the_maps_and_json_of_an_uninterrupted_one(capsys, tmp_path, monkeypatch):
    code, whole, _ = cli(capsys, *SMALL, "--out", tmp_path / "whole.npz")
    assert code == 0 and not (tmp_path / "whole.checkpoint.npz").exists()  # removed once the maps are saved
    with monkeypatch.context() as m:
        interrupt_at_save(m, 2, during=False)
        assert cli(capsys, *SMALL, "--out", tmp_path / "part.npz")[0] == 130
    code, resumed, err = cli(capsys, "train", "--resume", tmp_path / "part.checkpoint.npz", "--json")
    assert code == 0 and err == ""
    a, b = load_maps(tmp_path / "whole.npz"), load_maps(tmp_path / "part.npz")
    for leaf_a, leaf_b in zip(a.ekm, b.ekm):
        np.testing.assert_array_equal(np.asarray(leaf_a), np.asarray(leaf_b))  # bit for bit
    whole, resumed = json.loads(whole), json.loads(resumed)
    for j in (whole, resumed):
        j.pop("seconds"), j.pop("out")  # wall time and file name are the only differences
    assert whole == resumed and a.curve == b.curve
    assert not (tmp_path / "part.checkpoint.npz").exists()


@pytest.mark.parametrize("extra, message", [
    (["--steps", "10"], "--resume continues the run with the settings it was started with; drop --steps"),
    (["--mapping", "direct", "--seed", "3"], "drop --mapping, --seed"),
])
def test_resume_refuses_new_settings(capsys, tmp_path, monkeypatch, extra, message):
    with monkeypatch.context() as m:
        interrupt_at_save(m, 2, during=False)
        cli(capsys, *SMALL, "--out", tmp_path / "part.npz")
    code, _, err = cli(capsys, "train", "--resume", tmp_path / "part.checkpoint.npz", *extra)
    assert code == 2 and message in err and err.count("\n") == 1


@pytest.mark.parametrize("damage, message", [
    (lambda p: p.write_bytes(b"not a zip"), "not a training checkpoint"),
    (lambda p: p.unlink(), "no such training checkpoint"),
    (lambda p: p.write_bytes(p.read_bytes()[:200]), "not a training checkpoint"),
])
def test_a_damaged_checkpoint_is_one_line(capsys, tmp_path, monkeypatch, damage, message):
    with monkeypatch.context() as m:
        interrupt_at_save(m, 2, during=False)
        cli(capsys, *SMALL, "--out", tmp_path / "part.npz")
    ckpt = tmp_path / "part.checkpoint.npz"
    damage(ckpt)
    code, _, err = cli(capsys, "train", "--resume", ckpt)
    assert code == 2 and message in err and err.count("\n") == 1


def test_a_checkpoint_with_a_wrong_array_is_refused(capsys, tmp_path, monkeypatch):
    with monkeypatch.context() as m:
        interrupt_at_save(m, 2, during=False)
        cli(capsys, *SMALL, "--out", tmp_path / "part.npz")
    ckpt = tmp_path / "part.checkpoint.npz"
    with np.load(ckpt) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["carry.ekm.M"] = arrays["carry.ekm.M"][:, :5]
    np.savez(ckpt, **arrays)
    code, _, err = cli(capsys, "train", "--resume", ckpt)
    assert code == 2 and "array 'carry.ekm.M' has shape (2, 5, 2, 2)" in err


def test_sigint_from_the_terminal_ends_training_with_one_line_and_status_130(tmp_path):
    """A real SIGINT (what Ctrl-C sends) to `ekm train`, once it has written a checkpoint."""
    out = tmp_path / "long.npz"
    ckpt = tmp_path / "long.checkpoint.npz"
    proc = subprocess.Popen([sys.executable, "-m", "ekm.cli", "train", "--mapping", "indirect", "--neurons", "4",
                             "--trials", "1", "--steps", "5000000", "--eval-every", "2000", "--eval-targets", "2",
                             "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not ckpt.exists() and proc.poll() is None and time.time() < deadline:
        time.sleep(0.2)
    assert ckpt.exists(), proc.communicate()
    os.kill(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "Traceback" not in stderr
    assert stderr.startswith("interrupted: training stopped; the checkpoint at step ") and stderr.count("\n") == 1
    assert saved_step(ckpt) and saved_step(ckpt) % 2000 == 0 and not out.exists()


def test_a_fine_tuning_run_resumed_ends_as_the_uninterrupted_one(capsys, tmp_path, monkeypatch):
    """``ekm train --init MAP --robot R`` keeps the same checkpoint and resume guarantees."""
    assert cli(capsys, *SMALL, "--out", tmp_path / "base.npz")[0] == 0
    fine = ["train", "--init", tmp_path / "base.npz", "--robot", "weak-motor", "--steps", "2000", "--eval-every", "1000",
            "--eval-targets", "4", "--json"]
    code, whole, _ = cli(capsys, *fine, "--out", tmp_path / "whole.npz")
    assert code == 0
    with monkeypatch.context() as m:
        interrupt_at_save(m, 2, during=False)  # the checkpoint at step 1000 is saved, the maps at 2000 are not
        assert cli(capsys, *fine, "--out", tmp_path / "part.npz")[0] == 130
    code, resumed, _ = cli(capsys, "train", "--resume", tmp_path / "part.checkpoint.npz", "--json")
    assert code == 0
    a, b = load_maps(tmp_path / "whole.npz"), load_maps(tmp_path / "part.npz")
    for leaf_a, leaf_b in zip(a.ekm, b.ekm):
        np.testing.assert_array_equal(np.asarray(leaf_a), np.asarray(leaf_b))  # bit for bit
    assert a.curve == b.curve and json.loads(resumed)["steps"] == 2000
    assert b.meta["robot"]["name"] == "weak-motor" and b.meta["init"]["robot"] == "khepera"
    assert b.meta["init"]["rate"] == "error"
    base = load_maps(tmp_path / "base.npz")
    assert not np.array_equal(np.asarray(base.ekm.M), np.asarray(b.ekm.M))  # it did learn
