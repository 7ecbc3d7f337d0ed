"""Training maps in Python: :func:`train` (the ch. 6.1 protocol, ``ekm train``) and :func:`resume`."""

from __future__ import annotations

from ekm.api.checks import choice, output_path, whole
from ekm.api.mapset import Maps
from ekm.errors import InputError, Interrupted

_PROG = "ekm train"


def train(mapping: str, *, neurons: int = 15, priority: int | None = None, chart: str = "signed",
          steps: int = 100_000, trials: int = 5, seed: int = 0, eval_every: int = 10_000, eval_targets: int = 50,
          test_seed: int = 0, world="open-arena", out=None, checkpoint=None, progress: bool = False) -> Maps:
    """Train ``trials`` independent EKMs online on the noisy robot (thesis ch. 4.3) with the protocol of
    ch. 6.1, testing them as in ch. 6.1 every ``eval_every`` steps.

    Parameters
    ----------
    mapping : {"direct", "indirect"}
        Direct mapping (ch. 4.1, a command per neuron) or indirect (ch. 4.2, a linear model per neuron).
    neurons : int, default 15
        The lattice is ``neurons`` × ``neurons``.
    priority : int, optional
        |A(α)| of Eq. 4.4: the K neurons of most similar angle compete (default: ``neurons``).
    chart : {"signed", "polar"}, default "signed"
        Coordinates of the linear model c = M u (Eq. 4.1): "polar" is the thesis as written, "signed"
        measures targets behind from the robot's back with negative distance (README, "signed chart").
    steps : int, default 100000
        Training steps of 1.024 s each.
    trials : int, default 5
        Independent maps, trained side by side (``vmap``) from keys split from ``seed``.
    seed : int, default 0
        Training seed: the same seed gives the same maps, bit for bit.
    eval_every : int, default 10000
        Steps between ch. 6.1 tests (the learning curve; with ``out``, a checkpoint after each).
    eval_targets : int, default 50
        Targets of each test.
    test_seed : int, default 0
        Seed of the test's targets and noise.
    world : str or World, default "open-arena"
        An obstacle-free named world or world file; its arena is trained and tested in.
    out : path, optional
        Save the maps there (``.npz``) when training ends. With ``out`` a checkpoint is written at every
        test (``checkpoint``, by default ``OUT.checkpoint.npz``, removed at the end), from which
        :func:`resume` continues after an interruption.
    progress : bool, default False
        Show a progress bar and each test's E and P(25) on stderr.

    Returns
    -------
    Maps
        Its ``to_dict()`` is ``ekm train --json`` for the same arguments.

    Examples
    --------
    ::

        maps = ekm.train(mapping="indirect", neurons=8, steps=2000, trials=2, seed=0)
        maps.curve[-1]["E_mm"]      # mm, the last test
    """
    settings = {"mapping": choice(mapping, ("direct", "indirect"), "--mapping", _PROG),
                "neurons": whole(neurons, "--neurons", _PROG, strict=True),
                "priority": None if priority is None else whole(priority, "--priority", _PROG, strict=True),
                "chart": chart, "steps": whole(steps, "--steps", _PROG, strict=True),
                "trials": whole(trials, "--trials", _PROG, strict=True),
                "seed": whole(seed, "--seed", _PROG, strict=False),
                "eval_every": whole(eval_every, "--eval-every", _PROG, strict=True),
                "eval_targets": whole(eval_targets, "--eval-targets", _PROG, strict=True),
                "test_seed": whole(test_seed, "--test-seed", _PROG, strict=False),
                "world": getattr(world, "source", world), "out": None if out is None else str(out)}
    from ekm.config import CHARTS

    choice(chart, CHARTS, "--chart", _PROG)
    out_path = None if out is None else output_path(out, "--out", ".npz")
    ckpt = None
    if out_path is not None:
        ckpt = output_path(checkpoint or str(default_checkpoint(out_path)), "--checkpoint", ".npz")
    elif checkpoint is not None:
        raise InputError("--checkpoint: needs --out (the checkpoint is removed once the maps are saved there)")
    return _train(settings, ckpt, None, [], progress)


def resume(checkpoint, *, out=None, checkpoint_to=None, progress: bool = False) -> Maps:
    """Continue a training run interrupted after a checkpoint, with the settings it was started with; the
    maps end bit for bit as if it had never stopped. ``out``: save them elsewhere than the run's own
    ``out``; ``checkpoint_to``: keep the checkpoint there from now on (default: where it is). The
    checkpoint is updated as training goes on, and removed once the maps are saved.

    Example: ``maps = ekm.resume("indirect.checkpoint.npz")`` (what ``ekm train --resume`` does).
    """
    from training.checkpoint import load_checkpoint

    ckpt = load_checkpoint(checkpoint, _Template)
    settings = ckpt.settings | ({"out": str(out)} if out else {})
    path = output_path(checkpoint_to or checkpoint, "--checkpoint", ".npz")
    return _train(settings, path, (ckpt.done, ckpt.trainees, ckpt.key_run), list(ckpt.curve), progress)


