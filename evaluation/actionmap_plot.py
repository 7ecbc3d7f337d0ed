"""Samba's action maps at one moment of a run, drawn as polar heatmaps beside the run (``ekm run --maps-at T``).

Riekki draws velocity maps as surfaces over (direction, speed) with the robot's heading up (1999, Figs.
13–15, 19, 22, 23: "in all figures, action maps are presented at this same orientation"). Here each map is a
polar heatmap: the angle is the action's direction in the robot frame (ahead up, left to the left), the
radius its speed (0 … c*), the colour its weight — blue for Goto weights (+1 = reached at once), red for
Avoid weights (−1), white for zero — on one scale for the three maps: the Goto map of the current checkpoint,
the Avoid map of the obstacle markers after the time-to-collision filter, and their MAV composite, with the
action the arbiter chose marked (★) and the checkpoint's direction drawn as a dashed ray.

The maps are not recorded during a run — the runner does not know what it runs (docs/design.md §5). A
run is a pure function of (world, architecture, seed), so :func:`record_tick` runs it again with the
controller wrapped to keep every tick's (state, observation), and
:func:`samba.maps <robots.controllers.samba.maps>`, pure, recomputes from the one nearest T the very
maps that tick used::

    rec, moment = record_tick(load_world("three-rooms-static"), parse_architecture("samba"), at=5.0)
    save_run_with_maps(rec, moment, "maps.png")
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ekm.errors import InputError
from evaluation.scenario import RunRecord, ScenarioConfig, run_scenario
from evaluation.scenario_plot import _check_writable, _outline, draw_run
from robots.plot import save_figure

#: Colour map of the weights: red for Avoid (−1), white for 0, blue for Goto (+1).
WEIGHT_CMAP = "RdBu"


@dataclass(frozen=True)
class Moment:
    """One recorded tick: its time ``t``, the controller's ``state`` before it and its ``obs``, and the
    :class:`~robots.controllers.samba.Tick` that :func:`samba.maps` recomputes from them."""

    t: float
    state: Any
    obs: Any
    tick: Any
    params: Any
    robot: Any


def record_tick(world, spec, at: float, seed: int = 0, config: ScenarioConfig = ScenarioConfig()):
    """Run ``spec`` (Samba) through ``world`` with the controller wrapped to record every tick's (state,
    observation); return the run's :class:`RunRecord` and the :class:`Moment` of the tick nearest ``at`` s
    (the last tick if the run ended before). Raises :class:`InputError` for an architecture without maps."""
    if spec.name != "samba":
        raise InputError(f"--maps-at: architecture {spec.name} has no action maps (only samba has)")
    controller = spec.build()
    seen: list = []
    inner = controller.step

    def step(state, obs):
        seen.append((float(obs.t), state, obs))
        return inner(state, obs)

    rec = run_scenario(world, replace(controller, step=step), seed=seed, config=config)
    if not seen:
        raise InputError(f"--maps-at {at:g}: the run has no control ticks")
    k = int(np.argmin([abs(t - at) for t, _, _ in seen]))
    t, state, obs = seen[k]
    tick = _jitted_maps()(state, obs, p=controller.params, robot=controller.robot)  # eagerly it compiles op by op
    return rec, Moment(t, state, obs, tick, controller.params, controller.robot)


@functools.cache
def _jitted_maps():
    import jax

    from robots.controllers import samba

    return jax.jit(samba.maps, static_argnames=("p", "robot"))


# ---------------------------------------------------------------------------------------------- drawing

def draw_map(ax, weights, moment: Moment, title: str, mark: bool = True):
    """One velocity map ``(n_dir, n_speed)`` on the polar axes ``ax`` (heading up, left to the left), the
    chosen action (★) and the checkpoint's direction (dashed)."""
    p, robot = moment.params, moment.robot
    grid = p.grid(robot)
    w = np.asarray(weights, dtype=float)
    half = 0.5 * grid.step_angle
    order = np.argsort(grid.angles())  # directions increasing from −π, for the mesh's edges
    theta_sorted = np.append(np.sort(grid.angles()).astype(float) - half, np.max(grid.angles()) + half)
    r = grid.step_speed * (np.arange(grid.speeds + 1) + 0.5)  # speed edges round s_j = (j + 1) Δs
    mesh = ax.pcolormesh(theta_sorted, r, w[order].T, cmap=colormaps[WEIGHT_CMAP], norm=Normalize(-1.0, 1.0),
                         shading="flat")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(1)  # anticlockwise: + = left, as the robot frame
    ax.set_ylim(0.0, r[-1])
    ax.set_yticks([s for s in (0.04, 0.08, 0.12, 0.16) if s <= grid.max_speed + 1e-9])
    ax.set_yticklabels([f"{s:.2f}" for s in ax.get_yticks()], fontsize="x-small", color="0.3")
    ax.set_rlabel_position(-157.5)
    ax.set_xticks(np.radians([0, 45, 90, 135, 180, 225, 270, 315]))
    ax.set_xticklabels(["ahead", "45°", "left", "135°", "behind", "−135°", "right", "−45°"], fontsize="x-small")
    ax.grid(True, color="0.6", linewidth=0.4, alpha=0.6)
    alpha_t = float(moment.obs.target[0])
    ax.plot([alpha_t, alpha_t], [0.0, r[-1]], color="tab:green", linestyle="--", linewidth=1.2)
    if mark and bool(moment.tick.go):
        j = int(moment.tick.j)
        ax.plot([float(moment.tick.direction)], [grid.speed_values()[j]], marker="*", markersize=14,
                color="gold", markeredgecolor="black", markeredgewidth=0.8, linestyle="none", zorder=5)
    ax.set_title(title, fontsize="small", pad=12)
    return mesh


