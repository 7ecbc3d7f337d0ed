"""``ekm run``: the outcome as JSON, the text report, and one-line errors with exit status 2."""

import json
import subprocess
import sys

import pytest

from ekm.cli import main


def run(capsys, *argv):
    status = main(["run", *argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_run_prints_the_outcome_record_as_json(capsys):
    status, out, err = run(capsys, "--world", "three-rooms-static", "--architecture", "fields", "--json")
    assert status == 0 and err == ""
    rec = json.loads(out)
    assert list(rec)[:10] == ["world", "architecture", "reached", "time_s", "path_m", "collisions",
                              "checkpoints_reached", "replans", "trapped", "final_distance_m"]
    assert rec["world"] == "three-rooms-static" and rec["architecture"].startswith("fields:sensors=long,form=extended")
    from planner import plan
    from robots.worldnames import load_world

    planned = len(plan(load_world("three-rooms-static")).checkpoints)  # the visible checkpoints, goal included
    assert rec["reached"] and rec["collisions"] == 0 and rec["checkpoints_reached"] == planned
    assert rec["map"] == "shipped signed-chart map" and rec["trial"] == 0 and rec["seed"] == 0
    assert rec["config"]["checkpoint_tolerance"] == 0.005 and rec["ekm_version"] and rec["jax_version"]


def test_sensors_and_parameters_reach_the_architecture_and_the_text_report(capsys):
    status, out, _ = run(capsys, "--world", "open-arena", "--architecture", "fusion:beta=0.9", "--sensors", "long",
                         "--seed", "3", "--time-limit", "20")
    assert status == 0
    assert "fusion:sensors=long,beta=0.9," in out and "seed 3" in out and "trial 3" in out
    assert "REACHED the goal" in out


def test_a_given_map_and_trial_drive_the_run(capsys, tmp_path):
    from ekm.data import default_map

    path = tmp_path / "m.npz"
    path.write_bytes(default_map("signed").read_bytes())
    status, out, _ = run(capsys, "--world", "open-arena", "--architecture", "fields", "--map", str(path), "--trial", "4",
                         "--json")
    rec = json.loads(out)
    assert status == 0 and rec["map"] == str(path) and rec["trial"] == 4 and rec["reached"]


def test_plot_and_gif_are_written(capsys, tmp_path):
    png, gif = tmp_path / "run.png", tmp_path / "run.gif"
    status, out, _ = run(capsys, "--world", "three-rooms-moving", "--architecture", "fusion", "--time-limit", "3",
                         "--plot", str(png), "--gif", str(gif))
    assert status == 0 and png.stat().st_size > 10_000 and gif.stat().st_size > 10_000
    assert f"written to {png}" in out


def bad_world(tmp_path, name, doc):
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(doc))
    return str(path)


@pytest.mark.parametrize("argv, message", [
    (["--world", "nowhere", "--architecture", "fields"], "nowhere: no such world file or named world"),
    (["--world", "open-arena", "--architecture", "samba-ish"], "architecture 'samba-ish': unknown"),
    (["--world", "open-arena", "--architecture", "fields:form=best"], "fields: form: must be one of extended, thesis"),
    (["--world", "open-arena", "--architecture", "fusion:gain=2"], "fusion: unknown parameter 'gain'"),
    (["--world", "open-arena", "--architecture", "fields", "--map", "README.md"], "README.md: not a map file"),
    (["--world", "open-arena", "--architecture", "fields", "--map", "missing.npz"], "missing.npz: no such map file"),
    (["--world", "open-arena", "--architecture", "fields", "--trial", "7"], "--trial 7: the map file holds trials 0..4"),
    (["--world", "open-arena", "--architecture", "fields", "--seed", "-1"], "--seed: must be >= 0"),
    (["--world", "open-arena", "--architecture", "fields", "--time-limit", "nan"], "--time-limit: must be finite"),
    (["--world", "open-arena", "--architecture", "fields", "--plot", "run.jpg"], "--plot run.jpg: expected a file name ending in .png"),
    (["--world", "open-arena", "--architecture", "fields", "--sensors", "mid"], "--sensors: invalid choice: 'mid'"),
])
def test_bad_arguments_are_one_line_errors(capsys, argv, message):
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert err.startswith("error: ") and message in err and err.count("\n") == 1


def test_a_world_the_planner_cannot_route_through_is_one_line(capsys, tmp_path):
    walled = bad_world(tmp_path, "walled", {"name": "walled", "size": [1.0, 0.5], "walls": [[0.5, 0.0, 0.5, 0.5]],
                                            "start": [0.2, 0.25, 0.0], "goal": [0.8, 0.25]})
    status, _, err = run(capsys, "--world", walled, "--architecture", "fusion")
    assert status == 2 and "no route from start (0.2, 0.25) to goal (0.8, 0.25)" in err and err.count("\n") == 1


def test_a_combined_family_no_world_of_fits_is_one_line(capsys):
    # corridor:0's passage is too narrow for a mover across it and the 5 cm robot to pass each other (13 cm at least)
    status, out, err = run(capsys, "--world", "corridor+traffic:0", "--architecture", "samba")
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("error: corridor+traffic:0: no world of this spelling from seed 0: traffic found no place")


def test_a_start_inside_an_obstacle_is_one_line(capsys, tmp_path):
    inside = bad_world(tmp_path, "inside", {"name": "inside", "size": [1.0, 1.0], "start": [0.5, 0.5, 0.0],
                                            "goal": [0.8, 0.8],
                                            "obstacles": [{"type": "box", "center": [0.5, 0.5], "size": [0.1, 0.1]}]})
    status, _, err = run(capsys, "--world", inside, "--architecture", "fields")
    assert status == 2 and "start: the robot (radius 0.025 m) at [0.5, 0.5] overlaps a wall or obstacle" in err
    assert err.count("\n") == 1


def test_no_file_is_left_behind_when_the_run_fails(capsys, tmp_path):
    png = tmp_path / "out.png"
    status, _, _ = run(capsys, "--world", "open-arena", "--architecture", "fields", "--map", "missing.npz",
                       "--plot", str(png))
    assert status == 2 and not png.exists() and list(tmp_path.iterdir()) == []


def test_python_m_ekm_cli_run_exits_2_without_a_traceback():
    proc = subprocess.run([sys.executable, "-m", "ekm.cli", "run", "--world", "open-arena", "--architecture", "x"],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1


# ---------------------------------------------------------------------------------------------- --maps-at (Samba)

def test_maps_at_draws_samba_s_action_maps_below_the_run(capsys, tmp_path):
    png = tmp_path / "maps.png"
    status, out, err = run(capsys, "--world", "open-arena", "--architecture", "samba", "--maps-at", "1",
                           "--plot", str(png), "--json")
    rec = json.loads(out)
    assert status == 0 and err == "" and rec["reached"] and rec["architecture"].startswith("samba:")
    assert rec["map"] is None and rec["trial"] is None
    assert png.stat().st_size > 50_000


def test_the_jax_engine_drives_the_same_route_and_says_so(capsys):
    """The planner's route through the concave obstacle's world is one checkpoint, the goal; on the JAX engine the
    fields reach it without a collision as on pymunk, and the record names the engine."""
    status, out, err = run(capsys, "--world", "concave-obstacle", "--architecture", "fields", "--engine", "jax",
                           "--json")
    rec = json.loads(out)
    assert status == 0 and err == "" and rec["engine"] == "jax"
    assert rec["reached"] and rec["collisions"] == 0 and rec["checkpoints_reached"] == 1 and rec["trial"] == 0
    assert rec["final_distance_m"] < 0.005  # within the 5 mm of docs/design.md §5


@pytest.mark.parametrize("argv, message", [
    (["--world", "open-arena", "--architecture", "samba", "--engine", "jax", "--maps-at", "1", "--plot", "x.png"],
     "--maps-at: draws a tick of the pymunk engine's run"),
    (["--world", "open-arena", "--architecture", "samba", "--engine", "gpu"], "--engine"),
])
def test_what_the_jax_engine_cannot_run_is_one_line(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == "" and message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, message", [
    (["--architecture", "fusion", "--maps-at", "5", "--plot", "x.png"],
     "--maps-at: architecture fusion has no action maps (only samba has)"),
    (["--architecture", "fields", "--maps-at", "5", "--plot", "x.png"], "--maps-at: architecture fields has no action"),
    (["--architecture", "samba", "--maps-at", "5"], "--maps-at: needs --plot PNG"),
    (["--architecture", "samba", "--maps-at", "-1", "--plot", "x.png"], "--maps-at: must be >= 0"),
    (["--architecture", "samba", "--maps-at", "soon", "--plot", "x.png"], "--maps-at"),
    (["--architecture", "samba:avoid_ttc=-1"], "samba: avoid_ttc must be > 0"),
])
def test_maps_at_and_samba_parameters_are_checked_in_one_line(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "--world", "open-arena", *argv)
    assert status == 2 and out == "" and err.startswith("error: ") and message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
