"""Comparing architectures at scale: every architecture × world × trial through the scenario runner.

A comparison is a bag of independent runs (docs/design.md §5): a run is a pure function of
(world, architecture, run seed, map), so the runs can go to any workers (:mod:`evaluation.workers`: this
process, local processes, a Dask cluster) in any order, on any number of them, and run again where a
worker died, and the results are the same. Trial ``i`` of a comparison started with ``seed`` runs with run
seed ``seed + i`` in every world and for every architecture: the same noise streams for all of them
(common random numbers), so differences between architectures are not differences of luck.

:data:`COMPARISON` hands the runs of :func:`jobs` to the batch runner (:func:`evaluation.batch.run_batch`), whose
workers call :func:`run_job`; :func:`summarize` turns their records into the rows of ``ekm compare``
(docs/design.md §6) with each success rate's 95 % Wilson interval.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from evaluation.batch import Batch
from evaluation.results import key
from evaluation.scenario import ScenarioConfig


@dataclass(frozen=True)
class Job:
    """One run of a comparison: everything a worker needs, as plain values (it pickles to any process or
    machine). ``world``: a named world or a world file's path (read by the worker); ``architecture``: the
    full spelling (:class:`robots.controllers.spec.ArchitectureSpec`); ``label``: the spelling the user
    gave; ``map_path``: a map file, or None for the architecture's shipped map; ``keep_path``: return the
    robot's path too (for the trajectory grid); ``added``: what was registered in the parent process
    (:func:`robots.registry.added_here`: an architecture or a family of a script), for the worker to register
    too."""

    world: str
    architecture: str
    label: str
    trial: int
    seed: int
    config: ScenarioConfig
    map_path: str | None = None
    keep_path: bool = False
    added: tuple = ()
    robot: str | None = None  # the robot's file as JSON text (robots.robotfile), None for the Khepera
    learn: str | None = None  # the learning rule of the maps that drive (robots.controllers.learner), None: frozen
    engine: str = "pymunk"  # the world's engine: "pymunk" (evaluation.scenario) or "jax" (evaluation.jaxrun)

    def identity(self) -> dict:
        """The run as its results-file line names it (:mod:`evaluation.results`)."""
        from ekm import __version__

        from robots.robotfile import robot_from_json

        robot = robot_from_json(self.robot)
        return {"world": self.world, "architecture": self.architecture, "label": self.label, "trial": self.trial,
                "seed": self.seed, "map": self.map_path, "robot": robot.name, "robot_fingerprint": robot.fingerprint,
                "learn": self.learn, "engine": self.engine, "ekm_version": __version__}


_MAPS: dict = {}


def failed_record(job: Job, reason: str, world: str | None = None, family: str | None = None) -> dict:
    """The record of a run that could not be made: ``failed`` (the one-line reason), ``reached`` False,
    ``ended`` "failed", and the job's identity (``given`` world, ``label``, ``trial``, ``seed``)."""
    return {"world": world or job.world, "architecture": job.architecture, "reached": False, "time_s": None,
            "path_m": None, "collisions": 0, "checkpoints_reached": 0, "replans": 0, "trapped": False,
            "final_distance_m": None, "contact_s": 0.0, "arrived": False, "recoveries": 0, "ended": "failed",
            "barn_score": 0.0,
            "failed": reason, "seed": job.seed, "label": job.label, "trial": job.trial, "given": job.world,
            "family": family}


def run_job(job: Job) -> dict:
    """Run one job (in whichever process the executor chose): its outcome record, plus ``label``, ``trial``,
    the ``given`` world spelling, the world's ``family`` (generated worlds; None otherwise) and, with
    ``keep_path``, ``path`` (the centre every 0.128 s, as lists) and ``collided_at`` (the centre where each
    collision began).

    A run that cannot be made is a record too, never the end of a comparison: a world the planner finds no
    route through at any cell, or any exception the run raises, gives :func:`failed_record` with the reason
    in one line that names the world."""
    from evaluation.scenario import driven, run_scenario

    world = None
    try:
        d = job_driver(job)  # first: it registers what the job's script added (a family its world may be of)
        world = _world(job.world)
        rec = run_scenario(world, d.controller, seed=job.seed, config=job.config)
    except Exception as exc:
        return failed_record(job, failure(job, exc), world.name if world is not None else None,
                             world_family(world) if world is not None else None)
    return job_record(job, driven(rec, d))


