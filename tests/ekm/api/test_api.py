"""The Python API (issue 13): every command's JSON is ``to_dict()`` of the API function it wraps, for the
same arguments; bad arguments raise :class:`ekm.InputError` with the line the command prints; and
``import ekm`` loads neither JAX nor pymunk.

Fields ignored in the comparisons: ``seconds`` of ``train``, ``plan`` and ``compare`` (wall time, different
on every call). Nothing else.
"""

import functools
import json
import math
import subprocess
import sys

import numpy as np
import pytest

import ekm
from ekm.cli import main
from ekm.errors import InputError
from robots.generator import generate

WALL_TIME = ("seconds",)


def cli_json(capsys, *argv) -> dict:
    code = main([str(a) for a in argv] + ["--json"])
    out, err = capsys.readouterr()
    assert code == 0 and err == "", err
    return json.loads(out)


def same(cli: dict, api: dict, ignore=()):
    drop = lambda d: {k: v for k, v in d.items() if k not in ignore}  # noqa: E731
    assert list(cli) == list(api)  # the same keys in the same order
    assert drop(cli) == drop(api)


# ------------------------------------------------------------------------------------- the same JSON

def test_worlds(capsys, tmp_path):
    same(cli_json(capsys, "worlds"), ekm.worlds().to_dict())
    lab = tmp_path / "lab.json"
    lab.write_text(json.dumps({"name": "lab", "size": [1.0, 0.5], "start": [0.1, 0.1, 0.0], "goal": [0.9, 0.4]}))
    same(cli_json(capsys, "worlds", "--check", lab), ekm.worlds(check=[str(lab)]).to_dict())


def test_plan(capsys):
    cli = cli_json(capsys, "plan", "--world", "three-rooms-changed", "--at", "7", "--method", "quadtree")
    same(cli, ekm.plan("three-rooms-changed", at=7, method="quadtree").to_dict(), ignore=WALL_TIME)
    cli = cli_json(capsys, "plan", "--world", "three-rooms", "--start", "0.1,0.3", "--goal", "1.1,0.3", "--cell", "0.03")
    same(cli, ekm.plan(ekm.world("three-rooms"), (0.1, 0.3), (1.1, 0.3), cell=0.03).to_dict(), ignore=WALL_TIME)


TINY = dict(neurons=4, steps=200, trials=2, seed=3, eval_every=100, eval_targets=3, test_seed=1)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """``(path, Maps)``: a tiny map trained once by ekm.train and saved."""
    out = tmp_path_factory.mktemp("api") / "tiny.npz"
    return out, ekm.train(mapping="direct", **TINY, out=out)


def test_train(capsys, tiny):
    out, maps = tiny
    argv = [a for k, v in TINY.items() for a in (f"--{k.replace('_', '-')}", v)]
    cli = cli_json(capsys, "train", "--mapping", "direct", *argv, "--out", out)
    same(cli, maps.to_dict(), ignore=WALL_TIME)
    same(cli, ekm.load(out).to_dict(), ignore=WALL_TIME)  # what the file says about its training
    assert maps.to_dict()["curve"] and not out.with_name("tiny.checkpoint.npz").exists()


def test_evaluate(capsys, tiny):
    out, maps = tiny
    # 3 targets, as in training: the test's jitted code is compiled once
    same(cli_json(capsys, "evaluate", out, "--targets", 3, "--seed", 2), ekm.evaluate(str(out), targets=3, seed=2).to_dict())
    both = ekm.evaluate([str(out), str(out)], targets=3)
    same(cli_json(capsys, "evaluate", out, out, "--targets", 3), both.to_dict())
    assert ekm.evaluate(maps, targets=3).E_mm == both[0].E_mm  # the maps in memory are the maps in the file


def test_run(capsys, tiny):
    same(cli_json(capsys, "run", "--world", "open-arena", "--architecture", "fusion", "--seed", 3, "--time-limit", 15),
         ekm.run("open-arena", architecture="fusion", seed=3, time_limit=15).to_dict())
    out, _ = tiny
    cli = cli_json(capsys, "run", "--world", "three-rooms-static", "--architecture", "schema", "--sensors", "long",
                   "--recover", "--time-limit", 10)
    same(cli, ekm.run(ekm.world("three-rooms-static"), "schema", sensors="long", recover=True, time_limit=10).to_dict())


