"""The adaptation experiment in Python: :func:`adapt` (``ekm adapt``) and its :class:`AdaptationTable`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ekm.api.checks import whole
from ekm.api.result import Result
from ekm.errors import InputError

_PROG = "ekm adapt"
#: The robots :func:`adapt` runs by default: every named one, the Khepera first (the unchanged robot).
DEFAULT_ROBOTS = "khepera,worn-wheel,weak-motor,wide-base,slippery,e-puck"


@dataclass(frozen=True)
class AdaptationTable(Result):
    """The adaptation experiment (:mod:`evaluation.adaptation`): ``rows``, one per robot, each ``{robot,
    fingerprint, curves: {frozen, fine-tuned, scratch}, summary}`` — the curves are ch. 6.1 test points
    ``{step, E_mm, E_ci95, P, T, D, capped}`` — and ``setup`` (steps, tests, seeds, rate), ``map`` (the map
    every robot starts from, and the robot it was trained on). ``summary`` holds, for the table, E (mm, with its
    95 % interval), T(5) and D(25) of the frozen map, of the fine-tuned map after every step and of the map
    trained from scratch after ``scratch_steps``, and how many steps fine-tuning and training from scratch
    needed to reach E ≤ 3 mm (the thesis's indirect figure) and T(5) within 5 % of the from-scratch map's last
    (what a map made for the robot achieves; ``scratch_T5``).
    ``to_dict()`` is ``ekm adapt --json``; ``plot()`` draws every curve."""

    rows: tuple
    setup: dict
    map: dict
    seconds: float

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        return {"robots": list(self.rows), "setup": self.setup, "map": self.map, "seconds": round(self.seconds, 1),
                **provenance()}

    def plot(self):
        """E, T(5) and D(25) against training steps, a row of panels per robot: the frozen map (dashed), the
        fine-tuned one and the one trained from scratch. Returns the matplotlib Figure."""
        from evaluation.adaptation_plot import adaptation_figure

        return adaptation_figure(list(self.rows))

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path`` (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from robots.plot import save_figure

        out = plot_path(path, "--plot")
        save_figure(self.plot(), out, dpi=100)
        return out


def adapt(robots=DEFAULT_ROBOTS, *, maps=None, steps: int = 10_000, every: int = 500, scratch_steps: int = 20_000,
          scratch_every: int = 500, targets: int = 50, seed: int = 1000, test_seed: int = 1000, rate=None,
          progress: bool = False) -> AdaptationTable:
    """For each robot, a trained map as it is (frozen), going on learning (fine-tuned, ``ekm train --init``) and a
    map trained on the robot from scratch, tested as in ch. 6.1 against training steps (docs/design.md §10).

    Parameters
    ----------
    robots : str or list, default every named robot
        Named robots or robot files, ``"worn-wheel,weak-motor"``.
    maps : path or Maps, optional
        The map every robot starts from (default: the shipped signed-chart map, trained on the Khepera).
    steps, every : int, default 10000, 500
        Fine-tuning steps, and the steps between its tests.
    scratch_steps, scratch_every : int, default 20000, 500
        The first steps of the ch. 6.1 protocol (100,000 steps) trained from scratch, and between its tests.
    targets : int, default 50
        Targets of each test.
    seed, test_seed : int, default 1000, 1000
        Seeds of every training and of every test (the same targets and noise for all three maps). From 1000
        on: seeds on which no parameter of the package was chosen.
    rate : str, optional
        The fine-tuning rule (``ekm train --rate``; default its own).
    progress : bool, default False
        Progress bars on stderr.

    Examples
    --------
    ::

        ekm.adapt("worn-wheel", steps=2000, scratch_steps=4000).rows[0]["summary"]
    """
    import time

    from ekm.api.mapset import load
    from evaluation.adaptation import Setup, fine_tuned, first_step, frozen, scratch
    from evaluation.scenario import map_robot
    from robots.robotfile import load_robot

    names = [r.strip() for r in robots.split(",")] if isinstance(robots, str) else list(robots)
    if not names or not all(str(n).strip() for n in names):
        raise InputError(f"--robots {robots!r}: empty item between commas")
    setup = Setup(steps=whole(steps, "--steps", _PROG, strict=True), every=whole(every, "--every", _PROG, strict=True),
                  scratch_steps=whole(scratch_steps, "--scratch-steps", _PROG, strict=True),
                  scratch_every=whole(scratch_every, "--scratch-every", _PROG, strict=True),
                  targets=whole(targets, "--targets", _PROG, strict=True), seed=whole(seed, "--seed", _PROG, strict=False),
                  test_seed=whole(test_seed, "--test-seed", _PROG, strict=False), rate=rate)
    loaded = [load_robot(n) for n in names]  # every robot checked before anything runs
    start = load(maps)
    if start.cfg.mapping != "indirect":
        raise InputError(f"--map {start.source}: the adaptation experiment fine-tunes an indirect map, got a "
                         f"{start.cfg.mapping} one")
    from ekm.api.training import _rate

    rate_spelt = _rate(rate)
    t0 = time.perf_counter()
    rows = []
    for robot in loaded:
        curves = {"frozen": frozen(start, robot, setup), "fine-tuned": fine_tuned(start, robot, setup, progress),
                  "scratch": scratch(start, robot, setup, progress)}
        rows.append({"robot": robot.name, "fingerprint": robot.fingerprint, "curves": curves,
                     "summary": _summary(curves, first_step)})
    return AdaptationTable(rows=tuple(rows), setup={**setup.__dict__, "rate": rate_spelt},
                           map={"source": start.source, "robot": map_robot(start)}, seconds=time.perf_counter() - t0)


#: The E the thesis gives for its indirect map (ch. 6.1), mm: the level both maps are timed to.
THESIS_E_MM = 3.0


#: How much above the from-scratch map's T(5) counts as reaching it: the test's T varies by a few per cent.
SLACK = 1.05


def _summary(curves: dict, first_step) -> dict:
    """The table's numbers of one robot (see :class:`AdaptationTable`)."""
    def point(p):
        return {"E_mm": round(p["E_mm"], 3), "E_ci95": p["E_ci95"], "T5": _round(p["T"]["5"], 2),
                "D25": _round(p["D"]["25"], 4), "capped": p["capped"]}

    fine, scratch = curves["fine-tuned"], curves["scratch"]
    t5 = scratch[-1]["T"]["5"]
    level = None if t5 is None else round(SLACK * t5, 3)
    return {"frozen": point(curves["frozen"][0]), "fine_tuned": point(fine[-1]), "scratch": point(scratch[-1]),
            "steps_to_thesis_E": {"fine_tuned": first_step(fine, THESIS_E_MM),
                                  "scratch": first_step(scratch, THESIS_E_MM)},
            "scratch_T5": level,
            "steps_to_scratch_T5": {"fine_tuned": None if level is None else first_step(fine, level, "T5"),
                                    "scratch": None if level is None else first_step(scratch, level, "T5")}}


def _round(x, digits):
    return None if x is None else round(x, digits)
