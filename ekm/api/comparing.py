"""Comparing architectures in Python: :func:`compare` (``ekm compare``) and its :class:`Table`."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ekm.api.checks import whole
from ekm.api.result import Result
from ekm.errors import InputError

_PROG = "ekm compare"
#: The robot's worlds a comparison can run in (:func:`compare`'s ``engine``).
ENGINES = ("pymunk", "jax")


@dataclass(frozen=True)
class Table(Result):
    """A comparison: ``rows``, one per architecture and world (architectures in the order given, worlds
    within each), each a dict with ``world``, ``architecture``, ``trials``, ``success_rate`` and its 95 %
    Wilson interval ``success_ci95`` over the runs that were made (both None when every run ``failed``),
    ``mean_time_s`` and ``mean_path_m`` of the successes, ``collisions``,
    ``trapped`` and ``runs_by_trial`` (a letter per trial); ``seconds`` the wall time and ``workers`` where
    the runs went. ``families``: with generated worlds, one row per family and architecture (and
    ``"all"``), each with the number of ``worlds`` and the same summary over their runs. ``overall``: one row
    per architecture over all its runs, every world pooled (success and each motion measure with its 95 %
    interval: ``ekm compare --motion``). ``to_dict()`` is
    ``ekm compare --json``; ``plot()`` draws the success rates with their intervals and the first trial's
    path in each world (by family, with one example world each, for a suite).
    """

    rows: tuple
    worlds: tuple
    labels: tuple
    trials: int
    seed: int
    seconds: float
    workers: str
    config: object = field(repr=False)
    records: tuple = field(repr=False, compare=False, default=())
    families: tuple = ()
    overall: tuple = ()
    robot: dict | None = None  # {"name", "fingerprint"} of the robot every run drove
    learn: str | None = None  # the learning rule of the maps, None: frozen
    engine: str = "pymunk"  # the world the runs drove in: "pymunk" or "jax"

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        out = {"results": [{k: v for k, v in r.items() if k != "runs_by_trial"} for r in self.rows]}
        if self.families:
            out["families"] = list(self.families)
        if self.overall:
            out["overall"] = list(self.overall)
        failures = [{"world": r["given"], "architecture": r["label"], "trial": r["trial"], "seed": r["seed"],
                     "reason": r["failed"]} for r in self.records if "failed" in r]
        if failures:
            out["failures"] = failures
        return {**out, "robot": self.robot, "learn": self.learn, "engine": self.engine, "trials": self.trials,
                "seed": self.seed,
                "seconds": round(self.seconds, 2),
                "runs": len(self.records), "workers": self.workers, "config": asdict(self.config), **provenance()}

    def plot(self):
        """Success rates with their 95 % intervals, and one path per architecture and world — by family, with
        one world of each, when the comparison has generated worlds; returns the matplotlib Figure."""
        from evaluation.compare_plot import comparison_figure, family_figure

        if self.families:
            return family_figure(list(self.families), list(self.records), list(self.labels))
        return comparison_figure(list(self.rows), list(self.records), list(self.worlds), list(self.labels))

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path`` (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from robots.plot import save_figure

        out = plot_path(path, "--plot")
        save_figure(self.plot(), out, dpi=110)
        return out


def _names(items, option: str) -> tuple[str, list[str]]:
    """``(spelling, names)`` of ``--worlds``: a comma-separated string or a list of names, paths or worlds."""
    if isinstance(items, (str, Path)):
        text = str(items)
        names = [w.strip() for w in text.split(",")]
    else:
        names = [str(getattr(w, "source", w)) for w in items]
        text = ",".join(names)
    if not all(names):
        raise InputError(f"{option} {text!r}: empty item between commas")
    if len(set(names)) != len(names):
        raise InputError(f"{option} {text!r}: a world is named twice")
    return text, names


def suite_worlds(suite, first_seed: int = 1000) -> list[str]:
    """The generated worlds of ``suite`` — ``"FAMILY:COUNT[,FAMILY:COUNT...]"`` or a list of such items — as
    spellings ``FAMILY:SEED`` with seeds ``first_seed … first_seed + COUNT − 1`` for each family (seeds from
    1000 on are the test seeds: no parameter of the package was chosen on them)."""
    from robots.generator import family_of, no_family

    items = [t.strip() for t in suite.split(",")] if isinstance(suite, str) else [str(t) for t in suite]
    first_seed = whole(first_seed, "--world-seed", _PROG, strict=False)
    names = []
    for item in items:
        family, sep, count = item.partition(":")
        if family_of(family) is None:
            raise InputError(f"--suite {item!r}: {no_family(family)}")
        try:
            n = int(count) if sep else -1
        except ValueError:
            n = -1
        if n < 1:
            raise InputError(f"--suite {item!r}: expected FAMILY:COUNT with COUNT a whole number >= 1")
        names += [f"{family}:{first_seed + i}" for i in range(n)]
    return names


def compare(worlds=(), architectures="fusion,fields,samba,schema", *, suite=None, world_seed: int = 1000,
            trials: int = 10, seed: int = 0, maps=None, recover: bool = True,
            time_limit: float | None = None, checkpoints: str = "visible", cell: float | None = None,
            workers: int | None = None, scheduler: str | None = None, out=None, resume=None,
            robot=None, learn=None, engine: str = "pymunk", progress: bool = False) -> Table:
    """Run every architecture in every world ``trials`` times, in parallel, and summarise success with 95 %
    intervals (thesis ch. 6.2 at scale). Trial i runs with seed ``seed + i`` for every architecture and
    world (the same noise for all of them), so the result does not depend on ``workers`` or ``scheduler``.

    Parameters
    ----------
    worlds : list of str or World, or "W1,W2,...", optional
        Named worlds, world files or generated worlds (``maze:7``).
    suite : str or list, optional
        Generated worlds by family, ``"corridor:20,maze:20"`` (:func:`suite_worlds`): COUNT worlds of each
        family with seeds ``world_seed …``; the table then also reports by family.
    world_seed : int, default 1000
        First seed of the suite's worlds (1000 on: the test seeds).
    architectures : list of str, or "A1[:k=v,...],A2,..."
        As :func:`ekm.run` spells them.
    trials : int, default 10
        Runs per architecture and world.
    seed : int, default 0
        Trial i runs with seed ``seed + i``.
    maps : path or Maps saved to a file, optional
        Map for the EKM architectures (default: their shipped maps); the workers read the file.
    recover : bool, default True
        Cognizant-failure recovery (thesis 7.1.1): when trapped, the sensed obstacle joins the planner's
        map and the route is replanned; False ends a run at its first trap.
    time_limit : float, optional
        Simulated seconds per run; by default ten times the planned route's time at the robot's top speed,
        and at least 120 (:func:`evaluation.scenario.time_limit_for`).
    checkpoints : {"visible", "thesis"}, default "visible"
        The planner's checkpoint rule (:func:`ekm.run`).
    cell : float, optional
        The planner's bitmap cell in metres (default 0.02, refined automatically where needed).
    workers : int, optional
        Local worker processes (default: the machine's cores; 1 runs in this process). Worker processes
        are spawned, so a script that calls :func:`compare` with several needs the usual
        ``if __name__ == "__main__":`` guard (a notebook does not); without it every worker dies as it
        starts and :class:`ekm.InputError` names the script and the guard.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``; needs ``ekm[cluster]``) to send the runs to.
    out : path, optional
        Results file (JSON Lines, :mod:`evaluation.results`): every finished run is appended and flushed as
        it arrives, so a crash or Ctrl-C loses at most the runs in flight. Must not exist.
    resume : path, optional
        A results file of an earlier, unfinished call with the same arguments: only the missing runs are
        made, and appended to it; the table is the same as an uninterrupted comparison's. A file made with
        other arguments is refused.
    robot : str or RobotParams, optional
        The robot every run drives (``ekm robots``; default the Khepera), as :func:`ekm.run` takes it.
    learn : str or bool, optional
        The maps of the architectures that drive one go on learning during each run (:func:`ekm.run`'s
        ``learn``); every run starts from the same map. Default: frozen.
    engine : {"pymunk", "jax"}, default "pymunk"
        The robot's world: pymunk (the reference, one run at a time on ``workers``), or the JAX engine
        (:mod:`evaluation.jaxrun`: each architecture's runs in one batch in this process, on the devices JAX has;
        docs/guide/jaxworld.md). The results file
        records it: a file of one engine is never resumed with the other.
    progress : bool, default False
        Show a progress bar (runs done, failed, time left) on stderr.

    Returns
    -------
    Table
        Its ``to_dict()`` is ``ekm compare --json`` for the same arguments (but for ``seconds``, the wall
        time). A run that could not be made (its world has no route, it raised, its worker kept dying) is
        in the table as failed, with its reason in ``records``; it never ends the comparison.

    Raises
    ------
    ekm.InputError
        Bad arguments; or every local worker died as it started (a script without the ``__main__`` guard).
    ekm.Interrupted
        On Ctrl-C or SIGTERM in the console script: the workers are stopped and the message says how many
        runs the results file keeps and how to resume.

    Examples
    --------
    ::

        t = ekm.compare(["open-arena", "concave-obstacle"], ["fusion", "fields"], trials=2, time_limit=40)
        [(r["architecture"], r["world"], r["success_rate"]) for r in t.rows]
    """
    import time

    from ekm.api.worlds import world as load_world
    from ekm.api.driving import scenario_config
    from evaluation.batch import run_batch
    from evaluation.compare import COMPARISON, by_architecture, by_family, jobs, run_job, summarize
    from evaluation.workers import workers_for
    from robots.controllers.spec import parse_architectures

    if engine not in ENGINES:
        raise InputError(f"--engine: must be one of {', '.join(ENGINES)}, got {engine!r}")
    if engine == "jax" and (workers not in (None, 1) or scheduler is not None):
        raise InputError("--engine jax runs every architecture's runs in one batch in this process: drop --workers "
                         "and --scheduler")
    trials = whole(trials, "--trials", _PROG, strict=True)
    seed = whole(seed, "--seed", _PROG, strict=False)
    config = scenario_config(_PROG, time_limit=time_limit, recover=recover, checkpoints=checkpoints, cell=cell)
    if workers is not None:
        workers = whole(workers, "--workers", _PROG, strict=True)
    names = _names(worlds, "--worlds")[1] if (isinstance(worlds, (str, Path)) and str(worlds)) or \
        (not isinstance(worlds, (str, Path)) and len(worlds)) else []
    for w in names:
        load_world(w)
    if suite:
        names += [w for w in suite_worlds(suite, world_seed) if w not in names]
    if not names:
        raise InputError(f"{_PROG}: no worlds: give --worlds, --suite or both")
    text = architectures if isinstance(architectures, str) else ",".join(architectures)
    specs = parse_architectures(text)
    labels = [s.label for s in specs]
    if len(set(labels)) != len(labels):
        raise InputError(f"--architectures {text!r}: an architecture is named twice")
    map_path = _map_path(maps, specs)
    from robots.robotfile import load_robot

    robot = load_robot(robot)
    learning = None
    if learn is not None and learn is not False:
        from robots.controllers.learner import parse_learning, spell_learning

        learning = spell_learning(parse_learning(learn))
        if not any(s.uses_map for s in specs):
            raise InputError("--learn: none of the architectures drives a map, so none has anything to learn")
    job_list = jobs(names, specs, trials, seed, config, map_path, keep_paths=True, robot=robot, learn=learning,
                    engine=engine)
    settings = json.loads(json.dumps({  # as the results file holds them (tuples become lists)
        "worlds": names, "architectures": [str(s) for s in specs], "labels": labels, "trials": trials, "seed": seed,
        "config": asdict(config), "map": map_path, "robot": {"name": robot.name, "fingerprint": robot.fingerprint},
        "learn": learning, "engine": engine, "ekm_version": _version()}))
    t0 = time.perf_counter()
    if engine == "jax":
        import jax

        from evaluation.batch import kept
        from evaluation.jaxrun import run_jobs

        where = f"the JAX engine ({', '.join(str(d) for d in jax.devices())})"
        records = kept(COMPARISON, job_list, settings, lambda done, on_done: run_jobs(job_list, on_done, done=done),
                       out=out, resume=resume, progress=progress)
    else:
        pool = workers_for(run_job, workers, scheduler)
        where = pool.where
        records = run_batch(COMPARISON, job_list, pool, settings, out=out, resume=resume, progress=progress)
    seconds = time.perf_counter() - t0
    return Table(rows=tuple(summarize(records, names, labels)), worlds=tuple(names), labels=tuple(labels),
                 trials=trials, seed=seed, seconds=seconds, workers=where, config=config,
                 records=tuple(records), families=tuple(by_family(records, labels)),
                 overall=tuple(by_architecture(records, labels)), robot=settings["robot"], learn=learning,
                 engine=engine)


def load_comparison(path) -> Table:
    """The :class:`Table` of a finished comparison, from its results file alone (``ekm compare --from``):
    the same rows, families and plot as the comparison that wrote it.

    Raises :class:`ekm.InputError` if the file is not a results file or does not hold every run (then
    ``ekm compare … --resume PATH`` finishes it)."""
    from evaluation.compare import by_architecture, by_family, summarize
    from evaluation.results import UNSAID, key, kind, read, whose
    from evaluation.scenario import ScenarioConfig

    settings, records = read(path)
    if kind(settings) != "comparison":
        raise InputError(f"{path}: {whose(kind(settings))} results file, not a comparison's (ekm compare --out "
                         f"writes those)")
    names, labels, trials = settings["worlds"], settings["labels"], settings["trials"]
    have = {key(r["given"], r["label"], r["trial"]): r for r in records}
    want = [key(w, a, i) for w in names for i in range(trials) for a in labels]
    missing = [k for k in want if k not in have]
    if missing:
        raise InputError(f"--from {path}: holds {len(want) - len(missing)} of the comparison's {len(want)} runs; "
                         f"finish it with ekm compare … --resume {path}")
    ordered = [have[k] for k in want]
    return Table(rows=tuple(summarize(ordered, names, labels)), worlds=tuple(names), labels=tuple(labels),
                 trials=trials, seed=settings["seed"], seconds=0.0, workers=f"results file {path}",
                 config=ScenarioConfig(**settings["config"]), records=tuple(ordered),
                 families=tuple(by_family(ordered, labels)), overall=tuple(by_architecture(ordered, labels)),
                 robot=settings.get("robot"), learn=settings.get("learn"),
                 engine=settings.get("engine", UNSAID["engine"]))


def _version() -> str:
    from ekm import __version__

    return __version__


def _map_path(maps, specs) -> str | None:
    """The map file the workers read: ``maps`` itself, or the file a :class:`ekm.Maps` came from — checked,
    and refused in one line for an architecture of ``specs`` that does not drive its chart."""
    from ekm.api.mapset import Maps, load

    if maps is None:
        return None
    if isinstance(maps, Maps):
        if maps.path is None:
            raise InputError("maps: ekm.compare sends the workers a map file; save the maps first (maps.save(PATH))")
        loaded, path = maps, maps.path
    else:
        loaded, path = load(maps), str(maps)
    for spec in specs:
        if spec.uses_map:
            spec.check_map(loaded.cfg, path)
    return path