def failure(job: Job, exc: Exception) -> str:
    """The one-line reason of a run that raised ``exc``: an :class:`~ekm.errors.InputError`'s own line, any other
    exception's type and first line, led by the job's world when the line does not name it."""
    from ekm.errors import InputError

    text = str(exc).splitlines()[0] if str(exc) else ""
    reason = text if isinstance(exc, InputError) else f"{type(exc).__name__}: {text}".rstrip(": ")
    return reason if job.world in reason else f"{job.world}: {reason}"


def job_driver(job: Job):
    """The :class:`evaluation.scenario.Driver` of a job's architecture, map (read once per process), robot and
    learning rule, for the job's seed."""
    from ekm.mapfile import load_maps
    from evaluation.scenario import driver
    from robots.controllers.spec import parse_architecture
    from robots.registry import adopt
    from robots.robotfile import robot_from_json

    adopt(job.added)
    spec = parse_architecture(job.architecture)
    maps = None
    if job.map_path and spec.uses_map:
        if job.map_path not in _MAPS:  # one load per worker process, not one per run
            _MAPS[job.map_path] = load_maps(job.map_path)
        maps = _MAPS[job.map_path]
    learn = None
    if job.learn is not None and spec.uses_map:
        from robots.controllers.learner import parse_learning

        learn = parse_learning(job.learn)
    return driver(spec, maps, seed=job.seed, source=job.map_path or "", robot=robot_from_json(job.robot), learn=learn)


def job_record(job: Job, rec) -> dict:
    """A job's record of the run ``rec`` (:func:`run_job`'s answer, whichever engine drove)."""
    out = {**rec.outcome(), "label": job.label, "trial": job.trial, "given": job.world,
           "family": world_family(rec.world)}
    if job.keep_path:
        every = max(1, round(rec.period / (rec.times[1] - rec.times[0]))) if len(rec.times) > 1 else 1
        out["path"] = rec.poses[::every, :2].round(5).tolist()
        out["collided_at"] = [[round(float(x), 5), round(float(y), 5)] for _, x, y in rec.collision_log]
    return out


@functools.lru_cache(maxsize=256)
def _world(spelling: str):
    """The world of a job, read or generated once per worker process (a suite runs every architecture in it)."""
    from robots.worldnames import load_world

    return load_world(spelling)


def world_family(world) -> str | None:
    """The family of a generated world (its ``difficulty`` entry), None for any other world."""
    difficulty = getattr(world, "difficulty", None)
    return getattr(difficulty, "family", None)


def jobs(worlds, specs, trials: int, seed: int, config: ScenarioConfig, map_path: str | None = None,
         keep_paths: bool = False, robot=None, learn: str | None = None, engine: str = "pymunk") -> list[Job]:
    """Every (architecture, world, trial) of a comparison, in a fixed order — world by world, so that a worker
    plans a world once for all the architectures it runs there; trial 0 keeps its path when ``keep_paths``.
    ``robot``: the :class:`~robots.params.RobotParams` that drives (None: the Khepera); ``learn``: the spelling
    of the learning rule of the maps that drive (None: frozen); ``engine`` the world's ("pymunk" or "jax")."""
    from robots.registry import added_here

    added = added_here()
    document = None
    if robot is not None:
        from robots.robotfile import robot_json

        document = robot_json(robot)
    return [Job(world=w, architecture=str(spec), label=spec.label, trial=i, seed=seed + i, config=config,
                map_path=map_path, keep_path=keep_paths and i == 0, added=added, robot=document,
                learn=learn if spec.uses_map else None, engine=engine)
            for w in worlds for i in range(trials) for spec in specs]


def failed_run(job: Job, reason: str) -> dict:
    """The record of a run the batch runner could not make (its worker kept dying, or the pool raised), the reason
    led by the world (read here, for its name and family)."""
    try:
        world = _world(job.world)
        return failed_record(job, f"{job.world}: {reason}", world.name, world_family(world))
    except Exception:
        return failed_record(job, f"{job.world}: {reason}")


