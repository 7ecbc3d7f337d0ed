"""The adaptation experiment (docs/design.md §10; ``ekm adapt``): a map trained on one robot, on another.

For each robot, starting from a trained map (the shipped Khepera map by default), the ch. 6.1 test (E, P(ε),
T(ε), D(ε), :mod:`evaluation.protocol`) against training steps for three maps:

- ``frozen``: the map as it is, on the new robot — one test, the same at every step;
- ``fine-tuned``: the map going on learning on the new robot (``ekm train --init``: the same online training,
  at the rates of :mod:`ekm.learning`), tested every ``every`` steps;
- ``scratch``: a map trained on the new robot from nothing with the ch. 6.1 protocol (its 100,000-step
  schedules), tested every ``scratch_every`` steps up to ``scratch_steps``.

Every test uses the same targets and noise (``test_seed``), every training the same seed (``seed``): the
three curves of a robot differ only by the map. Each test point carries E's 95 % interval over its trials ×
targets (:func:`evaluation.motion.mean_ci`). :func:`first_step` reads from a curve when a measure first
reaches a level — how many steps fine-tuning and training from scratch need to reach the same E.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MODES = ("frozen", "fine-tuned", "scratch")


@dataclass(frozen=True)
class Setup:
    """How the experiment is run (see the module docstring); ``rate``: the fine-tuning rule's spelling."""

    steps: int = 10_000
    every: int = 500
    scratch_steps: int = 20_000
    scratch_every: int = 500
    targets: int = 50
    seed: int = 1000
    test_seed: int = 1000
    rate: str | None = None


def test_point(step: int, maps, cfg, arena, robot, setup: Setup) -> dict:
    """The ch. 6.1 test of stacked ``maps`` on ``robot`` after ``step`` steps, as a training curve's point: ``step,
    E_mm, E_ci95, P, T, D, capped``."""
    from ekm.api.evaluation import summarize_test

    s = summarize_test(maps, cfg, arena, setup.targets, setup.test_seed, robot)
    return {"step": int(step), **{k: s[k] for k in ("E_mm", "E_ci95", "P", "T", "D", "capped")}}


def frozen(maps, robot, setup: Setup) -> list[dict]:
    """The frozen map's test, at step 0 and at the fine-tuning's last step (the same numbers)."""
    point = test_point(0, maps.ekm, maps.cfg, maps.arena, robot, setup)
    return [point, {**point, "step": setup.steps}]


def fine_tuned(maps, robot, setup: Setup, progress: bool = False) -> list[dict]:
    """The map going on learning on ``robot`` (:func:`ekm.api.training.train` with ``init``), tested every
    ``setup.every`` steps."""
    from ekm.api.training import train

    trained = train(init=maps, robot=robot, steps=setup.steps, eval_every=setup.every,
                    eval_targets=setup.targets, seed=setup.seed, test_seed=setup.test_seed, rate=setup.rate,
                    world=_arena_world(maps), progress=progress)
    return list(trained.curve)


def scratch(maps, robot, setup: Setup, progress: bool = False) -> list[dict]:
    """A map of the same lattice and chart trained on ``robot`` from nothing, the first ``setup.scratch_steps``
    steps of the ch. 6.1 protocol, tested every ``setup.scratch_every`` steps."""
    from ekm.api.training import train

    cfg = maps.cfg
    trained = train(cfg.mapping, neurons=cfg.neurons, priority=cfg.priority, chart=cfg.chart, trials=maps.trials,
                    robot=robot, eval_every=setup.scratch_every, eval_targets=setup.targets, seed=setup.seed,
                    test_seed=setup.test_seed, world=_arena_world(maps), progress=progress,
                    until=setup.scratch_steps)
    return list(trained.curve)


def _arena_world(maps) -> str:
    """The obstacle-free world the maps were trained in (its name in their metadata; ``open-arena`` if none)."""
    world = maps.meta.get("world") if isinstance(maps.meta, dict) else None
    return world if isinstance(world, str) else "open-arena"


def first_step(curve: list[dict], at_most: float, key: str = "E_mm", reached: float = 0.9) -> int | None:
    """The first step of ``curve`` at which ``key`` (``E_mm``, or ``T5``/``D25``: T or D at that ε in mm) is at
    most ``at_most``, and stays so at the next test; None if it never does. T and D average over the targets
    reached within ε only, so for them the step also needs P(ε) ≥ ``reached`` (an untrained map that happens to
    reach two targets quickly has not learned)."""
    def value(p):
        v = _value(p, key)
        if key != "E_mm" and p["P"].get(key[1:], 0.0) < reached:
            return None
        return v

    values = [value(p) for p in curve]
    for i, v in enumerate(values):
        if v is not None and v <= at_most and (i + 1 == len(values) or (values[i + 1] or np.inf) <= at_most):
            return int(curve[i]["step"])
    return None


def _value(point: dict, key: str):
    if key in point:
        return point[key]
    measure, eps = key[0], key[1:]
    return point[measure].get(eps)