def test_run_with_a_given_map_and_trial(capsys):
    shipped = ekm.load()
    path = shipped.path
    cli = cli_json(capsys, "run", "--world", "open-arena", "--architecture", "fields", "--map", path, "--trial", 2,
                   "--time-limit", 15)
    assert cli == ekm.run("open-arena", "fields", maps=path, trial=2, time_limit=15).to_dict()
    via_map = ekm.run("open-arena", "fields", maps=ekm.load(path)[2], time_limit=15).to_dict()
    assert via_map == cli  # maps[2] drives as --trial 2 does


def test_compare(capsys):
    argv = ["--worlds", "open-arena", "--architectures", "schema,fusion:beta=0.8", "--trials", 2, "--seed", 4,
            "--time-limit", 10, "--workers", 1]
    api = ekm.compare("open-arena", ["schema", "fusion:beta=0.8"], trials=2, seed=4, time_limit=10, workers=1)
    same(cli_json(capsys, "compare", *argv), api.to_dict(), ignore=WALL_TIME)
    assert [r["architecture"] for r in api.rows] == ["schema", "fusion:beta=0.8"]


# ------------------------------------------------------------------------ the same errors, the same line

def cli_error(capsys, *argv) -> str:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.startswith("error: ") and err.count("\n") == 1, err
    return err[len("error: "):-1]


BAD = [
    (["train", "--mapping", "direct", "--steps", "0", "--out", "x.npz"], ekm.train, ("direct",), dict(steps=0, out="x.npz")),
    (["train", "--mapping", "direct", "--neurons", "1", "--out", "x.npz"], ekm.train, ("direct",), dict(neurons=1, out="x.npz")),
    (["train", "--mapping", "direct", "--neurons", "5", "--priority", "26", "--out", "x.npz"], ekm.train, ("direct",),
     dict(neurons=5, priority=26, out="x.npz")),
    (["train", "--mapping", "direct", "--chart", "cartesian", "--out", "x.npz"], ekm.train, ("direct",),
     dict(chart="cartesian", out="x.npz")),
    (["train", "--mapping", "diagonal", "--out", "x.npz"], ekm.train, ("diagonal",), dict(out="x.npz")),
    (["train", "--mapping", "direct", "--seed", "-1", "--out", "x.npz"], ekm.train, ("direct",), dict(seed=-1, out="x.npz")),
    (["train", "--mapping", "direct", "--out", "x.txt"], ekm.train, ("direct",), dict(out="x.txt")),
    (["train", "--mapping", "direct", "--out", "x.npz", "--world", "three-rooms"], ekm.train, ("direct",),
     dict(out="x.npz", world="three-rooms")),
    (["evaluate", "missing.npz"], ekm.evaluate, ("missing.npz",), {}),
    (["evaluate", "README.md"], ekm.evaluate, ("README.md",), {}),
    (["plan", "--world", "no-such-world"], ekm.plan, ("no-such-world",), {}),
    (["plan", "--world", "three-rooms", "--method", "voronoi"], ekm.plan, ("three-rooms",), dict(method="voronoi")),
    (["plan", "--world", "three-rooms", "--at", "-1"], ekm.plan, ("three-rooms",), dict(at=-1)),
    (["plan", "--world", "three-rooms", "--checkpoints", "greedy"], ekm.plan, ("three-rooms",),
     dict(checkpoints="greedy")),
    (["run", "--world", "open-arena", "--architecture", "samba-ish"], ekm.run, ("open-arena", "samba-ish"), {}),
    (["run", "--world", "open-arena", "--architecture", "fusion:beta=3"], ekm.run, ("open-arena", "fusion:beta=3"), {}),
    (["run", "--world", "open-arena", "--architecture", "fields", "--trial", "7"], ekm.run, ("open-arena", "fields"),
     dict(trial=7)),
    (["run", "--world", "open-arena", "--architecture", "samba", "--map", "m.npz"], ekm.run, ("open-arena", "samba"),
     dict(maps="m.npz")),
    (["run", "--world", "open-arena", "--architecture", "fields", "--time-limit", "nan"], ekm.run,
     ("open-arena", "fields"), dict(time_limit=math.nan)),
    (["run", "--world", "open-arena", "--architecture", "fields", "--sensors", "mid"], ekm.run, ("open-arena", "fields"),
     dict(sensors="mid")),
    (["compare", "--worlds", "open-arena,open-arena", "--architectures", "fusion"], ekm.compare,
     ("open-arena,open-arena", "fusion"), {}),
    (["compare", "--worlds", "open-arena", "--architectures", "fusion,fusion"], ekm.compare, (["open-arena"], ["fusion", "fusion"]), {}),
    (["compare", "--worlds", "open-arena", "--architectures", "fusion", "--trials", "0"], ekm.compare,
     ("open-arena", "fusion"), dict(trials=0)),
    (["compare", "--worlds", "open-arena", "--architectures", "fusion", "--map", "missing.npz"], ekm.compare,
     ("open-arena", "fusion"), dict(maps="missing.npz")),
]


