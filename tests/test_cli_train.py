"""``ekm train``, ``ekm evaluate`` and ``ekm bench`` from the command line (DESIGN §6)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from ekm.cli import main
from ekm.mapfile import load_maps

TRAIN_KEYS = {"mapping", "neurons", "steps", "trials", "seconds", "curve", "out"}


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """A small indirect map trained by ``ekm train`` once per module: ``(dir, map file, plot, train JSON)``.
    Every test that uses it can run alone."""
    d = tmp_path_factory.mktemp("maps")
    out, plot = d / "ind.npz", d / "ind.png"
    code = main(["train", "--mapping", "indirect", "--neurons", "8", "--steps", "1500", "--trials", "2",
                 "--eval-every", "500", "--eval-targets", "10", "--out", str(out), "--plot", str(plot), "--json"])
    assert code == 0
    return d, out, plot


def run_cli(capsys, *argv):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def test_train_then_evaluate_gives_the_same_numbers(trained, capsys):
    d, out, plot = trained
    capsys.readouterr()  # the fixture's own output
    code, stdout, _ = run_cli(capsys, "train", "--mapping", "indirect", "--neurons", "8", "--steps", "1500",
                              "--trials", "2", "--eval-every", "500", "--eval-targets", "10", "--out", d / "again.npz",
                              "--json")
    assert code == 0
    result = json.loads(stdout)
    assert TRAIN_KEYS <= set(result)
    assert [p["step"] for p in result["curve"]] == [0, 500, 1000, 1500]
    assert set(result["curve"][0]) >= {"step", "E_mm", "P", "T", "D"}
    assert out.stat().st_size > 0 and plot.stat().st_size > 10_000
    assert np.array_equal(load_maps(out).ekm.M, load_maps(d / "again.npz").ekm.M)  # the same seed, the same maps
    code, stdout, _ = run_cli(capsys, "evaluate", out, "--targets", "10", "--json")
    assert code == 0
    ev = json.loads(stdout)
    assert list(ev)[:7] == ["E_mm", "P", "T", "D", "trials", "targets", "capped"]  # DESIGN §6, then provenance
    assert ev["seed"] == 0 and ev["ekm"]["neurons"] == 8 and ev["trained"]["seed"] == 0 and ev["ekm_version"]
    assert result["seed"] == 0 and result["ekm"]["mapping"] == "indirect" and result["train"]["steps"] == 1500
    assert result["jax_version"] and result["ekm_version"] and result["test"] == {"targets": 10, "seed": 0}
    assert set(ev["P"]) == {"5", "10", "25"} and ev["trials"] == 2 and ev["targets"] == 10
    last = result["curve"][-1]
    assert ev["E_mm"] == last["E_mm"] and ev["P"] == last["P"] and ev["T"] == last["T"] and ev["D"] == last["D"]


def test_evaluate_several_maps_on_one_plot(trained, capsys, tmp_path):
    d, out, _ = trained
    capsys.readouterr()
    code, stdout, _ = run_cli(capsys, "train", "--mapping", "direct", "--neurons", "8", "--priority", "16",
                              "--chart", "polar", "--steps", "500", "--trials", "1", "--eval-every", "500", "--eval-targets", "5",
                              "--out", tmp_path / "dir.npz", "--json")
    assert code == 0
    saved = load_maps(tmp_path / "dir.npz").cfg
    assert (saved.priority, saved.chart) == (16, "polar")  # --priority and --chart reach the map and its file
    code, stdout, _ = run_cli(capsys, "evaluate", out, tmp_path / "dir.npz", "--targets", "5", "--json",
                              "--plot", tmp_path / "both.png", "--paths", tmp_path / "paths.png")
    assert code == 0
    maps = json.loads(stdout)["maps"]
    assert [m["mapping"] for m in maps] == ["indirect", "direct"]
    assert (tmp_path / "both.png").stat().st_size > 10_000
    assert (tmp_path / "paths.png").stat().st_size > 10_000
    code, stdout, _ = run_cli(capsys, "evaluate", out, "--targets", "5")
    assert code == 0 and "E =" in stdout and "P(eps)" in stdout


def test_paths_of_a_map_that_never_comes_within_25_mm_are_drawn(capsys, tmp_path):
    """An untrained map reaches no target: the paths plot says so instead of failing on the missing T/D."""
    code, _, _ = run_cli(capsys, "train", "--mapping", "indirect", "--neurons", "4", "--steps", "1", "--trials", "1",
                         "--eval-every", "1", "--eval-targets", "3", "--out", tmp_path / "raw.npz", "--json")
    assert code == 0
    code, stdout, stderr = run_cli(capsys, "evaluate", tmp_path / "raw.npz", "--targets", "3", "--json",
                                   "--paths", tmp_path / "paths.png")
    result = json.loads(stdout)
    assert code == 0 and stderr == "" and (tmp_path / "paths.png").stat().st_size > 10_000
    assert result["P"]["25"] == 0.0 and result["T"]["25"] is None


@pytest.mark.parametrize("argv, message", [
    (["train", "--mapping", "both", "--out", "x.npz"], "invalid choice"),
    (["train", "--mapping", "direct", "--steps", "0", "--out", "x.npz"], "must be > 0"),
    (["train", "--mapping", "direct", "--trials", "two", "--out", "x.npz"], "whole number"),
    (["train", "--mapping", "direct", "--neurons", "1", "--out", "x.npz"], "neurons must be >= 2"),
    (["train", "--mapping", "direct", "--neurons", "5", "--priority", "26", "--out", "x.npz"], "priority must be in 1..25"),
    (["train", "--mapping", "direct", "--priority", "0", "--out", "x.npz"], "must be > 0"),
    (["train", "--mapping", "direct", "--chart", "cartesian", "--out", "x.npz"], "invalid choice: 'cartesian'"),
    (["train", "--mapping", "direct"], "--out"),
    (["train", "--mapping", "direct", "--out", "x.txt"], "ending in .npz"),
    (["train", "--mapping", "direct", "--out", "x.npz", "--world", "three-rooms"], "obstacle-free"),
    (["train", "--mapping", "direct", "--out", "x.npz", "--world", "nowhere"], "no such world"),
    (["evaluate", "missing.npz"], "no such map file"),
    (["evaluate"], "required"),
    (["evaluate", "missing.npz", "--paths", "paths.jpg"], "ending in .png"),
])
def test_bad_arguments_give_one_line_and_status_2(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = run_cli(capsys, *argv)
    assert code == 2
    assert message in stderr and stderr.count("\n") == 1 and stdout == ""
    assert not (tmp_path / "x.npz").exists()


def test_output_directory_is_refused_before_training(capsys, tmp_path):
    code, _, stderr = run_cli(capsys, "train", "--mapping", "direct", "--out", tmp_path)
    assert code == 2 and "is a directory" in stderr


def test_a_corrupt_map_file_exits_2_without_traceback(trained, tmp_path):
    _, out, _ = trained
    with np.load(out) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["M"][0, 3, 0, 0] = np.nan
    bad = tmp_path / "bad.npz"
    np.savez(bad, **arrays)
    proc = subprocess.run([sys.executable, "-m", "ekm.cli", "evaluate", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"error: {bad}: array 'M' contains NaN or infinite values"
    assert "Traceback" not in proc.stderr


def test_bench_reports_jax_and_numpy_throughput(capsys):
    code, stdout, _ = run_cli(capsys, "bench", "--json")
    assert code == 0
    r = json.loads(stdout)
    assert r["jax_trial_steps_per_s"] > 0 and r["numpy_trial_steps_per_s"] > 0
    assert r["ratio"] == pytest.approx(r["jax_trial_steps_per_s"] / r["numpy_trial_steps_per_s"], rel=0.01)
