"""Drawing a run to scale like thesis Figs. 6.3–6.8, and animating it.

:func:`draw_run` / :func:`save_run` put a whole :class:`~evaluation.scenario.RunRecord` on one figure:
the world, the path coloured by time, the robot's outline at regular instants (moving obstacles and a
moving goal drawn at the same instants in the same colour, so the reader sees where they were when the
robot was there), the checkpoints of every plan, collisions, traps and, after a recovery, the sensed
points that joined the planner's map. :func:`save_animation` plays the same run as a GIF (matplotlib's
Pillow writer, no extra dependency).

Figures are built on :class:`matplotlib.figure.Figure`, never ``pyplot`` (headless, no global state),
and files are written atomically: an unwritable path raises :class:`ekm.errors.InputError` and leaves
nothing behind::

    rec = run_architecture(load_world("three-rooms-moving"), parse_architecture("fusion"))
    save_run(rec, "run.png")
    save_animation(rec, "run.gif")
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
from matplotlib import colormaps, patches
from matplotlib.collections import LineCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ekm.errors import InputError
from evaluation.scenario import SENSED, RunRecord
from robots.params import KHEPERA
from robots.plot import STYLE, draw_fixed, draw_shape, frame, save_figure
from robots.worldfile import CirclePath, World

#: Colours of the plans made after the first (event or recovery replans), in order.
REPLAN_COLORS = ("deeppink", "chocolate", "crimson", "olive", "dimgray")
#: The colour map of time: the path, the robot outlines and the movers drawn at the same instants.
TIME_CMAP = "viridis"
_NICE_STEPS = (2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 60.0, 120.0, 300.0)


# ---------------------------------------------------------------------------------------------- helpers

def architecture_label(spec: str) -> str:
    """The short name of the architecture spelled in full in ``spec`` (``name:k=v,...``): its name and only
    the parameters that differ from the defaults (``fusion``, ``fusion:beta=0.6``)."""
    try:
        from robots.controllers.spec import parse_architecture

        return parse_architecture(spec).label
    except Exception:  # an unknown or stale spelling: the name is still worth showing
        return spec.split(":")[0]


def outline_instants(duration: float, every: float = 2.0, most: int = 12) -> np.ndarray:
    """Times of the robot outlines: every ``every`` s, or a rounder, longer step so that there are at most
    ``most`` of them on a long run (start and end are drawn separately)."""
    step = next((s for s in (every,) + _NICE_STEPS if s >= every and duration / s <= most), _NICE_STEPS[-1])
    return np.arange(step, duration - 0.25 * step, step)


def _pose_at(rec: RunRecord, t: float) -> np.ndarray:
    """The recorded pose at (or just after) time ``t``."""
    k = min(int(np.searchsorted(rec.times, t - 1e-9)), len(rec.times) - 1)
    return rec.poses[k]


def _status(rec: RunRecord) -> str:
    """How the run went: reached, trapped (and why), or not reached and why it ended."""
    if rec.reached:
        return "reached the goal"
    if rec.trapped:
        return rec.ended if rec.ended.startswith("trapped") else "trapped"
    if rec.arrived:
        return "not reached: arrived with collisions"
    return f"not reached: {rec.ended or 'ended'}"


def run_title(rec: RunRecord) -> str:
    """Two-line title: world, architecture, seed; then outcome, time, path length, collisions."""
    extra = []
    if rec.replans:
        extra.append(f"{rec.replans} replan{'s' * (rec.replans != 1)}")
    if rec.recoveries:
        extra.append(f"{rec.recoveries} recover{'ies' if rec.recoveries != 1 else 'y'}")
    tail = (", " + ", ".join(extra)) if extra else ""
    return (f"{rec.world.name} — {architecture_label(rec.architecture)}, seed {rec.seed}\n"
            f"{_status(rec)}, {rec.time_s:.1f} s, path {rec.path_m:.2f} m, "
            f"{rec.collisions} collision{'s' * (rec.collisions != 1)}{tail}")


def sensed_points(rec: RunRecord, until: float = math.inf) -> np.ndarray:
    """``(n, 2)`` obstacle points that the recoveries and blocked checkpoints up to time ``until`` added to the
    planner's map."""
    added = [p.added for p in rec.plans if p.reason in SENSED and p.t <= until and len(p.added)]
    return np.vstack(added) if added else np.zeros((0, 2))