@pytest.mark.parametrize("argv, function, args, kwargs", BAD, ids=[" ".join(b[0][:4]) for b in BAD])
def test_bad_arguments_raise_the_line_the_cli_prints(capsys, tmp_path, monkeypatch, argv, function, args, kwargs):
    import shutil

    shutil.copy("README.md", tmp_path / "README.md")
    monkeypatch.chdir(tmp_path)
    line = cli_error(capsys, *argv)
    with pytest.raises(ekm.InputError) as exc:
        function(*args, **kwargs)
    assert str(exc.value) == line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md"]  # nothing written by either


# ------------------------------------------------------------------------------------ maps and results

def test_maps_index_to_one_trial_whose_command_is_eq_4_5_of_its_map(tiny):
    import jax

    from ekm.maps import control

    out, maps = tiny
    assert len(maps) == 2 and [m.trial for m in maps] == [0, 1] and maps[-1].trial == 1
    one = jax.tree.map(lambda a: a[1], maps.ekm)
    expected = np.asarray(control(one, np.array([0.4, 0.05], np.float32), maps.cfg)[0])
    np.testing.assert_allclose(maps[1].command(0.4, 0.05), expected, rtol=1e-6)
    with pytest.raises(ekm.InputError, match=r"--trial 2: the map file holds trials 0..1"):
        maps[2]


def test_save_then_load_gives_the_same_maps(tiny, tmp_path):
    _, maps = tiny
    again = ekm.load(maps.save(tmp_path / "again.npz"))
    for a, b in zip(maps.ekm, again.ekm):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert again.cfg == maps.cfg and again.curve == maps.curve and again.meta["seed"] == 3


def test_results_are_frozen_and_plot(tiny):
    import dataclasses

    outcome = ekm.run("open-arena", "fusion", time_limit=5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        outcome.reached = True
    assert outcome.plot().has_data() and ekm.plan("three-rooms").plot().has_data()
    assert tiny[1][0].plot().has_data() and len(tiny[1].plot().axes) >= 5


def test_import_ekm_loads_neither_jax_nor_pymunk():
    code = ("import sys, ekm; ekm.InputError; ekm.world; "
            "print(sorted(m for m in ('jax', 'pymunk', 'matplotlib') if m in sys.modules))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert proc.stdout.strip() == "[]"
    assert set(ekm.__all__) <= set(dir(ekm)) and "train" in ekm.__all__


# --------------------------------------------------------------------------------------------- ekm.generate

@functools.lru_cache(maxsize=None)
def made(family, seed, difficulty=None):
    return generate(family, seed, difficulty)


@pytest.mark.parametrize("args, message", [
    (("mazes", 1), "ekm worlds: argument --generate: invalid choice: 'mazes'"),
    (("maze", -1), "ekm worlds: argument --seed: must be >= 0, got -1"),
    (("maze", 1.5), "ekm worlds: argument --seed: must be a whole number, got 1.5"),
    (("maze", 1, 1.5), "ekm worlds: argument --difficulty: must be in [0, 1], got 1.5"),
    (("maze", 1, -0.1), "ekm worlds: argument --difficulty: must be >= 0, got -0.1"),
    (("maze", 1, float("nan")), "ekm worlds: argument --difficulty: must be finite, got nan"),
])
def test_ekm_generate_refuses_bad_arguments_as_the_command_line_does(args, message):
    with pytest.raises(InputError) as err:
        ekm.generate(*args)
    assert str(err.value).startswith(message)


def test_ekm_generate_is_the_generator():
    assert ekm.generate("traps", 4) == made("traps", 4) and ekm.world("traps:4") == made("traps", 4)
