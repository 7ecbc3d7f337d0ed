"""Drawing a soccer game, animating it, and drawing a round robin's standings.

:func:`save_match` puts a whole :class:`~evaluation.match.MatchRecord` on one figure: the field and its goals,
each robot's path (side 0 blue, side 1 red), the ball's path in black, and a star where every goal fell.
:func:`save_match_animation` plays the game as a GIF (matplotlib's Pillow writer). :func:`save_standings`
draws each player's mean goal difference per game and its win rate, each with its 95 % interval.
Figures are built on :class:`matplotlib.figure.Figure` (headless), files written atomically; an unwritable
path raises :class:`ekm.errors.InputError` and leaves nothing behind.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib import patches
from matplotlib.figure import Figure

from ekm.errors import InputError
from evaluation.match import MatchRecord
from robots.params import KHEPERA
from robots.plot import save_figure
from robots.soccer.field import Field

SIDE_COLORS = ("tab:blue", "tab:red")


def draw_field(ax, field: Field) -> None:
    """The walls (their thickness to scale), the half-way line and the centre spot on ``ax``."""
    for seg in field.walls():
        (x0, y0), (x1, y1) = seg.start, seg.end
        ax.plot([x0, x1], [y0, y1], color="0.25", lw=1.0, solid_capstyle="round")
    ax.plot([0.5 * field.length] * 2, [0, field.width], color="0.8", lw=0.8, zorder=0)
    ax.add_patch(patches.Circle(field.centre_spot, 0.006, color="0.7", zorder=0))
    for side in (0, 1):
        x0, y0, x1, y1 = field.goal_box(side)
        ax.add_patch(patches.Rectangle((x0, y0), x1 - x0, y1 - y0, color=SIDE_COLORS[side], alpha=0.12, lw=0))
    ax.set_aspect("equal")
    ax.set_xlim(-field.goal_depth - 0.03, field.length + field.goal_depth + 0.03)
    ax.set_ylim(-0.03, field.width + 0.03)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _broken(xy: np.ndarray, jump: float = 0.1) -> np.ndarray:
    """``xy`` ``(T, 2)`` with a NaN row wherever it jumps more than ``jump`` m in one tick (a kick-off puts the
    ball and the robots back): the line breaks there instead of crossing the field."""
    cut = np.flatnonzero(np.hypot(*np.diff(xy, axis=0).T) > jump) + 1
    return np.insert(xy.astype(float), cut, np.nan, axis=0)


def _title(rec: MatchRecord) -> str:
    a, b = rec.goals
    return (f"{rec.players[0]} (blue, defends x = 0) {a} – {b} {rec.players[1]} (red)\n"
            f"{rec.minutes:g} min, seed {rec.seed}, rule {rec.rule}")


def save_match(rec: MatchRecord, path: str | os.PathLike, dpi: int = 130) -> Path:
    """Draw the whole game (module docstring) and write it to ``path`` (format from the suffix)."""
    _check_writable(Path(path), "plot")
    fig = Figure(figsize=(8.0, 5.6), layout="constrained")
    ax = fig.add_subplot()
    draw_field(ax, rec.field)
    for side in (0, 1):
        xy = _broken(rec.poses[:, side, :2])
        ax.plot(xy[:, 0], xy[:, 1], color=SIDE_COLORS[side], lw=0.5, alpha=0.55, label=rec.players[side])
    ball = _broken(rec.ball)
    ax.plot(ball[:, 0], ball[:, 1], color="k", lw=0.6, alpha=0.7, label="ball")
    for t, side in rec.goal_log:
        k = min(int(np.searchsorted(rec.times, t)), len(rec.times) - 1)
        x = rec.field.goal_x(1 - side)
        ax.plot([x], [rec.ball[max(k - 1, 0), 1]], marker="*", ms=13, color=SIDE_COLORS[side], mec="k", ls="none")
    fig.suptitle(_title(rec), fontsize="small")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize="small", frameon=False)
    return save_figure(fig, path, dpi=dpi)


def save_match_animation(rec: MatchRecord, path: str | os.PathLike, fps: float = 20.0, speed: float = 8.0,
                         max_frames: int = 600, dpi: int = 80, progress: bool = False) -> Path:
    """Play the game as a GIF at ``speed``× real time (thinned to at most ``max_frames`` frames); ``progress``: a
    bar of the frames on stderr (:func:`robots.plot.save_gif`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from robots.plot import save_gif

    path = Path(path)
    _check_writable(path, "animation")
    duration = float(rec.times[-1])
    step = max(speed / fps, duration / max(max_frames - 1, 1))
    frames = np.searchsorted(rec.times, np.arange(0.0, duration + 1e-9, step))
    frames = np.minimum(frames, len(rec.times) - 1)
    fig = Figure(figsize=(6.4, 4.6), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    draw_field(ax, rec.field)
    r = KHEPERA.radius
    bodies = [ax.add_patch(patches.Circle((0, 0), r, color=c, alpha=0.85)) for c in SIDE_COLORS]
    heads = [ax.plot([], [], color="k", lw=1.2)[0] for _ in SIDE_COLORS]
    ball = ax.add_patch(patches.Circle((0, 0), 0.02, color="orange", ec="k", lw=0.5))
    goals = np.array([t for t, _ in rec.goal_log])
    sides = np.array([s for _, s in rec.goal_log], int)

    def update(k):
        for side in (0, 1):
            x, y, th = rec.poses[k, side]
            bodies[side].center = (x, y)
            heads[side].set_data([x, x + r * np.cos(th)], [y, y + r * np.sin(th)])
        ball.center = tuple(rec.ball[k])
        done = goals <= rec.times[k] + 1e-9
        a, b = int(np.sum(sides[done] == 0)), int(np.sum(sides[done] == 1))
        ax.set_title(f"{rec.players[0]} (blue) {a} – {b} {rec.players[1]} (red)    t = {rec.times[k]:5.1f} s",
                     fontsize="small")
        return []

    return save_gif(fig, update, frames, path, fps=fps, dpi=dpi, progress=progress)


def save_standings(rows: list[dict], path: str | os.PathLike, title: str = "", dpi: int = 130) -> Path:
    """Each player's mean goal difference per game and win rate, with 95 % intervals (:func:`evaluation.match.standings`)."""
    _check_writable(Path(path), "plot")
    rows = [r for r in rows if r["games"]]
    fig = Figure(figsize=(8.0, 0.6 + 0.45 * max(len(rows), 1)), layout="constrained")
    gd, wr = fig.subplots(1, 2, sharey=True)
    y = np.arange(len(rows))[::-1]
    for ax, key, ci, label in ((gd, "goal_difference", "gd_ci95", "goal difference per game"),
                               (wr, "win_rate", "win_ci95", "win rate (a draw is half)")):
        m = np.array([r[key] for r in rows], float)
        lo = np.array([r[ci][0] for r in rows], float)
        hi = np.array([r[ci][1] for r in rows], float)
        ax.errorbar(m, y, xerr=[m - lo, hi - m], fmt="o", color="k", capsize=3)
        ax.axvline(0.0 if key == "goal_difference" else 0.5, color="0.7", lw=0.8)
        ax.set_xlabel(label)
    gd.set_yticks(y, [r["player"] for r in rows])
    if title:
        fig.suptitle(title, fontsize="small")
    return save_figure(fig, path, dpi=dpi)


def _check_writable(path: Path, what: str) -> None:
    if path.is_dir():
        raise InputError(f"{path}: cannot write the {what} (it is a directory)")
    if not path.parent.is_dir():
        raise InputError(f"{path}: cannot write the {what} (no directory {path.parent})")