def _new_axes(world: World, width: float, right: float, dpi: float = 100):
    """A constrained-layout figure whose axes hold the arena to scale: ``width`` inches wide (less for a
    tall arena, so that it stays under ``width`` high too), ``right`` inches to its right for the colorbar
    and the legend, and room for tick labels and a two-line title."""
    w, h = world.size
    ax_w = min(width, width * w / h)
    ax_h = ax_w * h / w
    fig = Figure(figsize=(ax_w + 0.8 + right, max(ax_h + 1.2, 3.8)), dpi=dpi, layout="constrained")
    return fig.add_subplot()


def draw_static(ax, world: World, t: float | None = None) -> dict:
    """The world's fixed parts (:func:`robots.plot.draw_fixed`).

    With ``t`` given (the animation), an event's shapes are drawn faintly before ``at_s`` and solid after;
    returns ``{event index: [(patch, at_s), ...]}`` so the caller can restyle them frame by frame.
    """
    events = {k: [(p, world.events[k].at_s) for p in patches] for k, patches in draw_fixed(ax, world).items()}
    if t is not None:
        _restyle_events(events, t)
    return events


def _restyle_events(events: dict, t: float) -> None:
    """Event shapes: a faint hatched outline until they appear, filled from then on."""
    for items in events.values():
        for patch, at_s in items:
            there = t >= at_s
            patch.set_facecolor("tab:orange" if there else "none")
            patch.set_alpha(0.9 if there else 0.35)


def _draw_mover_path(ax, path, color: str, label: str | None, linewidth: float = 1.0) -> None:
    """A mover's (or the goal's) path, dashed."""
    if isinstance(path, CirclePath):
        ax.add_patch(patches.Circle(path.center, path.radius, fill=False, linestyle="--", edgecolor=color,
                                    linewidth=linewidth, label=label, zorder=2))
    else:
        xs, ys = zip(path.start, path.end)
        ax.add_line(Line2D(xs, ys, color=color, linestyle="--", linewidth=linewidth, label=label, zorder=2))


def _outline(ax, pose, color, radius: float = KHEPERA.radius, lw: float = 0.9, alpha: float = 1.0,
             fill=None, label: str | None = None, zorder: float = 5) -> None:
    """The robot's body circle and a heading tick from centre to rim."""
    x, y, th = map(float, pose)
    ax.add_patch(patches.Circle((x, y), radius, fill=fill is not None, facecolor=fill or "none", edgecolor=color,
                                linewidth=lw, alpha=alpha, label=label, zorder=zorder))
    ax.add_line(Line2D([x, x + radius * math.cos(th)], [y, y + radius * math.sin(th)], color=color,
                       linewidth=lw + 0.3, alpha=alpha, zorder=zorder + 0.1))


def _plan_route(rec: RunRecord, change) -> np.ndarray:
    """The planned route of ``change``: from where the robot was when it was made through its checkpoints."""
    start = _pose_at(rec, change.t)[:2] if change.t > 0 else np.asarray(rec.world.start[:2])
    return np.vstack([start, change.checkpoints])


# ---------------------------------------------------------------------------------------------- the figure