#: How the batch runner (:mod:`evaluation.batch`) names, keys and fails a comparison's runs.
COMPARISON = Batch("comparison", "run", "comparing", job_key=lambda j: key(j.world, j.label, j.trial),
                   record_key=lambda r: key(r["given"], r["label"], r["trial"]), identity=Job.identity,
                   failed=failed_run)


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """The 95 % Wilson score interval of a success rate ``successes / n`` (Wilson 1927): unlike the normal
    approximation it stays inside [0, 1] and is not empty at 0/10 or 10/10."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def _row(rs: list[dict]) -> dict:
    """The summary of runs ``rs``: ``trials, success_rate, success_ci95, mean_time_s, mean_path_m, collisions,
    trapped, contact_s, failed`` — the means over the runs that reached the goal (None if none did) — and
    ``motion`` (:func:`motion_summary`). The success rate and its interval are over the runs that were made: a
    run that failed (``failed``: it could not be made) did not drive, so it is no run that missed the goal; with
    every run failed both are None (``ekm compare`` prints *failed*)."""
    made = [r for r in rs if "failed" not in r]
    ok = [r for r in made if r["reached"]]
    ci = [round(x, 4) for x in wilson(len(ok), len(made))] if made else None
    return {"trials": len(rs), "success_rate": round(len(ok) / len(made), 4) if made else None,
            "success_ci95": ci,
            "mean_time_s": round(sum(r["time_s"] for r in ok) / len(ok), 3) if ok else None,
            "mean_path_m": round(sum(r["path_m"] for r in ok) / len(ok), 4) if ok else None,
            "collisions": sum(r["collisions"] for r in rs), "trapped": sum(r["trapped"] for r in rs),
            "contact_s": round(sum(r["contact_s"] for r in rs), 3), "failed": len(rs) - len(made),
            "motion": motion_summary(made)}


def motion_summary(rs: list[dict]) -> dict:
    """Each motion measure (:mod:`evaluation.motion`) of runs ``rs`` as ``{"mean": m, "ci95": [lo, hi]}`` over
    the runs that have it (all that ran; ``stop_distance_m``: those that stopped at the goal)."""
    from evaluation.motion import KEYS, mean_ci

    out = {}
    for name in KEYS:
        m, ci = mean_ci([r.get(name) for r in rs])
        out[name] = {"mean": None if m is None else round(m, 5),
                     "ci95": None if ci is None else [round(x, 5) for x in ci]}
    return out


def summarize(records: list[dict], worlds, labels) -> list[dict]:
    """One row per (world, architecture) in the given order — the ``results`` of docs/design.md §6: ``world,
    architecture, trials, success_rate, success_ci95, mean_time_s, mean_path_m, collisions, trapped`` (then
    ``contact_s``, ``failed``: runs that could not start, and ``runs_by_trial``, a letter per trial)."""
    rows = []
    for label in labels:
        for world in worlds:
            rs = [r for r in records if r["label"] == label and r["given"] == world]
            row = {"world": rs[0]["world"] if rs else world, "architecture": label, **_row(rs)}
            row["runs_by_trial"] = "".join(run_letter(r) for r in sorted(rs, key=lambda r: r["trial"]))
            rows.append(row)
    return rows


def by_family(records: list[dict], labels) -> list[dict]:
    """One row per (family, architecture) of the generated worlds' runs, families in the order of
    :data:`robots.generator.FAMILIES` then ``"all"`` (every generated world): ``family, architecture, worlds``
    and the summary of :func:`summarize`'s rows over all their runs."""
    from robots.generator import FAMILIES

    generated = [r for r in records if r.get("family")]
    rows = []
    seen = list(dict.fromkeys(r["family"] for r in generated))  # combined families (A+B) after the registered ones
    order = [f for f in FAMILIES if f in seen] + [f for f in seen if f not in FAMILIES]
    for family in order + (["all"] if generated else []):
        for label in labels:
            rs = [r for r in generated if r["label"] == label and family in ("all", r["family"])]
            rows.append({"family": family, "architecture": label, "worlds": len({r["given"] for r in rs}),
                         **_row(rs)})
    return rows


def by_architecture(records: list[dict], labels) -> list[dict]:
    """One row per architecture over all its runs, every world pooled (``ekm compare --motion``, the JSON's
    ``overall``): ``architecture, worlds`` and the summary of :func:`summarize`'s rows — success with its
    interval and each motion measure's mean with its 95 % interval over the runs."""
    rows = []
    for label in labels:
        rs = [r for r in records if r["label"] == label]
        rows.append({"architecture": label, "worlds": len({r["given"] for r in rs}), **_row(rs)})
    return rows


def run_letter(r: dict) -> str:
    """R reached, T trapped, C arrived after a collision, N no route (after a change of the map), L time limit,
    F failed (the run could not be made: no route at the start, an error, its worker kept dying)."""
    if "failed" in r:
        return "F"
    if r["reached"]:
        return "R"
    if r["trapped"]:
        return "T"
    if r["arrived"]:
        return "C"
    return "N" if "route" in r["ended"] else "L"
