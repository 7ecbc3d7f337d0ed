"""Drawing worlds to scale with matplotlib (the thesis's Figs. 6.3–6.8 style: robot, obstacles, rooms
"drawn to the same scale").

Figures are built on :class:`matplotlib.figure.Figure` directly, never through ``pyplot``: no GUI
backend, no global figure state, safe on a headless machine (PNG output goes through Agg)::

    from robots.plot import plot_world, save_figure
    ax = plot_world(load_world("concave-obstacle"))
    save_figure(ax.figure, "concave-obstacle.png")
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
from matplotlib import patches
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ekm.errors import InputError
from ekm.files import atomic_write
from robots.geometry import Box, Circle, Polygon, Segment, Shape
from robots.params import KHEPERA, LONG_RANGE, RobotParams, SensorSet
from robots.sensors import sensor_rays
from robots.worldfile import CirclePath, World

#: Colours of the things in a world (known obstacles grey as on the planner's map; unforeseen ones red).
STYLE = {
    "wall": dict(facecolor="0.25", edgecolor="0.25"),
    "obstacle": dict(facecolor="0.6", edgecolor="0.25"),
    "unforeseen": dict(facecolor="tab:red", edgecolor="darkred"),
    "event": dict(facecolor="none", edgecolor="tab:orange", hatch="///"),
    "moving": dict(facecolor="tab:purple", edgecolor="indigo"),
    "robot": dict(facecolor="0.8", edgecolor="black"),
}


def _capsule(a, b, r: float, n: int = 8) -> np.ndarray:
    """Outline ``(2n + 2, 2)`` of the points within ``r`` of segment ``a``–``b`` (a wall of thickness 2r)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    heading = math.atan2(b[1] - a[1], b[0] - a[0])
    cap = np.linspace(-math.pi / 2, math.pi / 2, n + 1)
    end = b + r * np.stack([np.cos(heading + cap), np.sin(heading + cap)], axis=1)
    start = a + r * np.stack([np.cos(heading + math.pi + cap), np.sin(heading + math.pi + cap)], axis=1)
    return np.concatenate([end, start])


def draw_shape(ax, shape: Shape, style: dict, label: str | None = None, thickness: float = 0.0, **kw):
    """Add ``shape`` to ``ax``: a filled patch, a capsule for a thick segment, a line for a thin one."""
    if isinstance(shape, Segment) and thickness <= 0.0:
        xs, ys = zip(shape.start, shape.end)
        ax.add_line(Line2D(xs, ys, color=style["edgecolor"], linewidth=2.0, label=label, **kw))
        return
    if isinstance(shape, Circle):
        patch = patches.Circle(shape.center, shape.radius)
    elif isinstance(shape, Segment):
        patch = patches.Polygon(_capsule(shape.start, shape.end, 0.5 * thickness), closed=True)
    elif isinstance(shape, (Box, Polygon)):
        patch = patches.Polygon(shape.vertices(), closed=True)
    else:
        raise TypeError(f"not a world shape: {shape!r}")
    patch.set(label=label, linewidth=1.0, **style, **kw)
    ax.add_patch(patch)


def _draw_path(ax, path, color: str, label: str | None, t: float) -> None:
    """A mover's path, dashed, with an arrow along its velocity at ``t``."""
    if isinstance(path, CirclePath):
        ax.add_patch(patches.Circle(path.center, path.radius, fill=False, linestyle="--", edgecolor=color,
                                    linewidth=1.0, label=label))
    else:
        xs, ys = zip(path.start, path.end)
        ax.add_line(Line2D(xs, ys, color=color, linestyle="--", linewidth=1.0, label=label))
    (x, y), (vx, vy) = path.position(t), path.velocity(t)
    speed = math.hypot(vx, vy)
    if speed > 0:
        k = 0.06 / speed  # a 6 cm arrow in the direction of travel
        ax.annotate("", xy=(x + k * vx, y + k * vy), xytext=(x, y),
                    arrowprops=dict(arrowstyle="->", color=color, linewidth=1.2), zorder=5)


def draw_robot(ax, pose, params: RobotParams = KHEPERA, sensors: SensorSet | None = LONG_RANGE,
               label: str | None = "robot") -> None:
    """The robot to scale at ``pose``: body disc, heading line and (unless ``sensors`` is None) its IR rays
    from the rim out to their range."""
    x, y, theta = map(float, pose)
    if sensors is not None:
        start, end = sensor_rays(np.asarray(pose, float), sensors, params.radius)
        ax.add_collection(LineCollection(np.stack([start, end], axis=1), colors="tab:blue", linewidths=0.6,
                                         alpha=0.6, label=f"IR rays ({100 * sensors.range_m:g} cm)"))
    ax.add_patch(patches.Circle((x, y), params.radius, linewidth=1.0, label=label, zorder=3, **STYLE["robot"]))
    ax.add_line(Line2D([x, x + params.radius * math.cos(theta)], [y, y + params.radius * math.sin(theta)],
                       color="black", linewidth=1.2, zorder=4))


