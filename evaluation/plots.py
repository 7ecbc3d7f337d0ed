"""Figures of thesis ch. 6.1: Fig. 6.1 (E during training; P, T, D after training, maps on the same
axes), Fig. 6.2 (input weights w_i = (α_i, d_i) of the trained neurons), and the test paths themselves
(what T and D measure)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter

from evaluation.protocol import EPSILONS
from robots.plot import save_figure

_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown")


def figure_6_1_6_2(results: list[dict]) -> Figure:
    """One figure for maps trained and tested by the ch. 6.1 protocol.

    ``results``: one dict per map with ``label``, ``curve`` (list of ``{step, E_mm, ...}``, may be
    empty), ``summary`` (the :func:`evaluation.metrics.summarize` dict after training) and ``w``
    (``(N², 2)`` input weights of one trained map, for Fig. 6.2).
    Top row: Fig. 6.1 (a) E vs training steps, (b) P(ε), (c) T(ε), (d) D(ε). Bottom row: Fig. 6.2.
    """
    fig = Figure(figsize=(14, 7.5), layout="constrained")
    grid = fig.add_gridspec(2, 4 * max(1, len(results)))
    span = grid.ncols // 4
    axes = [fig.add_subplot(grid[0, i * span:(i + 1) * span]) for i in range(4)]
    eps_mm = [round(e * 1000) for e in EPSILONS]
    for j, r in enumerate(results):
        colour, label = _COLOURS[j % len(_COLOURS)], r["label"]
        if r.get("curve"):
            steps = [p["step"] for p in r["curve"]]
            axes[0].plot(steps, [p["E_mm"] for p in r["curve"]], "o-", color=colour, label=label, ms=4)
        s = r["summary"]
        for ax, key in zip(axes[1:], ("P", "T", "D")):
            vals = [np.nan if s[key][str(e)] is None else s[key][str(e)] for e in eps_mm]
            ax.plot(eps_mm, vals, "o-", color=colour, label=label, ms=5)
    axes[0].set(title="(a) E during training (Eq. 6.1)", xlabel="training steps", ylabel="E (mm)", yscale="log")
    axes[0].xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x / 1000:g}k" if x else "0"))
    axes[1].set(title="(b) reaching probability P(ε)", xlabel="ε (mm)", ylabel="P(ε)", ylim=(0, 1.05))
    axes[2].set(title="(c) time-to-target T(ε) (Eq. 6.2)", xlabel="ε (mm)", ylabel="steps per metre")
    axes[3].set(title="(d) deviation D(ε) (Eq. 6.3)", xlabel="ε (mm)", ylabel="|path - straight| / straight")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    for ax in axes[1:]:
        ax.set_xticks(eps_mm)
    for j, r in enumerate(results):
        ax = fig.add_subplot(grid[1, j * 4:(j + 1) * 4] if len(results) > 1 else grid[1, :])
        w = np.asarray(r["w"])
        ax.plot(w[:, 0], w[:, 1], ".", color=_COLOURS[j % len(_COLOURS)], ms=5)
        ax.set(title=f"Fig. 6.2: trained input weights w_i — {r['label']} (max d {w[:, 1].max():.3f} m)",
               xlabel="α_i (rad)", ylabel="d_i (m)", xlim=(-np.pi, np.pi))
        ax.grid(alpha=0.3)
    return fig


def paths_figure(results: list[dict], arena, *, shown: int = 10) -> Figure:
    """The robot's paths through the first ``shown`` targets of the ch. 6.1 test, one panel per map.

    ``results``: one dict per map with ``label``, ``targets`` ``(N, 2)``, ``start`` ``(3,)``, ``xy``
    ``(N, m, 2)`` (the centre after every sub-step on each target, :func:`evaluation.protocol.trace_paths`)
    and ``summary`` (for the panel title). Paths are coloured by target; numbers mark the targets.
    """
    from matplotlib import colormaps
    from matplotlib.patches import Rectangle

    fig = Figure(figsize=(5.2 * len(results), 5.4), layout="constrained")
    cmap = colormaps["viridis"]
    for j, r in enumerate(results):
        ax = fig.add_subplot(1, len(results), j + 1)
        ax.add_patch(Rectangle((0, 0), arena[0], arena[1], fill=False, color="0.3", lw=1))
        targets, xy = np.asarray(r["targets"]), np.asarray(r["xy"])
        k = min(shown, len(targets))
        start = np.asarray(r["start"])[:2]
        for i in range(k):
            colour = cmap(i / max(1, k - 1))
            frm = start if i == 0 else targets[i - 1]
            ax.plot(*np.stack([frm, targets[i]]).T, ":", color="0.6", lw=0.8)
            ax.plot(*np.vstack([frm if i == 0 else xy[i - 1, -1], xy[i]]).T, "-", color=colour, lw=1.4)
            ax.plot(*targets[i], "x", color=colour, ms=7, mew=2)
            ax.annotate(str(i + 1), targets[i], textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax.plot(*start, "o", color="k", ms=5)
        s = r["summary"]
        t25, d25 = s["T"]["25"], s["D"]["25"]  # None when no target was come within 25 mm of
        figures = "no target within 25 mm" if t25 is None else f"T(25) {t25:.1f} steps/m, D(25) {d25:.3f}"
        ax.set(title=f"{r['label']}: first {k} targets\n{figures}",
               xlabel="x (m)", ylabel="y (m)", xlim=(0, arena[0]), ylim=(0, arena[1]), aspect="equal")
        ax.grid(alpha=0.3)
    return fig


def save_paths_figure(results: list[dict], arena, path, *, shown: int = 10) -> None:
    """Draw :func:`paths_figure` and write it atomically to ``path``."""
    save_figure(paths_figure(results, arena, shown=shown), path, dpi=110)
