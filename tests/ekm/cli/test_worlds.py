"""``ekm worlds`` (docs/design.md §6): the table, --json, --check, --plot and --generate; bad files and bad arguments
exit 2 with one line."""

import functools
import json
import subprocess
import sys
from pathlib import Path

import pytest

from ekm.cli import main
from robots.generator import FAMILIES, generate
from robots.worldfile import world_json
from robots.worldnames import named_worlds

ROOT = Path(__file__).resolve().parents[3]
GOOD = {"name": "lab", "size": [1.0, 0.5], "start": [0.1, 0.25, 0.0], "goal": [0.9, 0.25],
        "unforeseen": [{"type": "circle", "center": [0.5, 0.25], "radius": 0.05}]}


def run(capsys, *argv):
    status = main(["worlds", *argv])
    out, err = capsys.readouterr()
    return status, out, err


def write(tmp_path, name, doc):
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return str(path)


def test_table_lists_every_named_world(capsys):
    status, out, err = run(capsys)
    assert status == 0 and err == ""
    lines = out.splitlines()
    assert lines[0].split() == ["name", "size", "(m)", "walls", "obstacles", "unforeseen", "moving", "events", "goal"]
    assert [line.split()[0] for line in lines[1:]] == named_worlds()
    row = next(line.split() for line in lines if line.startswith("three-rooms-changed "))
    assert row == ["three-rooms-changed", "1.2", "x", "0.6", "5", "0", "0", "0", "1", "fixed"]


def test_json_counts_of_the_named_worlds(capsys):
    status, out, _ = run(capsys, "--json")
    assert status == 0
    worlds = {w["name"]: w for w in json.loads(out)["worlds"]}
    assert sorted(worlds) == named_worlds()
    assert len(worlds) == 8
    assert worlds["three-rooms-moving"] == {"name": "three-rooms-moving", "size": [1.2, 0.6], "walls": 4,
                                            "obstacles": 0, "unforeseen": 0, "moving": 1, "moving_goal": False}
    assert worlds["moving-target"]["moving_goal"] is True
    assert worlds["concave-obstacle"]["unforeseen"] == 1


def test_check_reports_the_checked_files(tmp_path, capsys):
    a = write(tmp_path, "a.json", GOOD)
    b = write(tmp_path, "b.json", {**GOOD, "name": "lab-2", "unforeseen": []})
    status, out, _ = run(capsys, "--json", "--check", a, b)
    assert status == 0
    assert [(w["name"], w["unforeseen"]) for w in json.loads(out)["worlds"]] == [("lab", 1), ("lab-2", 0)]


def test_check_exits_2_on_the_first_bad_file_with_one_line(tmp_path, capsys):
    good = write(tmp_path, "good.json", GOOD)
    bad = write(tmp_path, "bad.json", {**GOOD, "size": [1.0, "wide"]})
    worse = write(tmp_path, "worse.json", "{")
    status, out, err = run(capsys, "--check", good, bad, worse)
    assert status == 2 and out == ""
    assert err == f"error: {bad}: size[1]: must be a number, got \"wide\"\n"


def test_plot_draws_every_named_world(tmp_path, capsys):
    out_dir = tmp_path / "new" / "plots"  # created, parents too
    status, out, _ = run(capsys, "--plot", str(out_dir))
    assert status == 0
    pngs = sorted(out_dir.iterdir())
    assert [p.name for p in pngs] == sorted(f"{n}.png" for n in named_worlds())
    for p in pngs:
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert out.count("wrote ") == len(pngs)


def test_plot_with_check_draws_the_checked_files_only(tmp_path, capsys):
    path = write(tmp_path, "mine.json", GOOD)
    status, _, _ = run(capsys, "--check", path, "--plot", str(tmp_path / "out"))
    assert status == 0
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["lab.png"]


