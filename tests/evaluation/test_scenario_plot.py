"""Run plots and animations (evaluation.scenario_plot): files written atomically, the legend tells what
happened, unwritable paths are input errors that leave nothing behind."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from ekm.errors import InputError
from evaluation.scenario import PlanChange, RunRecord, ScenarioConfig, run_architecture
from evaluation.scenario_plot import (architecture_label, draw_run, frame_times, run_title, save_animation,
                                      save_run, sensed_points)
from robots.controllers.spec import parse_architecture
from robots.geometry import Polygon
from robots.worldnames import load_world


@pytest.fixture(scope="module")
def short_run() -> RunRecord:
    """Three simulated seconds of fusion in the world with a moving obstacle."""
    return run_architecture(load_world("three-rooms-moving"), parse_architecture("fusion"), seed=0,
                            config=ScenarioConfig(time_limit=3.0))


#: A declared mover's lane a plan kept off (planner.lanes).
LANE = Polygon(((0.5, 0.6), (0.9, 0.6), (0.9, 0.65), (0.5, 0.65)))


@pytest.fixture
def eventful() -> RunRecord:
    """A hand-made record with a replan after an event, two collisions, a trap and a recovery."""
    world = load_world("three-rooms-changed")
    times = np.arange(0.0, 10.0 + 1e-9, 0.016)
    x = 0.1 + 0.06 * times
    poses = np.stack([x, np.full_like(x, 0.3), np.zeros_like(x)], axis=1)
    first = np.array([[0.44, 0.28], [0.84, 0.18], [1.1, 0.3]])
    after_event = np.array([[0.84, 0.44], [1.1, 0.3]])
    after_trap = np.array([[0.6, 0.5], [1.1, 0.3]])
    return RunRecord(
        world=world, architecture=str(parse_architecture("fusion:beta=0.6")), seed=3, time_s=10.0, path_m=0.6,
        collisions=2, trapped=False, recoveries=1, replans=2, ended="time limit", poses=poses, times=times,
        plans=[PlanChange(0.0, "start", first, avoided=(LANE,)), PlanChange(6.0, "event", after_event, avoided=(LANE,)),
               PlanChange(8.0, "recovery", after_trap, added=np.array([[0.75, 0.35], [0.75, 0.36]]))],
        checkpoint_log=[(4.0, 0.44, 0.28)], collision_log=[(4.5, 0.37, 0.3), (5.0, 0.4, 0.3)],
        trap_log=[(8.0, 0.58, 0.3)], hits=[(7.5, np.array([[0.75, 0.35], [0.75, 0.36]]))])


def legend_texts(ax) -> list[str]:
    return [t.get_text() for legend in ax.figure.legends for t in legend.get_texts()]


def test_save_run_writes_a_png(short_run, tmp_path):
    path = save_run(short_run, tmp_path / "run.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.png"]  # no temporary file left


def test_save_animation_writes_a_gif_of_many_frames(short_run, tmp_path):
    path = save_animation(short_run, tmp_path / "run.gif")
    assert path.stat().st_size > 0
    with Image.open(path) as gif:
        assert gif.format == "GIF" and gif.n_frames > 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.gif"]


def test_animation_frames_are_capped(short_run, tmp_path):
    with Image.open(save_animation(short_run, tmp_path / "few.gif", max_frames=4)) as gif:
        assert 1 < gif.n_frames <= 4


@pytest.mark.parametrize("save, name", [(save_run, "run.png"), (save_animation, "run.gif")])
def test_unwritable_paths_are_input_errors_and_leave_no_file(short_run, tmp_path, save, name):
    missing = tmp_path / "no" / "such" / "dir" / name
    with pytest.raises(InputError, match="cannot write") as err:
        save(short_run, missing)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "no").exists()
    directory = tmp_path / name  # a directory where the file should go
    directory.mkdir()
    with pytest.raises(InputError, match="cannot write"):
        save(short_run, directory)
    assert directory.is_dir() and not any(directory.iterdir())
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # no temporary file beside it


def test_animation_wants_a_gif_path(short_run, tmp_path):
    with pytest.raises(InputError, match=r"\.gif"):
        save_animation(short_run, tmp_path / "run.mp4")
    assert not any(tmp_path.iterdir())


def test_legend_names_replans_collisions_traps_and_sensed_points(eventful):
    texts = legend_texts(draw_run(None, eventful))
    assert "checkpoints (2)" in texts
    assert "checkpoints after event at 6.0 s (1)" in texts
    assert "checkpoints after recovery at 8.0 s (1)" in texts
    assert "collisions (2)" in texts
    assert "trap detected (1)" in texts
    assert any(t.startswith("sensed points added to the map") for t in texts)
    assert any(t.startswith("added at 6 s") for t in texts)  # the event's shape
    assert "movers' lanes the route keeps off" in texts


def test_a_lane_two_plans_keep_off_is_drawn_once_hatched(eventful):
    ax = draw_run(None, eventful)
    hatched = [p for p in ax.patches if p.get_hatch() == "\\\\"]  # events' shapes: "///"
    assert len(hatched) == 1 and np.allclose(hatched[0].get_xy()[:4], LANE.vertices())


def test_legend_leaves_out_what_did_not_happen(short_run):
    texts = legend_texts(draw_run(None, short_run))
    assert any(t.startswith("checkpoints") for t in texts)
    assert not any("collision" in t or "trap" in t or "sensed" in t or "lanes" in t for t in texts)
    assert any(t.startswith("moving obstacles") for t in texts)  # on a circle: no lane


def test_title_names_world_architecture_seed_and_outcome(eventful):
    title = run_title(eventful)
    assert title.startswith("three-rooms-changed — fusion:beta=0.6, seed 3")
    assert "not reached: time limit" in title and "10.0 s" in title and "2 collisions" in title


def test_architecture_label_keeps_only_changed_parameters():
    assert architecture_label(str(parse_architecture("fusion"))) == "fusion"
    assert architecture_label(str(parse_architecture("fusion:beta=0.6"))) == "fusion:beta=0.6"
    assert architecture_label("unknown:x=1") == "unknown"


def test_sensed_points_are_those_the_recoveries_added(eventful):
    assert sensed_points(eventful).tolist() == [[0.75, 0.35], [0.75, 0.36]]
    assert len(sensed_points(eventful, until=7.9)) == 0  # no recovery yet


def test_frame_times_cover_the_run_and_are_capped():
    t = frame_times(30.0, fps=25.0, speed=2.5, max_frames=1000)
    assert t[0] == 0.0 and t[-1] == 30.0 and np.allclose(np.diff(t), 0.1)
    t = frame_times(120.0, fps=25.0, speed=2.5, max_frames=300)
    assert len(t) == 300 and t[-1] == 120.0 and np.all(np.diff(t) > 0)


def test_animation_of_an_eventful_run(eventful, tmp_path):
    with Image.open(save_animation(eventful, tmp_path / "eventful.gif", max_frames=6)) as gif:
        assert gif.n_frames > 1


def test_a_failed_write_leaves_no_partial_gif(short_run, tmp_path, monkeypatch):
    import matplotlib.animation

    def full_disk(self):
        with open(self.outfile, "wb") as f:  # half a file, then the disk is full
            f.write(b"GIF89a")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(matplotlib.animation.PillowWriter, "finish", full_disk)
    with pytest.raises(InputError, match="No space left"):
        save_animation(short_run, tmp_path / "run.gif", max_frames=3)
    assert not any(tmp_path.iterdir())


def test_a_gif_shows_its_progress_frame_by_frame_on_stderr_when_asked(tmp_path, capsys):
    """Issue 34: a game's GIF took a minute with nothing shown; the one GIF writer counts its frames."""
    from matplotlib.figure import Figure

    from robots.plot import save_gif

    fig = Figure(figsize=(1, 1))
    ax = fig.add_subplot()
    seen = []
    save_gif(fig, lambda k: seen.append(k) or [], [0, 1, 2], tmp_path / "quiet.gif", fps=5, dpi=20)
    assert capsys.readouterr().err == "" and (tmp_path / "quiet.gif").read_bytes()[:6] == b"GIF89a"
    save_gif(fig, lambda k: ax.set_title(str(k)), [0, 1, 2], tmp_path / "shown.gif", fps=5, dpi=20, progress=True)
    err = capsys.readouterr().err
    assert "writing shown.gif" in err and "3/3" in err and seen[-3:] == [0, 1, 2]


def test_a_comparison_thumbnail_marks_each_collision_where_it_began_not_at_the_goal():
    """A run that collided at a door and then stopped at the goal: a red cross at the door, a red ring at the
    goal (arrived, not reached)."""
    from matplotlib.figure import Figure

    from evaluation.compare_plot import _draw_cell, end_marker
    from robots.worldnames import load_world

    world = load_world("open-arena")
    gx, gy = world.goal_at(0.0)
    record = {"reached": False, "trapped": False, "arrived": True, "path": [[0.2, 0.2], [0.5, 0.4], [gx, gy]],
              "collided_at": [[0.5, 0.4]]}
    ax = Figure().add_subplot()
    _draw_cell(ax, world, record)
    crosses = [tuple(line.get_xydata()[0]) for line in ax.lines if line.get_marker() == "x"]
    rings = [tuple(line.get_xydata()[0]) for line in ax.lines if line.get_marker() == "o"]
    assert crosses == [(0.5, 0.4)] and rings == [(gx, gy)]
    assert end_marker({**record, "arrived": False}) == ("x", "red")
    assert end_marker({**record, "reached": True}) == ("o", "tab:green")
