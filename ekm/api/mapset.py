"""Trained maps in Python: :class:`Maps` (every trial of a training run), :class:`Map` (one trial) and
:func:`load`."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from ekm.api.result import Result, new_axes
from ekm.errors import InputError
from ekm.mapfile import SavedMaps

#: Metadata keys a map file's writer sets itself (:func:`ekm.mapfile.save_maps`); :meth:`Maps.save` leaves
#: them to it.
_WRITER_KEYS = ("format", "version", "mapping", "neurons", "trials", "ekm")


@dataclass(frozen=True)
class Maps(SavedMaps, Result):
    """The maps of every trial of one training run, stacked along a leading trial axis.

    Made by :func:`ekm.train` or :func:`ekm.load`. ``maps[i]`` is trial ``i``'s :class:`Map`, ``len(maps)``
    the number of trials. Fields (of :class:`ekm.mapfile.SavedMaps`): ``ekm`` the stacked map pytree,
    ``cfg`` its :class:`ekm.config.EKMConfig`, ``meta`` the training metadata, ``arena`` (m) and ``curve``
    the ch. 6.1 test after every ``eval_every`` steps; ``path`` the file they were loaded from or saved to
    by training (None for maps only in memory) and ``source`` what a run's record calls them.

    ``to_dict()`` is ``ekm train --json``; ``plot()`` draws Fig. 6.1/6.2 of the training curve.

    Example::

        maps = ekm.load()                     # the shipped indirect map, 5 trials
        left, right = maps[0].command(0.3, 0.1)   # wheel speeds (m/s) towards a target 0.1 m away, 0.3 rad left
    """

    path: str | None = None
    source: str = "maps in memory"

    def __len__(self) -> int:
        return self.trials

    def __getitem__(self, trial: int) -> "Map":
        if isinstance(trial, bool) or not isinstance(trial, int):
            raise InputError(f"trial {trial!r}: must be a whole number")
        if not -self.trials <= trial < self.trials:
            raise InputError(f"--trial {trial}: the map file holds trials 0..{self.trials - 1}")
        return Map(self, trial % self.trials)

    def __iter__(self):
        return (Map(self, i) for i in range(self.trials))

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        m, seconds = self.meta, self.meta.get("seconds")
        return {"mapping": self.cfg.mapping, "neurons": self.cfg.neurons, "steps": m.get("steps"),
                "trials": self.trials, "seconds": None if seconds is None else round(seconds, 3),
                "curve": list(self.curve), "out": self.path, "seed": m.get("seed"), "world": m.get("world"),
                "ekm": self.cfg.to_dict(), "train": m.get("train"), "test": m.get("test"), **provenance()}

    def save(self, path) -> Path:
        """Write the maps to ``path`` (``.npz``, atomically; its directory is created) with their metadata;
        returns the path. Read them back with :func:`ekm.load`.

        Example: ``maps.save("indirect.npz")``.
        """
        from ekm.api.checks import output_path
        from ekm.mapfile import save_maps

        out = output_path(path, "--out", ".npz")
        return save_maps(out, self.ekm, self.cfg, {k: v for k, v in self.meta.items() if k not in _WRITER_KEYS})

    def figure_entry(self, label: str | None = None, summary: dict | None = None) -> dict:
        """This run's entry for :func:`evaluation.plots.figure_6_1_6_2`: its curve, the first trial's weights
        and ``summary`` (by default the last test of the curve)."""
        import numpy as np

        if summary is None:
            if not self.curve:
                raise InputError(f"{self.source}: the maps carry no training curve to plot; "
                                 "ekm.evaluate(maps).plot() draws their test")
            summary = self.curve[-1] | {"trials": self.trials}
        return {"label": label or self.cfg.mapping, "curve": list(self.curve), "summary": summary,
                "w": np.asarray(self.ekm.w[0])}

    def plot(self):
        """Fig. 6.1/6.2 of the training: E during training, P, T, D of the last test, the first trial's
        input weights. Returns the matplotlib Figure (``fig.savefig("fig.png")``)."""
        from evaluation.plots import figure_6_1_6_2

        return figure_6_1_6_2([self.figure_entry()])

    def save_plot(self, path) -> Path:
        """:meth:`plot` written to a PNG, SVG or PDF (by its suffix) at ``path`` (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from robots.plot import save_figure

        out = plot_path(path, "--plot")
        save_figure(self.plot(), out, dpi=110)
        return out


@dataclass(frozen=True)
class Map:
    """One trial's trained map: ``maps[i]``. ``ekm`` is its pytree (no trial axis), ``cfg`` its config.

    Example::

        m = ekm.load()[2]
        m.command(0.0, 0.05)    # (left, right) wheel speeds in m/s for a target 5 cm straight ahead
    """

    maps: Maps
    trial: int

    @property
    def cfg(self):
        return self.maps.cfg

    @property
    def ekm(self):
        import jax

        return jax.tree.map(lambda a: a[self.trial], self.maps.ekm)

    def command(self, target_alpha: float, target_d: float) -> tuple[float, float]:
        """The wheel command c_p = (v_left, v_right) in m/s the map gives for a target at bearing
        ``target_alpha`` (rad, counter-clockwise from the robot's heading, wrapped to (-π, π]) and distance
        ``target_d`` (m): Eq. 4.5 of the winner (indirect maps; both wheels within ±c*) or the winner's
        output c_k (direct maps). The robot drives it for one 1.024 s step.

        Example: ``ekm.load()[0].command(0.5, 0.1)``.
        """
        import math

        import numpy as np

        from ekm.angles import wrap

        alpha, d = float(target_alpha), float(target_d)
        if not (math.isfinite(alpha) and math.isfinite(d)) or d < 0:
            raise InputError(f"target ({target_alpha}, {target_d}): needs a finite bearing (rad) and distance >= 0 (m)")
        alpha = wrap(alpha)
        c = np.asarray(_control(self.cfg)(self.ekm, np.array([alpha, d], np.float32)))
        return float(c[0]), float(c[1])

    def plot(self, ax=None):
        """Fig. 6.2 for this trial: its neurons' input weights w_i = (α_i, d_i) on ``ax`` (a new figure's if
        None); returns the axes."""
        import numpy as np

        ax = new_axes(ax, (6.0, 4.0))
        w = np.asarray(self.ekm.w)
        ax.plot(w[:, 0], w[:, 1], ".", ms=5)
        ax.set(title=f"input weights w_i, {self.cfg.mapping} map, trial {self.trial}", xlabel="α_i (rad)",
               ylabel="d_i (m)", xlim=(-np.pi, np.pi))
        ax.grid(alpha=0.3)
        return ax


@lru_cache(maxsize=None)
def _control(cfg):
    """``ekm.maps.control``'s command, jitted once per config."""
    import jax

    from ekm.maps import control

    return jax.jit(lambda ekm, u: control(ekm, u, cfg)[0])


def load(path=None, *, chart: str = "signed") -> Maps:
    """Read maps written by ``ekm train`` or :meth:`Maps.save`; without ``path``, the indirect map shipped
    with the package, trained in ``chart`` ("signed", the default, or "polar") — the map ``ekm run`` drives.

    Every key, shape and value of the file is checked; a bad file raises :class:`ekm.errors.InputError`
    naming it and what is wrong.

    Example::

        maps = ekm.load("indirect.npz")
        maps.trials, maps.cfg.neurons     # (5, 15)
    """
    from ekm.config import CHARTS
    from ekm.mapfile import load_maps

    if isinstance(path, Maps):
        return path
    if path is None:
        from importlib import resources

        from ekm.data import default_map

        if chart not in CHARTS:
            raise InputError(f"chart {chart!r}: no shipped map (charts: {', '.join(CHARTS)})")
        with resources.as_file(default_map(chart)) as file:
            saved = load_maps(file)
            shipped = str(file)
        return _wrap(saved, path=shipped, source=f"shipped {chart}-chart map")
    return _wrap(load_maps(path), path=str(path), source=str(path))


def _wrap(saved: SavedMaps, path: str | None, source: str) -> Maps:
    return Maps(ekm=saved.ekm, cfg=saved.cfg, meta=saved.meta, arena=saved.arena, curve=saved.curve, path=path,
                source=source)