def plot_world(world: World, ax=None, t: float = 0.0, sensors: SensorSet | None = LONG_RANGE,
               params: RobotParams = KHEPERA, pose=None):
    """Draw ``world`` at time ``t`` to scale and return the axes.

    Draws the arena border and walls (with their thickness), known obstacles (grey), unforeseen ones
    (red), shapes that events add (hatched, with their time), moving obstacles where they are at ``t``
    with their dashed paths and direction of travel, the robot at ``pose`` (default: the start pose) with
    its sensor rays, and the goal (a star; a moving goal also shows its dashed path).

    Parameters
    ----------
    world : World
    ax : matplotlib Axes, optional
        Drawn into if given; otherwise a new :class:`~matplotlib.figure.Figure` sized to the arena.
    t : float
        Time at which moving things are drawn.
    sensors : SensorSet or None
        Rays to draw around the robot (``None``: no rays).
    params : RobotParams
        The robot (its radius).
    pose : array ``(3,)``, optional
        Robot pose; the world's start pose by default.

    Returns
    -------
    matplotlib Axes (its ``.figure`` saves with :func:`save_figure`).
    """
    w, h = world.size
    if ax is None:
        width = 7.0
        ax = Figure(figsize=(width + 2.8, width * h / w + 0.8), layout="constrained").add_subplot()

    draw_fixed(ax, world)
    for i, mover in enumerate(world.moving):
        color = STYLE["moving"]["facecolor"]
        draw_shape(ax, mover.at(t), STYLE["moving"], "moving obstacles" if i == 0 else None)
        _draw_path(ax, mover.path, color, "their paths" if i == 0 else None, t)

    draw_robot(ax, world.start if pose is None else pose, params, sensors, label="robot (start pose)")
    gx, gy = world.goal_at(t)
    if world.moving_goal:
        _draw_path(ax, world.goal, "tab:green", "goal's path", t)
    ax.add_line(Line2D([gx], [gy], marker="*", markersize=14, color="tab:green", markeredgecolor="darkgreen",
                       linestyle="none", label="goal", zorder=5))

    frame(ax, world)
    ax.set_title(world.name if t == 0 else f"{world.name} at t = {t:g} s")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", frameon=False)
    return ax


def draw_fixed(ax, world: World) -> dict:
    """The world's fixed parts on ``ax``: border and walls (with their thickness), known (grey) and unforeseen (red)
    obstacles, and the shapes events add (hatched, labelled with their time); returns each event's patches,
    ``{event index: [patch, …]}``."""
    for i, wall in enumerate(world.border + world.walls):
        draw_shape(ax, wall, STYLE["wall"], "walls" if i == 0 else None, thickness=world.wall_thickness)
    for group, shapes, label in (("obstacle", world.obstacles, "known obstacles"),
                                 ("unforeseen", world.unforeseen, "unforeseen obstacles")):
        for i, shape in enumerate(shapes):
            draw_shape(ax, shape, STYLE[group], label if i == 0 else None)
    events = {}
    for k, event in enumerate(world.events):
        told = "planner told" if event.known else "unforeseen"
        before = len(ax.patches)
        for j, shape in enumerate(event.add):
            draw_shape(ax, shape, STYLE["event"], f"added at {event.at_s:g} s ({told})" if j == 0 else None)
        events[k] = list(ax.patches[before:])
    return events


def frame(ax, world: World) -> None:
    """``ax`` set to ``world``'s arena and its walls (2 cm round it at least), at equal aspect, axes in metres."""
    w, h = world.size
    margin = max(world.wall_thickness, 0.02)
    ax.set_xlim(-margin, w + margin)
    ax.set_ylim(-margin, h + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def save_gif(fig, update, frames, path: str | os.PathLike, *, fps: float, dpi: int, progress: bool = False,
             init_func=None) -> Path:
    """Animate ``fig`` — ``update(frame)`` for each of ``frames`` — into a GIF at ``path``, atomically (temporary
    file + rename), with :class:`matplotlib.animation.PillowWriter`; returns the path. ``progress``: a bar of the
    frames written on stderr (a long game's GIF takes a minute). The one GIF writer of the package (``ekm run
    --gif``, ``ekm match --gif``); a path that cannot be written raises :class:`ekm.errors.InputError`."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    path = Path(path)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(frames), unit="frame", desc=f"writing {path.name}", dynamic_ncols=True)
    try:
        with atomic_write(path) as tmp:
            anim = FuncAnimation(fig, update, frames=frames, init_func=init_func, blit=False, repeat=False,
                                 cache_frame_data=False)
            anim.save(tmp, writer=PillowWriter(fps=fps), dpi=dpi,
                      progress_callback=None if bar is None else lambda i, n: bar.update(1))
    except OSError as exc:
        raise InputError(f"{path}: cannot write the animation ({exc.strerror or exc})") from None
    finally:
        if bar is not None:
            bar.close()
    return path


def save_figure(fig, path: str | os.PathLike, dpi: int = 150) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) atomically: temp file + rename. Returns the path.

    A path that cannot be written raises :class:`ekm.errors.InputError` naming it.
    """
    path = Path(path)
    try:
        with atomic_write(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or "png")
    except OSError as exc:
        raise InputError(f"{path}: cannot write the plot ({exc.strerror or exc})") from None
    return path