def draw_moment(ax, moment: Moment) -> None:
    """On the run's axes: the robot at the moment (thick outline), the obstacle points Samba remembered
    then (black dots) and its current checkpoint (a green ring)."""
    x, y, th = (float(v) for v in moment.obs.pose)
    _outline(ax, (x, y, th), "crimson", radius=moment.robot.radius, lw=2.2, zorder=11,
             label=f"robot at t = {moment.t:.2f} s (maps below)")
    objects = np.asarray(moment.tick.objects)
    valid = np.asarray(moment.tick.valid)
    n = moment.params.memory_points
    pts = objects[:n][valid[:n], :2]
    if len(pts):
        c, s = math.cos(th), math.sin(th)
        world_pts = np.stack([x + c * pts[:, 0] - s * pts[:, 1], y + s * pts[:, 0] + c * pts[:, 1]], axis=1)
        ax.add_line(Line2D(world_pts[:, 0], world_pts[:, 1], marker=".", markersize=4, color="black",
                           linestyle="none", zorder=10.5, label=f"obstacle points remembered then ({len(pts)})"))
    a, d = (float(v) for v in moment.obs.target)
    ax.add_line(Line2D([x + d * math.cos(th + a)], [y + d * math.sin(th + a)], marker="o", markersize=12,
                       fillstyle="none", color="tab:green", mew=2, linestyle="none", zorder=10.5,
                       label="checkpoint then"))


def draw_run_with_maps(rec: RunRecord, moment: Moment) -> Figure:
    """The run figure (:func:`evaluation.scenario_plot.draw_run`) with the Goto, filtered Avoid and MAV maps of
    ``moment`` below it."""
    w, h = rec.world.size
    run_h = min(max(9.0 * h / w, 3.2), 5.5)  # a square arena no taller than 5.5 in, so the maps keep their room
    run_w = max(run_h * w / h, 7.0) if run_h * w / h < 9.0 else 9.0
    fig = Figure(figsize=(run_w + 4.6, run_h + 5.2), dpi=100, layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[run_h + 1.2, 4.0])
    ax = top.add_subplot()
    draw_moment(ax, moment)
    draw_run(ax, rec)
    axes = bottom.subplots(1, 3, subplot_kw={"projection": "polar"})
    tick, p = moment.tick, moment.params
    a, d = (float(v) for v in moment.obs.target)
    speed = float(tick.speed)
    chosen = (f"chosen ★: {math.degrees(float(tick.direction)):+.0f}°, "
              f"{moment.params.grid(moment.robot).speed_values()[int(tick.j)]:.2f} m/s"
              + (f" (wheels: {speed * max(math.cos(float(tick.direction)), 0.0):.2f} m/s ahead while turning)")
              if bool(tick.go) else "no positive action: stop")
    titles = (f"Goto, checkpoint {1000 * d:.0f} mm at {math.degrees(a):+.0f}° (dashed)",
              f"Avoid, actions colliding after {p.avoid_ttc:g} s filtered",
              "MAV(Goto, Avoid) composite")
    mesh = None
    for axis, weights, title in zip(axes, (tick.goto, tick.avoid, tick.composite), titles):
        mesh = draw_map(axis, weights, moment, title)
    bar = bottom.colorbar(mesh, ax=list(axes), shrink=0.8, pad=0.02, aspect=25)
    bar.set_label("weight (+ Goto, − Avoid)", fontsize="small")
    top_speed = p.grid(moment.robot).max_speed
    bottom.suptitle(f"Samba's velocity maps at t = {moment.t:.2f} s — {chosen}\n"
                    f"(direction in the robot frame, heading up; radius = speed 0–{top_speed:.2f} m/s)",
                    fontsize="medium")
    return fig


def save_run_with_maps(rec: RunRecord, moment: Moment, path: str | os.PathLike, dpi: int = 130) -> Path:
    """Draw :func:`draw_run_with_maps` and write it to ``path`` atomically; returns the path."""
    _check_writable(Path(path), "plot")
    return save_figure(draw_run_with_maps(rec, moment), path, dpi=dpi)
