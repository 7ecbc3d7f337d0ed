"""The ch. 6.1 positioning test of trained maps in Python: :func:`evaluate` and its :class:`Metrics`."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ekm.api.checks import whole
from ekm.api.result import Result

_PROG = "ekm evaluate"
#: Metrics of the test (docs/design.md §6), then what was tested — the order of ``ekm evaluate --json``.
_KEYS = ("E_mm", "P", "T", "D", "trials", "targets", "capped")
_ABOUT = ("file", "mapping", "ekm", "trained", "robot", "map_robot")


def summarize_test(maps, cfg, arena, targets: int, seed: int, robot=None) -> dict:
    """The ch. 6.1 test of stacked maps on ``robot`` (None: the Khepera), summarised (E, P, T, D, capped) with E's
    95 % interval over trials × targets (``E_ci95``, mm)."""
    from evaluation.metrics import summarize
    from evaluation.protocol import evaluate as run_test
    from robots.params import KHEPERA

    import numpy as np

    from evaluation.motion import mean_ci

    records = run_test(maps, cfg, arena, targets=targets, seed=seed, params=robot or KHEPERA)
    _, ci = mean_ci(list(1000.0 * np.asarray(records.error, float).ravel()))
    return {**summarize(records), "E_ci95": [round(x, 4) for x in ci]}


@dataclass(frozen=True)
class Metrics(Result):
    """The ch. 6.1 test of one map file (thesis Eq. 6.1–6.3): ``E_mm`` the mean final distance (mm), and
    for ε = 5, 10, 25 mm (keys ``"5"``, ``"10"``, ``"25"``) ``P`` the fraction of targets come within ε,
    ``T`` the steps per metre to get there and ``D`` the path's relative deviation from the straight line
    (None where no target was come within ε); over ``trials`` maps × ``targets`` targets, ``capped`` of
    which hit the 50-step cap. ``to_dict()`` is ``ekm evaluate MAP.npz --json``.

    Examples
    --------
    ::

        m = ekm.evaluate(ekm.load(), targets=20)
        m.E_mm, m.P["25"]
    """

    file: str
    mapping: str
    E_mm: float
    P: dict
    T: dict
    D: dict
    trials: int
    targets: int
    capped: int
    ekm: dict
    trained: dict
    seed: int
    maps: object = field(repr=False, compare=False, default=None)
    robot: str = "khepera"  # the robot the test drove
    map_robot: str = "khepera"  # the robot the map was trained on
    robot_params: object = field(repr=False, compare=False, default=None)

    def _entry(self) -> dict:
        return {k: getattr(self, k) for k in _ABOUT[:2] + _KEYS + _ABOUT[2:]}

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        return {**{k: getattr(self, k) for k in _KEYS + _ABOUT}, "seed": self.seed, **provenance()}

    @property
    def label(self) -> str:
        return f"{self.mapping} ({Path(self.file).name})"

    def plot(self):
        """Fig. 6.1/6.2: E during training, P, T, D of this test, the first trial's input weights. Returns
        the matplotlib Figure."""
        return Evaluation((self,)).plot()

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path``; returns the path."""
        return Evaluation((self,)).save_plot(path)

    def save_paths(self, path) -> Path:
        """The first trial's paths through the first 10 test targets, to a PNG, SVG or PDF (by its suffix) at
        ``path``."""
        return Evaluation((self,)).save_paths(path)


@dataclass(frozen=True)
class Evaluation(Result):
    """The same test of several map files (``ekm.evaluate([a, b])``): ``items`` holds one :class:`Metrics`
    each; ``to_dict()`` is ``ekm evaluate A.npz B.npz --json`` and ``plot()`` puts every map on the same
    axes."""

    items: tuple

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, i) -> Metrics:
        return self.items[i]

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        return {"maps": [m._entry() for m in self.items], "seed": self.items[0].seed, **provenance()}

    def plot(self):
        """Fig. 6.1/6.2 with every map on the same axes; returns the matplotlib Figure."""
        from evaluation.plots import figure_6_1_6_2

        return figure_6_1_6_2([m.maps.figure_entry(m.label, m.to_dict()) for m in self.items])

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path``; returns the path."""
        from ekm.api.checks import plot_path
        from robots.plot import save_figure

        out = plot_path(path, "--plot")
        save_figure(self.plot(), out, dpi=110)
        return out

    def save_paths(self, path) -> Path:
        """Each map's first trial through the first 10 test targets (the same targets and noise as the
        test), one panel per map, to a PNG, SVG or PDF (by its suffix) at ``path``; returns the path."""
        from ekm.api.checks import plot_path
        from evaluation.metrics import summarize
        from evaluation.plots import save_paths_figure
        from evaluation.protocol import trace_paths

        out = plot_path(path, "--paths")
        panels = []
        for m in self.items:
            saved = m.maps
            pts, start, xy, rec = trace_paths(saved.ekm, saved.cfg, saved.arena, targets=m.targets, seed=m.seed,
                                              params=m.robot_params)
            panels.append({"label": f"{m.mapping} ({Path(m.file).name}, trial 1)", "targets": pts, "start": start,
                           "xy": xy, "summary": summarize(rec)})
        save_paths_figure(panels, self.items[0].maps.arena, out)
        return out


def evaluate(maps, *, targets: int = 50, seed: int = 0, robot=None):
    """Run the ch. 6.1 positioning test on trained maps: every trial drives from the arena's centre to
    ``targets`` random targets in sequence (no learning), at most 50 steps of 1.024 s each, with the
    actuator noise of training.

    Parameters
    ----------
    maps : Maps, path, or a list of them
        Maps from :func:`ekm.train` / :func:`ekm.load`, or map files. A list gives an :class:`Evaluation`
        (every map tested on the same targets and noise).
    targets : int, default 50
        Test targets per trial.
    seed : int, default 0
        Seed of the targets and the noise.
    robot : str or RobotParams, optional
        The robot the test drives (``ekm robots``; default the Khepera); the result says which robot each map
        was trained on (``map_robot``).

    Returns
    -------
    Metrics or Evaluation
        :class:`Metrics` for one map, :class:`Evaluation` for a list; the same as ``ekm evaluate MAP.npz
        [--targets N] [--seed S] --json``.

    Examples
    --------
    ::

        ekm.evaluate(ekm.load(), targets=20).E_mm     # mm
        ekm.evaluate(["indirect.npz", "direct.npz"]).save_plot("fig6.png")
    """
    from ekm.api.mapset import load
    from evaluation.scenario import map_robot
    from robots.robotfile import load_robot

    robot = load_robot(robot)
    targets = whole(targets, "--targets", _PROG, strict=True)
    seed = whole(seed, "--seed", _PROG, strict=False)
    several = isinstance(maps, (list, tuple))
    loaded = [load(m) for m in (maps if several else [maps])]
    items = []
    for saved in loaded:
        s = summarize_test(saved.ekm, saved.cfg, saved.arena, targets, seed, robot)
        trained = {k: saved.meta.get(k) for k in ("seed", "steps", "package_version", "jax_version")}
        items.append(Metrics(file=saved.path or saved.source, mapping=saved.cfg.mapping,
                             **{k: s[k] for k in _KEYS}, ekm=saved.cfg.to_dict(), trained=trained, seed=seed,
                             maps=saved, robot=robot.name, map_robot=map_robot(saved), robot_params=robot))
    return Evaluation(tuple(items)) if several else items[0]
