"""``ekm plan`` (docs/design.md §6): stable JSON, readable summary, atomic plot, one-line errors with exit status 2."""

import json

import pytest

from ekm.cli import main


def run(capsys, *argv):
    status = main(["plan", *argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_json_keys_and_values(capsys):
    status, out, err = run(capsys, "--world", "three-rooms", "--json")
    assert status == 0 and err == ""
    doc = json.loads(out)
    assert list(doc)[:6] == ["method", "cells", "graph_edges", "path_cells", "checkpoints", "seconds"]  # docs/design.md §6
    assert doc["world"] == "three-rooms" and doc["cell"] == 0.02 and doc["at"] == 0.0 and doc["ekm_version"]
    assert doc["method"] == "slippery" and doc["cells"] == 5 and doc["graph_edges"] == 4
    assert len(doc["path_cells"]) == 3 and doc["rule"] == "visible"
    assert doc["checkpoints"][-1] == [1.1, 0.42]
    assert doc["seconds"] > 0


def test_thesis_checkpoints_one_per_boundary(capsys):
    status, out, _ = run(capsys, "--world", "three-rooms", "--checkpoints", "thesis", "--json")
    doc = json.loads(out)
    assert status == 0 and doc["rule"] == "thesis"
    assert doc["checkpoints"] == [[0.44, 0.28], [0.84, 0.18], [1.1, 0.42]]  # ch. 3.2.3's greedy points
    assert doc["length_m"] == pytest.approx(0.3406 + 0.4123 + 0.3538, abs=2e-4)  # |X-p1| + |p1-p2| + |p2-Y|


def test_a_cell_too_coarse_for_the_doorways_is_refined(capsys):
    status, out, _ = run(capsys, "--world", "three-rooms", "--cell", "0.5", "--json")
    doc = json.loads(out)
    assert status == 0 and doc["cell"] == 0.5 / 16  # 0.5 m cells hold no free cell; halved four times
    assert doc["checkpoints"][-1] == [1.1, 0.42]


def test_options_reach_the_planner(capsys):
    status, out, _ = run(capsys, "--world", "three-rooms-changed", "--start", "0.6,0.3", "--goal", "1.0,0.5",
                         "--cell", "0.01", "--method", "quadtree", "--at", "6", "--json")
    doc = json.loads(out)
    assert status == 0 and doc["method"] == "quadtree" and doc["checkpoints"][-1] == [1.0, 0.5]
    assert all(y > 0.3 for _, y in doc["checkpoints"])  # the lower doorway is closed at 6 s


def test_human_summary(capsys):
    status, out, _ = run(capsys, "--world", "three-rooms", "--checkpoints", "thesis")
    assert status == 0
    assert "three-rooms at t = 0 s: slippery decomposition of a 60 x 30 bitmap" in out
    assert "5 cells, 4 graph edges" in out
    assert "checkpoint 1 (0.440, 0.280)" in out and "goal (1.100, 0.420)" in out
    assert "(thesis checkpoints: the straight legs start - checkpoints - goal)" in out
    assert "route through the cells" in out and "the thesis's legs may cross walls" in out


def test_plot_is_a_png_written_atomically(capsys, tmp_path):
    target = tmp_path / "plan.png"
    status, out, _ = run(capsys, "--world", "three-rooms", "--method", "grid", "--plot", str(target))
    assert status == 0 and f"plot written to {target}" in out
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["plan.png"]  # no temporary file left behind


@pytest.mark.parametrize("argv, message", [
    (["--world", "three-rooms", "--start", "abc"], "argument --start: must be X,Y in metres"),
    (["--world", "three-rooms", "--start", "0.1,0.2,0.3"], "argument --start: must be X,Y"),
    (["--world", "three-rooms", "--goal", "nan,1"], "argument --goal: must be X,Y in metres"),
    (["--world", "three-rooms", "--start", "0.4,0.1"], "start (0.4, 0.1): not in the free space of three-rooms"),
    (["--world", "three-rooms", "--goal", "2,2"], "goal (2, 2): not in the free space"),
    (["--world", "three-rooms", "--cell", "0"], "argument --cell: must be > 0, got 0"),
    (["--world", "three-rooms", "--cell", "big"], "argument --cell: must be a number"),
    (["--world", "three-rooms", "--cell", "1e-5"], "cell size: 1e-05 m cuts the 1.2 x 0.6 m arena"),
    (["--world", "three-rooms", "--checkpoints", "greedy"], "argument --checkpoints: invalid choice"),
    (["--world", "no-such-world"], "no-such-world: no such world file or named world"),
    (["--world", "three-rooms", "--method", "voronoi"], "argument --method: invalid choice"),
    (["--world", "three-rooms", "--at", "-1"], "argument --at: must be >= 0, got -1"),
    (["--world", "three-rooms", "--plot", "/no/such/dir/plan.png"],
     "--plot /no/such/dir/plan.png: no such directory /no/such/dir (make it first)"),
    ([], "the following arguments are required: --world"),
])
def test_bad_input_is_one_line_and_exit_status_2(capsys, argv, message):
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("error: "), err
    assert message in err, err
    assert "Traceback" not in err


def test_no_route_is_one_line(capsys, tmp_path):
    world = tmp_path / "sealed.json"
    world.write_text(json.dumps({"name": "sealed", "size": [1.0, 0.5], "walls": [[0.5, 0.0, 0.5, 0.5]],
                                 "start": [0.2, 0.25, 0.0], "goal": [0.8, 0.25]}))
    status, out, err = run(capsys, "--world", str(world))
    assert status == 2 and out == ""
    assert err == "error: sealed: no route from start (0.2, 0.25) to goal (0.8, 0.25): they lie in parts of the " \
                  "free space that do not connect at this cell size (tried cells down to 0.005 m)\n"


@pytest.mark.parametrize("name, head", [("plan.svg", b"<?xml"), ("plan.pdf", b"%PDF-"), ("plan.png", b"\x89PNG")])
def test_a_plot_is_written_in_the_format_of_its_suffix(capsys, tmp_path, name, head):
    status, _, err = run(capsys, "--world", "open-arena", "--plot", str(tmp_path / name))
    assert status == 0 and err == "" and (tmp_path / name).read_bytes()[:len(head)] == head


@pytest.mark.parametrize("plot, line", [
    ("run.jpg", "--plot run.jpg: expected a file name ending in .png, .svg or .pdf"),
    ("nowhere/deeper/p.svg", "--plot nowhere/deeper/p.svg: no such directory nowhere/deeper (make it first)"),
])
def test_a_plot_of_another_format_or_in_a_missing_directory_is_refused_and_nothing_made(capsys, tmp_path,
                                                                                          monkeypatch, plot, line):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "--world", "open-arena", "--plot", plot)
    assert (status, out, err) == (2, "", f"error: {line}\n") and list(tmp_path.iterdir()) == []