def test_a_bad_file_leaves_no_plot_behind(tmp_path, capsys):
    good = write(tmp_path, "good.json", GOOD)
    bad = write(tmp_path, "bad.json", {**GOOD, "start": [0.5, 0.25, 0.0]})  # inside the obstacle
    status, _, err = run(capsys, "--check", good, bad, "--plot", str(tmp_path / "out"))
    assert status == 2 and "start: the robot" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_plot_into_a_file_is_refused(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    status, _, err = run(capsys, "--plot", str(blocker))
    assert status == 2
    assert err.startswith(f"error: --plot {blocker}: cannot create the directory") and err.count("\n") == 1


def test_one_world_plots_to_a_png_and_several_are_refused_one(tmp_path, capsys):
    path = write(tmp_path, "lab.json", GOOD)
    status, out, _ = run(capsys, "--check", path, "--plot", str(tmp_path / "lab.png"))
    assert status == 0 and (tmp_path / "lab.png").read_bytes()[:4] == b"\x89PNG"
    status, _, err = run(capsys, "--plot", str(tmp_path / "all.png"))
    assert status == 2 and "a plot file holds one world, and there are 8; give a directory" in err
    assert not (tmp_path / "all.png").exists()


@pytest.mark.parametrize("name", ["three-rooms", "concave-obstacle", "moving-target"])
def test_show_prints_a_named_world_as_its_shipped_file_holds_it(name, capsys, tmp_path):
    status, out, _ = run(capsys, "--show", name)
    shipped = json.loads((ROOT / "robots" / "worlds" / f"{name}.json").read_text())
    assert status == 0 and {k: v for k, v in json.loads(out).items() if k in shipped} == shipped
    status, out, _ = run(capsys, "--check", write(tmp_path, "copy.json", out))
    assert status == 0 and name in out


@pytest.mark.parametrize("doc, line", [
    ({**GOOD, "start": [0.1, 0.25]},
     "start: must be [x, y, θ] (m, m, rad: the heading, 0 = along +x), got [0.1, 0.25]"),
    ({**GOOD, "walls": [[0.1, 0.1, 0.3]]}, "walls[0]: must be [x0, y0, x1, y1] (m): a segment from (x0, y0) to "
                                           "(x1, y1), not a box; give a box as an obstacle, got [0.1, 0.1, 0.3]"),
    ({**GOOD, "unforeseen": [{"center": [0.5, 0.25], "radius": 0.05}]},
     "unforeseen[0].type: missing (one of box, circle, polygon, segment)"),
    ({**GOOD, "moving": [{"shape": {"type": "circle", "radius": 0.02}, "path": {"center": [0.5, 0.25]}}]},
     "moving[0].path.type: missing (one of circle, line)"),
])
def test_error_lines_say_what_a_list_holds_and_which_types_there_are(doc, line, tmp_path, capsys):
    path = write(tmp_path, "lab.json", doc)
    status, _, err = run(capsys, "--check", path)
    assert status == 2 and err == f"error: {path}: {line}\n"


def test_two_checked_worlds_with_one_name_are_refused_before_plotting(tmp_path, capsys):
    a, b = write(tmp_path, "a.json", GOOD), write(tmp_path, "b.json", GOOD)
    status, _, err = run(capsys, "--check", a, b, "--plot", str(tmp_path / "out"))
    assert status == 2 and "would both be drawn to lab.png" in err


@pytest.mark.parametrize("content, message", [
    (None, "no such world file or named world"),
    ("{nope", "not valid JSON"),
    (json.dumps({**GOOD, "colour": "red"}), "colour: unknown key"),
    (json.dumps({**GOOD, "goal": [0.5, 0.25]}), "goal: [0.5, 0.25] lies inside a wall or obstacle"),
    (json.dumps(GOOD).replace("0.05}", "NaN}"), "unforeseen[0].radius: must be finite, got nan"),
], ids=["missing", "bad-json", "unknown-key", "goal-inside", "nan"])
def test_the_console_script_prints_one_line_and_no_traceback(tmp_path, content, message):
    path = tmp_path / "w.json"
    if content is not None:
        path.write_text(content)
    proc = subprocess.run([sys.executable, "-m", "ekm.cli", "worlds", "--check", str(path)], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.startswith(f"error: {path}: ") and message in proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


# ----------------------------------------------------------------------------------------------- --generate

@functools.lru_cache(maxsize=None)
def made(family, seed, difficulty=None):
    return generate(family, seed, difficulty)


def test_cli_writes_a_world_file_that_check_accepts(tmp_path, capsys):
    out = tmp_path / "x.json"
    assert main(["worlds", "--generate", "maze", "--seed", "3", "--out", str(out)]) == 0
    text, err = capsys.readouterr()
    assert err == "" and f"wrote {out}" in text and text.startswith("maze:3: maze, seed 3")
    assert out.read_text() == world_json(made("maze", 3))
    assert main(["worlds", "--check", str(out), "--json"]) == 0
    listed = json.loads(capsys.readouterr()[0])["worlds"]
    assert listed == [made("maze", 3).counts()] and listed[0]["family"] == "maze"
    assert [p.name for p in tmp_path.iterdir()] == ["x.json"]  # written atomically: no temporary left


def test_cli_json_and_plot(tmp_path, capsys):
    out, png = tmp_path / "w.json", tmp_path / "w.png"
    argv = ["worlds", "--generate", "movers", "--seed", "5", "--difficulty", "0.25", "--out", str(out),
            "--plot", str(png), "--json"]
    assert main(argv) == 0
    result = json.loads(capsys.readouterr()[0])
    w = generate("movers", 5, 0.25)
    assert result["name"] == "movers:5:0.25" and result["difficulty"] == w.difficulty.to_dict()
    assert result["moving"] == len(w.moving) >= 1 and result["out"] == str(out)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_ekm_families_lists_the_families_and_the_help_of_worlds_points_to_it(capsys):
    assert main(["families"]) == 0
    text = capsys.readouterr()[0]
    for name, family in FAMILIES.all().items():
        assert f"{name} (built in)\n  " in text and family.summary[:60] in text
    with pytest.raises(SystemExit):
        main(["worlds", "--help"])
    assert "ekm families" in capsys.readouterr()[0]


@pytest.mark.parametrize("argv, message", [
    (["--generate", "mazes", "--seed", "1", "--out", "x.json"], "argument --generate: invalid choice: 'mazes'"),
    (["--generate", "maze", "--seed", "-3", "--out", "x.json"], "argument --seed: must be >= 0, got -3"),
    (["--generate", "maze", "--seed", "1", "--difficulty", "2", "--out", "x.json"],
     "argument --difficulty: must be in [0, 1], got 2"),
    (["--generate", "maze", "--seed", "1"], "argument --generate: needs --out"),
    (["--generate", "maze", "--out", "x.json"], "argument --generate: needs --seed"),
    (["--generate", "maze", "--seed", "1", "--out", "x.txt"], "--out x.txt: expected a file name ending in .json"),
    (["--seed", "1"], "argument --seed: only with --generate"),
], ids=["family", "seed", "difficulty", "no-out", "no-seed", "suffix", "seed-alone"])
def test_cli_bad_arguments_exit_2_with_one_line(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(["worlds", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and message in err and err.startswith("error: ")
    assert not list(tmp_path.iterdir())
