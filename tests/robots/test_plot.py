"""World plots (robots.plot): movers where they are, a legend naming every kind, and nothing left behind when
writing fails."""

from pathlib import Path

import pytest

from ekm.errors import InputError
from robots.plot import plot_world, save_figure
from robots.worldnames import load_world


def test_plot_draws_movers_where_they_are_and_names_every_kind_in_the_legend():
    world = load_world("three-rooms-moving")
    ax = plot_world(world, t=3.0)  # a quarter lap: the mover is at the top of its circle
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["walls", "moving obstacles", "their paths", "IR rays (17.5 cm)", "robot (start pose)", "goal"]
    mover = next(p for p in ax.patches if p.get_label() == "moving obstacles")
    assert mover.center == pytest.approx(world.moving[0].at(3.0).center)
    assert ax.get_title() == "three-rooms-moving at t = 3 s"
    changed = [t.get_text() for t in plot_world(load_world("three-rooms-changed")).get_legend().get_texts()]
    assert "added at 6 s (planner told)" in changed


def test_save_figure_leaves_nothing_behind_when_writing_fails(tmp_path):
    fig = plot_world(load_world("open-arena")).figure

    def broken(path, **kw):
        Path(path).write_bytes(b"half a PNG")
        raise OSError("disk full")

    fig.savefig = broken
    with pytest.raises(InputError, match="cannot write the plot.*disk full"):
        save_figure(fig, tmp_path / "arena.png")
    assert list(tmp_path.iterdir()) == []
