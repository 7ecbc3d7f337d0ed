"""``ekm train`` from the command line (docs/design.md §6): its JSON, its maps, the same numbers from ``ekm evaluate``,
and one-line errors for bad arguments of either command."""

import json

import numpy as np
import pytest

from ekm.mapfile import load_maps

TRAIN_KEYS = {"mapping", "neurons", "steps", "trials", "seconds", "curve", "out"}



def test_train_then_evaluate_gives_the_same_numbers(cli, trained, capsys):
    d, out, plot = trained
    capsys.readouterr()  # the fixture's own output
    code, stdout, _ = cli("train", "--mapping", "indirect", "--neurons", "8", "--steps", "1500",
                              "--trials", "2", "--eval-every", "500", "--eval-targets", "10", "--out", d / "again.npz",
                              "--json")
    assert code == 0
    result = json.loads(stdout)
    assert TRAIN_KEYS <= set(result)
    assert [p["step"] for p in result["curve"]] == [0, 500, 1000, 1500]
    assert set(result["curve"][0]) >= {"step", "E_mm", "P", "T", "D"}
    assert out.stat().st_size > 0 and plot.stat().st_size > 10_000
    assert np.array_equal(load_maps(out).ekm.M, load_maps(d / "again.npz").ekm.M)  # the same seed, the same maps
    code, stdout, _ = cli("evaluate", out, "--targets", "10", "--json")
    assert code == 0
    ev = json.loads(stdout)
    assert list(ev)[:7] == ["E_mm", "P", "T", "D", "trials", "targets", "capped"]  # docs/design.md §6, then provenance
    assert ev["seed"] == 0 and ev["ekm"]["neurons"] == 8 and ev["trained"]["seed"] == 0 and ev["ekm_version"]
    assert result["seed"] == 0 and result["ekm"]["mapping"] == "indirect" and result["train"]["steps"] == 1500
    assert result["jax_version"] and result["ekm_version"] and result["test"] == {"targets": 10, "seed": 0}
    assert set(ev["P"]) == {"5", "10", "25"} and ev["trials"] == 2 and ev["targets"] == 10
    last = result["curve"][-1]
    assert ev["E_mm"] == last["E_mm"] and ev["P"] == last["P"] and ev["T"] == last["T"] and ev["D"] == last["D"]


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
def test_bad_arguments_give_one_line_and_status_2(cli, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = cli(*argv)
    assert code == 2
    assert message in stderr and stderr.count("\n") == 1 and stdout == ""
    assert not (tmp_path / "x.npz").exists()


def test_output_directory_is_refused_before_training(cli, tmp_path):
    code, _, stderr = cli("train", "--mapping", "direct", "--out", tmp_path)
    assert code == 2 and "is a directory" in stderr


@pytest.mark.parametrize("extra, message", [
    (["--mapping", "direct"], "--mapping direct: --init "),
    (["--trials", "3"], "--trials 3: --init "),
    (["--neurons", "9"], "--neurons 9: --init "),
])
def test_fine_tuning_keeps_the_map_s_lattice_and_says_so(cli, trained, extra, message):
    d, out, _ = trained
    code, _, err = cli("train", "--init", out, *extra, "--out", d / "x.npz")
    assert code == 2 and message in err and "fine-tuning keeps the map's" in err and err.count("\n") == 1


def test_rate_needs_init_and_a_known_rule(cli, trained):
    d, out, _ = trained
    code, _, err = cli("train", "--mapping", "indirect", "--rate", "constant", "--out", d / "x.npz")
    assert code == 2 and "--rate: the rate of fine-tuning; needs --init MAP.npz" in err
    code, _, err = cli("train", "--init", out, "--rate", "sometimes", "--out", d / "x.npz")
    assert code == 2 and "learning rule 'sometimes': unknown" in err


def test_a_map_trained_on_one_robot_tested_on_another_says_so(cli, trained):
    d, out, _ = trained
    code, stdout, _ = cli("evaluate", out, "--targets", "5", "--robot", "worn-wheel")
    assert code == 0 and "on worn-wheel; trained on khepera" in stdout
    code, stdout, _ = cli("evaluate", out, "--targets", "5", "--json")
    ev = json.loads(stdout)
    assert ev["robot"] == "khepera" and ev["map_robot"] == "khepera"