def draw_run(ax, rec: RunRecord, outline_every: float = 2.0, title: str | None = None, colorbar: bool = True):
    """Draw ``rec`` to scale on ``ax`` (a new figure sized to the arena if None); return the axes.

    Drawn: the world (walls, known/unforeseen obstacles, event shapes); the path coloured by time (with
    a colorbar); the robot's outline every ``outline_every`` s (a longer, round step on long runs),
    filled at start and end; moving obstacles (and a moving goal) at the same instants in the same colour,
    faintly, with their dashed paths; the first plan's checkpoints as dots and later plans' (event or
    recovery replans) as triangles, one colour each, with the time in the legend, each with its planned
    route dotted; the declared movers' lanes a plan keeps off (hatched); the goal (a star; a moving goal also
    at its start, faint); collisions (red crosses), trap detections (orange squares) and on recovery runs the
    sensed points that joined the map.
    """
    world = rec.world
    if ax is None:
        ax = _new_axes(world, width=6.5, right=3.9)
    fig = ax.figure
    cmap, duration = colormaps[TIME_CMAP], max(rec.time_s, 1e-9)
    norm = Normalize(0.0, duration)
    draw_static(ax, world)
    instants = outline_instants(rec.time_s, outline_every)
    all_t = np.concatenate([[0.0], instants, [rec.time_s]])

    # Moving obstacles and a moving goal where they were at the outline instants, in the instant's colour.
    purple = STYLE["moving"]["facecolor"]
    for i, mover in enumerate(world.moving):
        _draw_mover_path(ax, mover.path, purple, "moving obstacles' paths" if i == 0 else None)
        for s in all_t:
            draw_shape(ax, mover.at(float(s)), dict(facecolor=cmap(norm(s)), edgecolor=cmap(norm(s))), alpha=0.22,
                       zorder=3)
        draw_shape(ax, mover.at(rec.time_s), dict(facecolor="none", edgecolor="indigo"),
                   "moving obstacles at the end" if i == 0 else None, zorder=3.5)
    if world.moving:
        ax.add_patch(patches.Circle((0, 0), 0, facecolor=cmap(0.5), alpha=0.3, edgecolor="none", visible=False,
                                    label="… at the robot's instants"))
    if world.moving_goal:
        _draw_mover_path(ax, world.goal, "tab:green", "goal's path")
        g = np.array([world.goal_at(float(s)) for s in all_t])
        ax.scatter(g[:, 0], g[:, 1], marker="*", s=70, c=all_t, cmap=cmap, norm=norm, alpha=0.45,
                   edgecolors="none", zorder=4)

    # The path coloured by time, and the outlines.
    xy = rec.poses[:, :2]
    if len(xy) > 1:
        lc = LineCollection(np.stack([xy[:-1], xy[1:]], axis=1), cmap=cmap, norm=norm, linewidths=1.8, zorder=6)
        lc.set_array(rec.times[1:])
        ax.add_collection(lc)
        if colorbar:
            fig.colorbar(lc, ax=ax, label="time (s)", shrink=0.85, pad=0.015, aspect=25)
    for s in instants:
        _outline(ax, _pose_at(rec, s), cmap(norm(s)), lw=0.8, alpha=0.85)
    if len(instants):
        ax.add_line(Line2D([], [], marker="o", markersize=8, fillstyle="none", color=cmap(0.5), linestyle="none",
                           label=f"robot every {instants[0]:g} s (colour = time)"))
    _outline(ax, rec.poses[0], "black", fill="0.85", label="robot at start", zorder=7)
    _outline(ax, rec.poses[-1], "black", fill=cmap(1.0), alpha=0.9, label=f"robot at {rec.time_s:.1f} s (end)",
             zorder=7)

    # Plans: dots for the first, triangles in their own colour for replans; the route dotted.
    for i, change in enumerate(rec.plans):
        cps, first = np.asarray(change.checkpoints), i == 0 and change.reason == "start"
        color = "black" if first else REPLAN_COLORS[(i - 1) % len(REPLAN_COLORS)]
        route = _plan_route(rec, change)
        ax.add_line(Line2D(route[:, 0], route[:, 1], color=color, linestyle=":", linewidth=0.9, alpha=0.6,
                           zorder=5.5))
        label = (f"checkpoints ({len(cps) - 1})" if first
                 else f"checkpoints after {change.reason} at {change.t:.1f} s ({len(cps) - 1})")
        if len(cps) < 2:  # the goal alone: nothing to mark
            label = f"replanned after {change.reason} at {change.t:.1f} s" if not first else None
        ax.add_line(Line2D(cps[:-1, 0], cps[:-1, 1], marker="o" if first else "^", markersize=5 if first else 7,
                           color=color, markeredgecolor="white" if first else "black", markeredgewidth=0.5,
                           linestyle="none", zorder=8, label=label))

    lanes = list(dict.fromkeys(lane for change in rec.plans for lane in change.avoided))
    for i, lane in enumerate(lanes):
        draw_shape(ax, lane, dict(facecolor="none", edgecolor=purple, hatch="\\\\"), zorder=2.5, alpha=0.5,
                   label="movers' lanes the route keeps off" if i == 0 else None)
    if rec.plans:
        ax.add_line(Line2D([], [], color="black", linestyle=":", linewidth=0.9, alpha=0.6,
                           label="planned route" + ("s" if len(rec.plans) > 1 else "")))
    gx, gy = world.goal_at(rec.time_s)
    ax.add_line(Line2D([gx], [gy], marker="*", markersize=15, color="tab:green", markeredgecolor="darkgreen",
                       linestyle="none", zorder=9,
                       label=f"goal at {rec.time_s:.1f} s (faint: earlier)" if world.moving_goal else "goal"))

    if rec.collision_log:
        c = np.asarray(rec.collision_log, dtype=float)
        ax.add_line(Line2D(c[:, 1], c[:, 2], marker="x", color="red", markersize=9, mew=2, linestyle="none",
                           zorder=10, label=f"collisions ({len(c)})"))
    if rec.trap_log:
        c = np.asarray(rec.trap_log, dtype=float)
        ax.add_line(Line2D(c[:, 1], c[:, 2], marker="s", color="darkorange", markersize=9, fillstyle="none",
                           mew=2, linestyle="none", zorder=10, label=f"trap detected ({len(c)})"))
    sensed = sensed_points(rec)
    if len(sensed):
        ax.add_line(Line2D(sensed[:, 0], sensed[:, 1], marker=".", markersize=3, color="0.35", alpha=0.7,
                           linestyle="none", zorder=4, label=f"sensed points added to the map ({len(sensed)})"))

    frame(ax, world)
    ax.set_title(title or run_title(rec), fontsize="medium")
    # The legend outside, right of the colorbar (constrained layout makes room for it).
    handles, labels = ax.get_legend_handles_labels()
    handles = [h if h.get_visible() else patches.Patch(facecolor=h.get_facecolor(), edgecolor="none")
               for h in handles]  # legend-only proxies are hidden on the axes
    fig.legend(handles, labels, loc="outside right upper", fontsize="small", frameon=False)
    return ax