def default_checkpoint(out):
    """``indirect.npz`` -> ``indirect.checkpoint.npz``, next to it."""
    from pathlib import Path

    out = Path(out)
    return out.with_name(out.name[: -len(out.suffix)] + ".checkpoint.npz")


def configs(settings: dict):
    """``(cfg, tcfg, world)`` of a run's settings; bad values are :class:`InputError`."""
    from ekm.config import EKMConfig
    from robots.worldfile import load_world
    from training.online import TrainConfig

    world = load_world(settings["world"])
    if world.walls or world.obstacles or world.unforeseen or world.moving:
        raise InputError(f"--world {settings['world']}: training needs an obstacle-free world (thesis ch. 4.3)")
    try:
        cfg = EKMConfig(mapping=settings["mapping"], neurons=settings["neurons"], priority=settings["priority"],
                        chart=settings["chart"])
        tcfg = TrainConfig(steps=settings["steps"], trials=settings["trials"], arena=tuple(world.size))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{_PROG}: {exc}") from None
    return cfg, tcfg, world


class _Template:
    """The fresh carry of a run's settings: what a checkpoint's arrays must look like."""

    def __init__(self, settings: dict):
        from training.run import fresh

        cfg, tcfg, _ = configs(settings)
        self.carry, key = fresh(cfg, tcfg, int(settings["seed"]))
        self.key_shape = tuple(key.shape)
        self.settings_steps = tcfg.steps


def _train(settings: dict, checkpoint, resume, curve: list, progress: bool) -> Maps:
    """Train (or go on training) the run of ``settings``; save it to ``settings["out"]`` if given."""
    import time

    import jax
    import numpy as np

    from ekm import __version__
    from ekm.api.evaluation import summarize_test
    from ekm.mapfile import save_maps
    from robots.params import KHEPERA
    from training.checkpoint import Checkpoint, save_checkpoint, saved_step
    from training.run import train as run

    out = None if settings["out"] is None else output_path(settings["out"], "--out", ".npz")
    if out is not None and checkpoint is not None and checkpoint.resolve() == out.resolve():
        raise InputError(f"--checkpoint {checkpoint}: must differ from --out")
    cfg, tcfg, world = configs(settings)

    def on_eval(step, maps):
        s = summarize_test(maps, cfg, tcfg.arena, settings["eval_targets"], settings["test_seed"])
        curve.append({"step": step, "E_mm": s["E_mm"], "P": s["P"], "T": s["T"], "D": s["D"], "capped": s["capped"]})
        if progress:
            from tqdm import tqdm

            tqdm.write(f"  step {step:>7}: E = {s['E_mm']:7.2f} mm, P(25) = {s['P']['25']:.2f}")

    def on_checkpoint(step, trainees, key_run):
        if checkpoint is not None and step < tcfg.steps:  # the last one is the map file itself
            save_checkpoint(checkpoint, Checkpoint(trainees, step, np.asarray(key_run), curve, settings))

    t0 = time.perf_counter()
    try:
        maps = run(cfg, tcfg, seed=int(settings["seed"]), eval_every=settings["eval_every"], on_eval=on_eval,
                   on_checkpoint=on_checkpoint, resume=resume, progress=progress)
    except KeyboardInterrupt:
        if checkpoint is None:
            raise
        step = saved_step(checkpoint)  # what the file holds: a save cut short leaves the one before
        if step is None:
            raise Interrupted("training stopped before its first checkpoint; nothing was written") from None
        raise Interrupted(f"training stopped; the checkpoint at step {step} is {checkpoint}; "
                          f"resume with: ekm train --resume {checkpoint}") from None
    seconds = time.perf_counter() - t0
    meta = {"steps": tcfg.steps, "seed": settings["seed"], "world": world.name, "train": tcfg.to_dict(),
            "robot": KHEPERA.to_dict(), "test": {"targets": settings["eval_targets"], "seed": settings["test_seed"]},
            "curve": curve, "seconds": seconds}
    if out is not None:
        save_maps(out, maps, cfg, meta)
        checkpoint.unlink(missing_ok=True)
    meta |= {"package_version": __version__, "jax_version": jax.__version__,
             **({"resumed_at": resume[0]} if resume else {})}
    return Maps(ekm=maps, cfg=cfg, meta=meta, arena=tuple(tcfg.arena), curve=tuple(curve),
                path=None if out is None else str(out), source="maps in memory" if out is None else str(out))
