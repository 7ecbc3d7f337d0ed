"""The adaptation experiment's figure (:mod:`evaluation.adaptation`): E, T(5), D(25) against training steps."""

from __future__ import annotations

#: The three maps of a robot: how each is drawn.
STYLE = {"frozen": dict(color="0.45", ls="--", lw=1.2), "fine-tuned": dict(color="tab:blue", lw=1.6),
         "scratch": dict(color="tab:orange", lw=1.2)}
PANELS = (("E_mm", "E (mm)"), ("T5", "T(5) (steps/m)"), ("D25", "D(25)"))


def _value(point, key):
    if key == "E_mm":
        return point["E_mm"]
    return point[key[0]].get(key[1:])


def adaptation_figure(rows: list[dict]):
    """A row of panels per robot — E (with its 95 % interval), T(5), D(25) — each with the frozen, fine-tuned and
    from-scratch maps' curves; E's axis is cut at 10 mm (an untrained map is metres off)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(rows), len(PANELS), figsize=(11, 2.3 * len(rows) + 0.6), squeeze=False,
                             sharex=True)
    for row, axrow in zip(rows, axes):
        for (key, label), ax in zip(PANELS, axrow):
            for mode, curve in row["curves"].items():
                steps = [p["step"] for p in curve]
                ys = [_value(p, key) for p in curve]
                ax.plot(steps, [float("nan") if y is None else y for y in ys], label=mode, **STYLE[mode])
                if key == "E_mm":
                    lo = [p["E_ci95"][0] for p in curve]
                    hi = [p["E_ci95"][1] for p in curve]
                    ax.fill_between(steps, lo, hi, color=STYLE[mode]["color"], alpha=0.15, lw=0)
            if key == "E_mm":
                ax.set_ylim(0, 10)
                ax.axhline(3.0, color="k", lw=0.6, ls=":")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        axrow[0].set_title(row["robot"], loc="left", fontsize=10, fontweight="bold")
    axes[0, -1].legend(loc="upper right", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("training steps (1.024 s)")
    fig.tight_layout()
    return fig