def save_run(rec: RunRecord, path: str | os.PathLike, dpi: int = 150, **kw) -> Path:
    """Draw ``rec`` (:func:`draw_run`; keywords passed on) and write it to ``path`` atomically (format from
    the suffix). Returns the path; an unwritable path raises :class:`ekm.errors.InputError`."""
    _check_writable(Path(path), "plot")
    ax = draw_run(None, rec, **kw)
    return save_figure(ax.figure, path, dpi=dpi)


def _check_writable(path: Path, what: str) -> None:
    """Fail before drawing when ``path`` clearly cannot be written (a directory, or in a missing one);
    the atomic write still catches anything else."""
    if path.is_dir():
        raise InputError(f"{path}: cannot write the {what} (it is a directory)")
    if not path.parent.is_dir():
        raise InputError(f"{path}: cannot write the {what} (no directory {path.parent})")


# ---------------------------------------------------------------------------------------------- the animation

def frame_times(duration: float, fps: float, speed: float, max_frames: int) -> np.ndarray:
    """Simulated times of the frames: ``fps / speed`` per simulated second (the GIF plays ``speed``× real
    time), thinned to at most ``max_frames`` (a long run then plays faster); the end is always the last."""
    step = speed / fps
    n = int(math.floor(duration / step)) + 1
    if n > max_frames - 1:
        step = duration / (max_frames - 1)
        n = max_frames - 1
    t = np.arange(n) * step
    return np.append(t[t < duration - 1e-9], duration)


def _checkpoint_state(rec: RunRecord, t: float):
    """The plan followed at ``t``, its index, and the index of the checkpoint it is heading for."""
    i = max((k for k, p in enumerate(rec.plans) if p.t <= t + 1e-9), default=0)
    change = rec.plans[i]
    cps, idx = np.asarray(change.checkpoints), 0
    for tc, x, y in rec.checkpoint_log:  # this plan's checkpoints reached so far, in order
        if change.t - 1e-9 <= tc <= t + 1e-9 and idx < len(cps) - 1 and np.allclose((x, y), cps[idx]):
            idx += 1
    return change, i, idx


