"""``ekm compare`` from the command line: the same JSON on any number of workers, and one-line errors before
any run starts."""

import json

import pytest




ARGS = ["compare", "--worlds", "open-arena,three-rooms", "--architectures", "fusion,fields:form=thesis",
        "--trials", "2", "--time-limit", "40", "--json"]


def strip(doc):
    return {k: v for k, v in doc.items() if k not in ("seconds", "workers")}


def test_one_worker_or_two_give_the_same_json(cli):
    code1, out1, err1 = cli(*ARGS, "--workers", "1")
    code2, out2, _ = cli(*ARGS, "--workers", "2")
    assert code1 == code2 == 0 and err1 == ""
    one, two = json.loads(out1), json.loads(out2)
    assert strip(one) == strip(two)
    assert [(r["world"], r["architecture"]) for r in one["results"]] == [
        ("open-arena", "fusion"), ("three-rooms", "fusion"), ("open-arena", "fields:form=thesis"),
        ("three-rooms", "fields:form=thesis")]
    assert one["results"][0]["success_rate"] == 1.0 and one["ekm_version"] and one["trials"] == 2


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
def test_bad_input_is_one_line_before_any_run(cli, monkeypatch, argv, message):
    import evaluation.compare as comparison

    monkeypatch.setattr(comparison, "run_job", lambda job: pytest.fail("a run started"))
    code, out, err = cli("compare", *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


@pytest.mark.parametrize("argv, message", [
    (["--worlds", "open-arena", "--workers", "2"], "drop --workers and --scheduler"),
])
def test_the_jax_engine_refuses_what_it_cannot_run_in_one_line_before_any_run(cli, monkeypatch, argv, message):
    import evaluation.jaxrun as jaxrun

    monkeypatch.setattr(jaxrun, "run_jobs", lambda *a, **k: pytest.fail("a run started"))
    code, out, err = cli("compare", "--engine", "jax", "--architectures", "schema", *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


def test_a_comparison_resumed_from_its_results_file_gives_the_same_json(cli, tmp_path):
    """Eight runs written to --out; the file cut after three runs and half a line (a crash); --resume makes
    the five missing runs, and the JSON is the uninterrupted one's; --from makes it again with no runs."""
    results = tmp_path / "r.jsonl"
    code, out, _ = cli(*ARGS, "--workers", "1", "--out", results)
    whole = json.loads(out)
    lines = results.read_text().splitlines(keepends=True)
    assert code == 0 and len(lines) == 1 + 8 and all(line.endswith("\n") for line in lines)
    results.write_text("".join(lines[:4]) + lines[4][:50])
    code, out, _ = cli(*ARGS, "--workers", "1", "--resume", results)
    assert code == 0 and strip(json.loads(out)) == strip(whole) and len(results.read_text().splitlines()) == 9
    code, out, _ = cli("compare", "--from", results, "--json", "--plot", tmp_path / "again.png")
    assert code == 0 and strip(json.loads(out)) == strip(whole) and (tmp_path / "again.png").stat().st_size > 0


def test_motion_pools_each_architecture_s_runs_over_the_worlds(cli):
    code, out, _ = cli(*ARGS, "--workers", "1")
    doc = json.loads(out)
    assert code == 0 and [r["architecture"] for r in doc["overall"]] == ["fusion", "fields:form=thesis"]
    for row in doc["overall"]:
        mine = [r for r in doc["results"] if r["architecture"] == row["architecture"]]
        assert row["trials"] == 4 and row["worlds"] == 2
        assert row["success_rate"] == sum(r["success_rate"] * r["trials"] for r in mine) / 4
    code, out, _ = cli(*[a for a in ARGS if a != "--json"], "--workers", "1", "--motion")
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.split()[:2] == ["architecture", "encoding"])
    assert code == 0 and "change mm/s" in lines[head] and "stop mm" in lines[head]
    assert lines[head + 1].split()[:3] == ["fusion", "continuous", "4"]
    assert lines[head + 2].split()[:3] == ["fields:form=thesis", "continuous", "4"]


def test_results_files_are_refused_in_one_line(cli, tmp_path):
    results = tmp_path / "r.jsonl"
    code, out, _ = cli("compare", "--worlds", "open-arena", "--architectures", "fusion", "--trials", "2",
                       "--time-limit", "10", "--workers", "1", "--out", results)
    assert code == 0 and out.splitlines()[-1] == f"results written to {results}"  # as the tournament says it
    lines = results.read_text().splitlines(keepends=True)
    results.write_text("".join(lines[:2]))
    for argv, message in [
        (["--worlds", "open-arena", "--architectures", "fusion", "--out", results], "exists; continue it with --resume"),
        (["--worlds", "open-arena", "--architectures", "samba", "--trials", "2", "--time-limit", "10",
          "--resume", results], "made with other settings (labels: fusion in the file, samba now)"),
        (["--from", results], "holds 1 of the comparison's 2 runs; finish it with ekm compare … --resume"),
        (["--from", results, "--out", tmp_path / "x.jsonl"], "--from makes no runs"),
    ]:
        code, out, err = cli("compare", *argv)
        assert code == 2 and message in err and err.count("\n") == 1, err
    assert results.read_text() == "".join(lines[:2])


def test_a_comparison_on_another_robot_with_learning_maps_records_both(capsys, tmp_path):
    from ekm.cli import main

    results = tmp_path / "r.jsonl"
    argv = ["compare", "--worlds", "open-arena", "--architectures", "fields,samba", "--trials", "1", "--workers", "1",
            "--robot", "worn-wheel", "--learn", "--out", str(results)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "robot: worn-wheel (the maps were trained on khepera); the maps learn while driving (error)" in out
    lines = [json.loads(line) for line in results.read_text().splitlines()]
    assert lines[0]["settings"]["robot"]["name"] == "worn-wheel" and lines[0]["settings"]["learn"] == "error"
    runs = {line["job"]["label"]: line for line in lines[1:]}
    assert runs["fields"]["job"]["learn"] == "error" and runs["samba"]["job"]["learn"] is None
    assert runs["fields"]["outcome"]["updates"] > 0 and runs["samba"]["outcome"]["updates"] is None
    assert {r["outcome"]["robot"] for r in runs.values()} == {"worn-wheel"}
    assert runs["fields"]["outcome"]["map_robot"] == "khepera" and runs["samba"]["outcome"]["map_robot"] is None
    same = argv[1:-2]  # the same arguments, without --out
    assert main(["compare", "--resume", str(results), *same]) == 0  # nothing left to run
    capsys.readouterr()
    other = [a if a != "worn-wheel" else "weak-motor" for a in same]
    assert main(["compare", "--resume", str(results), *other]) == 2
    assert "other settings" in capsys.readouterr().err
