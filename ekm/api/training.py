"""Training maps in Python: :func:`train` (the ch. 6.1 protocol, ``ekm train``) and :func:`resume`."""

from __future__ import annotations

from ekm.api.checks import choice, output_path, whole
from ekm.api.mapset import Maps
from ekm.errors import InputError, Interrupted

_PROG = "ekm train"


def train(mapping: str | None = None, *, neurons: int | None = None, priority: int | None = None,
          chart: str | None = None, steps: int | None = None, trials: int | None = None, seed: int = 0,
          eval_every: int | None = None, eval_targets: int = 50, test_seed: int = 0, world="open-arena", out=None,
          checkpoint=None, robot=None, init=None, rate=None, until: int | None = None,
          progress: bool = False) -> Maps:
    """Train ``trials`` independent EKMs online on the noisy robot (thesis ch. 4.3) with the protocol of
    ch. 6.1, testing them as in ch. 6.1 every ``eval_every`` steps — from scratch, or (``init``) going on from
    trained maps.

    Parameters
    ----------
    mapping : {"direct", "indirect"}
        Direct mapping (ch. 4.1, a command per neuron) or indirect (ch. 4.2, a linear model per neuron);
        required unless ``init`` gives it.
    neurons : int, default 15
        The lattice is ``neurons`` × ``neurons``.
    priority : int, optional
        |A(α)| of Eq. 4.4: the K neurons of most similar angle compete (default: ``neurons``).
    chart : {"signed", "polar"}, default "signed"
        Coordinates of the linear model c = M u (Eq. 4.1): "polar" is the thesis as written, "signed"
        measures targets behind from the robot's back with negative distance (README, "signed chart").
    steps : int, default 100000 (10000 with ``init``)
        Training steps of 1.024 s each.
    trials : int, default 5 (with ``init``: the file's)
        Independent maps, trained side by side (``vmap``) from keys split from ``seed``.
    seed : int, default 0
        Training seed: the same seed gives the same maps, bit for bit.
    eval_every : int, default 10000 (1000 with ``init``)
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
    robot : str or RobotParams, optional
        The robot trained and tested on (``ekm robots``; default the Khepera). From scratch, the map's c* and
        step length follow the robot's top speed.
    init : path or Maps, optional
        Go on training these maps (``ekm train --init``; every trial of the file, each with its own noise)
        instead of starting from scratch: their lattice, chart and hyper-parameters are kept, and η and σ follow
        ``rate`` instead of training's decaying schedules.
    rate : str, optional
        With ``init``: the fine-tuning rule (:mod:`ekm.learning`), ``"error"`` (default) or ``"constant"``,
        with parameters as ``ekm run --learn`` spells them (``"constant:eta=0.05,sigma=1"``).
    until : int, optional
        Stop after this many of the ``steps`` steps, the schedules unchanged: the maps of an early step of a
        full run (the adaptation experiment, :mod:`evaluation.adaptation`). Not with ``out``.
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
    from ekm.config import CHARTS
    from robots.robotfile import load_robot, robot_document

    fine = None if init is None else _initial(init, mapping=mapping, neurons=neurons, priority=priority,
                                               chart=chart, trials=trials)
    if fine is None:
        if rate is not None:
            raise InputError("--rate: the rate of fine-tuning; needs --init MAP.npz (training from scratch follows "
                             "the schedules of training.schedules)")
        if mapping is None:
            raise InputError("ekm train: the following arguments are required: --mapping (or --init MAP.npz)")
        mapping, neurons, chart = mapping, 15 if neurons is None else neurons, chart or "signed"
        trials = 5 if trials is None else trials
    else:
        mapping, neurons, priority, chart, trials = (fine[k] for k in ("mapping", "neurons", "priority", "chart",
                                                                        "trials"))
    settings = {"mapping": choice(mapping, ("direct", "indirect"), "--mapping", _PROG),
                "neurons": whole(neurons, "--neurons", _PROG, strict=True),
                "priority": None if priority is None else whole(priority, "--priority", _PROG, strict=True),
                "chart": chart, "steps": whole((10_000 if fine else 100_000) if steps is None else steps, "--steps", _PROG,
                               strict=True),
                "trials": whole(trials, "--trials", _PROG, strict=True),
                "seed": whole(seed, "--seed", _PROG, strict=False),
                "eval_every": whole((1_000 if fine else 10_000) if eval_every is None else eval_every, "--eval-every",
                                    _PROG, strict=True),
                "eval_targets": whole(eval_targets, "--eval-targets", _PROG, strict=True),
                "test_seed": whole(test_seed, "--test-seed", _PROG, strict=False),
                "world": getattr(world, "source", world), "out": None if out is None else str(out),
                "robot": robot_document(load_robot(robot)), "init": None, "rate": None}
    choice(chart, CHARTS, "--chart", _PROG)
    if fine is not None:
        settings |= {"init": fine["file"], "init_ekm": fine["ekm"], "init_robot": fine["robot"],
                     "rate": _rate(rate)}
    out_path = None if out is None else output_path(out, "--out", ".npz")
    if until is not None:
        settings["until"] = whole(until, "until", _PROG, strict=True)
        if out_path is not None:
            raise InputError("until: the maps of an unfinished run are not saved; drop out")
    ckpt = None
    if out_path is not None:
        ckpt = output_path(checkpoint or str(default_checkpoint(out_path)), "--checkpoint", ".npz")
    elif checkpoint is not None:
        raise InputError("--checkpoint: needs --out (the checkpoint is removed once the maps are saved there)")
    return _train(settings, ckpt, None, [], progress, None if fine is None else fine["maps"])


def _initial(init, *, mapping, neurons, priority, chart, trials) -> dict:
    """What fine-tuning takes from the maps ``init`` (a file or :class:`Maps`): their lattice, chart and
    trials (a different one given is refused in one line), hyper-parameters, robot and the maps themselves."""
    from ekm.api.mapset import Maps, load
    from evaluation.scenario import map_robot

    maps = init if isinstance(init, Maps) else load(init)
    cfg = maps.cfg
    have = {"mapping": cfg.mapping, "neurons": cfg.neurons, "priority": cfg.priority, "chart": cfg.chart,
            "trials": maps.trials}
    for key, given in (("mapping", mapping), ("neurons", neurons), ("priority", priority), ("chart", chart),
                       ("trials", trials)):
        if given is not None and given != have[key]:
            raise InputError(f"--{key} {given}: --init {maps.source} holds {have[key]}; fine-tuning keeps the map's "
                             f"{key} (drop --{key})")
    return {**have, "file": maps.path or maps.source, "ekm": cfg.to_dict(), "robot": map_robot(maps),
            "maps": maps.ekm}


#: The fine-tuning rule of ``ekm train --init`` when none is given (docs/reproduce/adaptation.md).
DEFAULT_RATE = "error"


def _rate(rate) -> str:
    """The spelling of a fine-tuning rule (:func:`robots.controllers.learner.parse_learning`), checked."""
    from robots.controllers.learner import LearnParams, parse_learning, spell_learning

    parsed = parse_learning(DEFAULT_RATE if rate is None else rate)
    if (parsed.steady, parsed.clear) != (LearnParams().steady, LearnParams().clear):
        raise InputError("--rate: steady and clear say which ticks of a run teach the map (ekm run --learn); "
                         "training in the arena learns at every step")
    return spell_learning(parsed)


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
    """``(cfg, tcfg, world, robot)`` of a run's settings; bad values are :class:`InputError`.

    From scratch the map's c* and step length (``d_scale``) are the robot's top speed c* and c* × 1 s — the
    thesis's 0.16 m/s and 0.16 m for the Khepera (ch. 6.1); fine-tuning keeps the map's own."""
    from ekm.config import EKMConfig
    from robots.robotfile import parse_robot
    from robots.worldnames import load_world
    from training.online import TrainConfig

    world = load_world(settings["world"])
    if world.walls or world.obstacles or world.unforeseen or world.moving:
        raise InputError(f"--world {settings['world']}: training needs an obstacle-free world (thesis ch. 4.3)")
    robot = parse_robot(settings.get("robot") or {"name": "khepera"}, "the run's robot")
    adapt = None
    try:
        if settings.get("init"):
            from robots.controllers.learner import parse_learning

            cfg = EKMConfig(**settings["init_ekm"])
            adapt = parse_learning(settings["rate"]).rule
        else:
            speed = {} if robot.max_wheel_speed == EKMConfig.c_max else {"c_max": robot.max_wheel_speed,
                                                                        "d_scale": robot.max_wheel_speed * 1.0}
            cfg = EKMConfig(mapping=settings["mapping"], neurons=settings["neurons"], priority=settings["priority"],
                            chart=settings["chart"], **speed)
        tcfg = TrainConfig(steps=settings["steps"], trials=settings["trials"], arena=tuple(world.size), adapt=adapt)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{_PROG}: {exc}") from None
    return cfg, tcfg, world, robot


class _Template:
    """The fresh carry of a run's settings: what a checkpoint's arrays must look like."""

    def __init__(self, settings: dict):
        from training.run import fresh

        cfg, tcfg, _, _ = configs(settings)
        self.carry, key = fresh(cfg, tcfg, int(settings["seed"]))
        self.key_shape = tuple(key.shape)
        self.settings_steps = tcfg.steps


def _train(settings: dict, checkpoint, resume, curve: list, progress: bool, init=None) -> Maps:
    """Train (or go on training) the run of ``settings``; save it to ``settings["out"]`` if given. ``init``: the
    stacked maps a fine-tuning run starts from (not needed to resume one)."""
    import time

    import jax
    import numpy as np

    from ekm import __version__
    from ekm.api.evaluation import summarize_test
    from ekm.mapfile import save_maps
    from training.checkpoint import Checkpoint, save_checkpoint, saved_step
    from training.run import train as run

    out = None if settings["out"] is None else output_path(settings["out"], "--out", ".npz")
    if out is not None and checkpoint is not None and checkpoint.resolve() == out.resolve():
        raise InputError(f"--checkpoint {checkpoint}: must differ from --out")
    cfg, tcfg, world, robot = configs(settings)

    def on_eval(step, maps):
        s = summarize_test(maps, cfg, tcfg.arena, settings["eval_targets"], settings["test_seed"], robot)
        curve.append({"step": step, "E_mm": s["E_mm"], "E_ci95": s["E_ci95"], "P": s["P"], "T": s["T"], "D": s["D"],
                      "capped": s["capped"]})
        if progress:
            from tqdm import tqdm

            tqdm.write(f"  step {step:>7}: E = {s['E_mm']:7.2f} mm, P(25) = {s['P']['25']:.2f}")

    def on_checkpoint(step, trainees, key_run):
        if checkpoint is not None and step < tcfg.steps:  # the last one is the map file itself
            save_checkpoint(checkpoint, Checkpoint(trainees, step, np.asarray(key_run), curve, settings))

    t0 = time.perf_counter()
    try:
        maps = run(cfg, tcfg, seed=int(settings["seed"]), eval_every=settings["eval_every"], on_eval=on_eval,
                   on_checkpoint=on_checkpoint, resume=resume, progress=progress, params=robot, init=init,
                   until=settings.get("until"))
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
            "robot": robot.to_dict(), "test": {"targets": settings["eval_targets"], "seed": settings["test_seed"]},
            "curve": curve, "seconds": seconds}
    if settings.get("init"):
        meta["init"] = {"file": settings["init"], "robot": settings["init_robot"], "rate": settings["rate"]}
    if out is not None:
        save_maps(out, maps, cfg, meta)
        checkpoint.unlink(missing_ok=True)
    meta |= {"package_version": __version__, "jax_version": jax.__version__,
             **({"resumed_at": resume[0]} if resume else {})}
    return Maps(ekm=maps, cfg=cfg, meta=meta, arena=tuple(tcfg.arena), curve=tuple(curve),
                path=None if out is None else str(out), source="maps in memory" if out is None else str(out))