def save_animation(rec: RunRecord, path: str | os.PathLike, fps: float = 25.0, speed: float = 2.5,
                   max_frames: int = 300, dpi: int = 80, progress: bool = False) -> Path:
    """Write the run as a GIF at ``path`` (``.gif``) and return the path; ``progress``: a bar of the frames on
    stderr.

    Each frame shows the world (event shapes appear at their time), the trail so far, the robot at its
    pose with its heading, the moving obstacles and a moving goal where they are, the plan being followed
    with its current checkpoint ringed, collisions and traps so far, and the time in the title. Frames are
    ``speed / fps`` simulated seconds apart (defaults: 25 fps played at 2.5× real time, i.e. 10 frames per
    simulated second), at most ``max_frames`` of them (a longer run plays faster): a 15 s run is ~150
    frames, ~0.6 MB at the default dpi. The static parts are rendered once (see :func:`_freeze_background`).

    Written atomically by :func:`robots.plot.save_gif` (temporary ``.gif`` next to ``path``, then a rename); an
    unwritable path raises :class:`ekm.errors.InputError` and leaves no file.
    """
    from robots.plot import save_gif

    path = Path(path)
    if path.suffix.lower() != ".gif":
        raise InputError(f"{path}: an animation is written as GIF; give a path ending in .gif")
    _check_writable(path, "animation")
    if len(rec.times) == 0:
        raise InputError(f"{path}: the run has no poses to animate")
    if not (fps > 0 and speed > 0 and max_frames >= 2):
        raise InputError(f"{path}: fps and speed must be > 0 and max_frames >= 2 (got {fps}, {speed}, {max_frames})")
    world = rec.world
    times = frame_times(rec.time_s, fps, speed, max_frames)
    ax = _new_axes(world, width=5.0, right=2.0, dpi=dpi)
    fig = ax.figure
    events = draw_static(ax, world, t=0.0)
    frame(ax, world)
    for i, mover in enumerate(world.moving):
        _draw_mover_path(ax, mover.path, STYLE["moving"]["facecolor"], "moving obstacles' paths" if i == 0 else None,
                         linewidth=0.7)
    if world.moving_goal:
        _draw_mover_path(ax, world.goal, "tab:green", "goal's path", linewidth=0.7)
    if world.moving:
        ax.add_line(Line2D([], [], color=STYLE["moving"]["facecolor"], marker="o", linestyle="none",
                           label="moving obstacles"))

    r = KHEPERA.radius
    trail = ax.add_line(Line2D([], [], color="tab:blue", linewidth=1.4, zorder=6, label="path so far"))
    body = patches.Circle(tuple(rec.poses[0, :2]), r, facecolor="0.85", edgecolor="black", linewidth=1.0, zorder=7,
                          label="robot")
    ax.add_patch(body)
    heading = ax.add_line(Line2D([], [], color="black", linewidth=1.4, zorder=7.1))
    plan_line = ax.add_line(Line2D([], [], color="0.3", linestyle=":", linewidth=0.9, zorder=5))
    plan_dots = ax.add_line(Line2D([], [], marker="o", markersize=4, color="0.3", linestyle="none", zorder=8,
                                   label="checkpoints of the plan"))
    current = ax.add_line(Line2D([], [], marker="o", markersize=11, fillstyle="none", color="tab:red", mew=1.8,
                                 linestyle="none", zorder=8.5, label="current checkpoint"))
    goal = ax.add_line(Line2D([], [], marker="*", markersize=14, color="tab:green", markeredgecolor="darkgreen",
                              linestyle="none", zorder=9, label="goal"))
    hits = ax.add_line(Line2D([], [], marker="x", color="red", markersize=8, mew=2, linestyle="none", zorder=10,
                              label="collisions" if rec.collision_log else None))
    traps = ax.add_line(Line2D([], [], marker="s", color="darkorange", markersize=8, fillstyle="none", mew=2,
                               linestyle="none", zorder=10, label="trap detected" if rec.trap_log else None))
    recoveries = sorted({p.t for p in rec.plans if p.reason in SENSED})
    sensed_at = {t_r: sensed_points(rec, until=t_r) for t_r in recoveries}
    sensed = ax.add_line(Line2D([], [], marker=".", markersize=3, color="0.35", alpha=0.7, linestyle="none",
                                zorder=4, label="sensed points added to the map" if recoveries else None))
    movers: list = []
    collisions = np.asarray(rec.collision_log, dtype=float).reshape(-1, 3)
    trapped = np.asarray(rec.trap_log, dtype=float).reshape(-1, 3)
    arch, run_speed = architecture_label(rec.architecture), (times[1] - times[0]) * fps if len(times) > 1 else speed
    fig.legend(*ax.get_legend_handles_labels(), loc="outside right upper", fontsize="x-small", frameon=False)

    def update(t: float):
        k = min(int(np.searchsorted(rec.times, t + 1e-9)), len(rec.times))
        xy = rec.poses[:max(k, 1), :2]
        trail.set_data(xy[:, 0], xy[:, 1])
        x, y, th = rec.poses[max(k, 1) - 1]
        body.set_center((x, y))
        heading.set_data([x, x + r * math.cos(th)], [y, y + r * math.sin(th)])
        while movers:
            movers.pop().remove()
        before = set(ax.patches) | set(ax.lines)
        for mover in world.moving:
            draw_shape(ax, mover.at(t), STYLE["moving"], zorder=4)
        movers.extend(a for a in list(ax.patches) + list(ax.lines) if a not in before)
        _restyle_events(events, t)
        if rec.plans:
            change, _, idx = _checkpoint_state(rec, t)
            route = _plan_route(rec, change)
            plan_line.set_data(route[:, 0], route[:, 1])
            cps = np.asarray(change.checkpoints)
            plan_dots.set_data(cps[:-1, 0], cps[:-1, 1])
            cx, cy = world.goal_at(t) if idx == len(cps) - 1 else cps[idx]
            current.set_data([cx], [cy])
        gx, gy = world.goal_at(t)
        goal.set_data([gx], [gy])
        seen = collisions[collisions[:, 0] <= t + 1e-9]
        hits.set_data(seen[:, 1], seen[:, 2])
        seen = trapped[trapped[:, 0] <= t + 1e-9]
        traps.set_data(seen[:, 1], seen[:, 2])
        done = [t_r for t_r in recoveries if t_r <= t + 1e-9]
        pts = sensed_at[done[-1]] if done else np.zeros((0, 2))
        sensed.set_data(pts[:, 0], pts[:, 1])
        ax.set_title(f"{world.name} — {arch}, seed {rec.seed}\nt = {t:5.1f} s of {rec.time_s:.1f} s "
                     f"({run_speed:.3g}× real time)", fontsize="small", y=1.01)  # y given: no auto-placement
        return []

    update(0.0)
    dynamic = [trail, body, heading, plan_line, plan_dots, current, goal, hits, traps, sensed, ax.title, *movers]
    dynamic += [p for items in events.values() for p, _ in items]
    _freeze_background(fig, ax, dynamic)
    return save_gif(fig, update, times, path, fps=fps, dpi=dpi, progress=progress, init_func=lambda: [])


def _freeze_background(fig, ax, dynamic: list) -> None:
    """Speed up the frames: lay the figure out once, render everything but the ``dynamic``
    artists (walls, axes, ticks, legend) to one image, and show that image instead of redrawing them.

    The frames must then be saved at the figure's own dpi (the image is in pixels).
    """
    from matplotlib.backend_bases import FigureCanvasBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)  # an Agg canvas to render into (headless, no pyplot)
    fig.canvas.draw()  # constrained layout runs once here; then the layout is kept as it is
    fig.set_layout_engine(None)
    for a in dynamic:
        a.set_visible(False)
    fig.canvas.draw()
    background = np.asarray(fig.canvas.buffer_rgba()).copy()
    keep = set(map(id, dynamic))
    for a in list(ax.get_children()) + list(fig.legends) + [fig.patch]:
        if id(a) not in keep:
            a.set_visible(False)
    for a in dynamic:
        a.set_visible(True)
    fig.figimage(background, xo=0, yo=0, origin="upper", zorder=-1)
    FigureCanvasBase(fig)  # FuncAnimation's draw_idle would otherwise render every frame twice; savefig renders
