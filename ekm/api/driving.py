"""Driving through a world in Python: :func:`run` (thesis ch. 6.2, ``ekm run``) and its :class:`Outcome`."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from ekm.api.checks import choice, number, whole
from ekm.api.result import Result
from ekm.errors import InputError

_PROG = "ekm run"
SENSORS = ("short", "long")


def _floor() -> float:
    from evaluation.scenario import TIME_FLOOR_S

    return TIME_FLOOR_S


def scenario_config(prog: str, *, time_limit, recover, checkpoints, cell):
    """The :class:`evaluation.scenario.ScenarioConfig` of ``ekm run`` / ``ekm compare``'s options, each checked
    with the command's own one-line errors."""
    from evaluation.scenario import ScenarioConfig
    from planner import DEFAULT_CELL, RULES

    time_limit = None if time_limit is None else number(time_limit, "--time-limit", prog, strict=True)
    choice(checkpoints, RULES, "--checkpoints", prog)
    cell = DEFAULT_CELL if cell is None else number(cell, "--cell", prog, strict=True)
    return ScenarioConfig(time_limit=time_limit, recover=bool(recover), checkpoints=checkpoints, cell=cell)


@dataclass(frozen=True)
class Outcome(Result):
    """How one run went (docs/design.md §6): ``reached`` the goal (within 5 mm and without a collision), after
    ``time_s`` simulated seconds along ``path_m`` metres, with ``collisions`` contact episodes,
    ``checkpoints_reached``, ``replans``, ``trapped`` (the monitor saw no progress), ``final_distance_m``
    to the goal, ``contact_s`` the time spent in contact; ``arrived`` (stopped at the goal, collisions or not), ``recoveries``, ``ended`` (why the run
    stopped), ``seed``, ``map`` and ``trial`` (which map drove; None for architectures without one),
    ``config`` (the :class:`evaluation.scenario.ScenarioConfig`), and how it moved: ``motion``, each measure of
    :data:`evaluation.motion.MEASURES` by key (``outcome.angular_accel_rms`` reads one). ``record`` holds the traces
    (poses every sub-step, commands, plans, sensed points). ``to_dict()`` is ``ekm run --json``; ``plot()`` draws
    the run to scale (Fig. 6.3–6.8).
    """

    world: str
    architecture: str
    reached: bool
    time_s: float
    path_m: float
    collisions: int
    checkpoints_reached: int
    replans: int
    trapped: bool
    final_distance_m: float
    contact_s: float
    arrived: bool
    recoveries: int
    ended: str
    seed: int
    map: str | None
    trial: int | None
    config: object = field(repr=False)
    record: object = field(repr=False, compare=False)
    spec: object = field(repr=False, compare=False)
    spec_maps: object = field(repr=False, compare=False, default=None)  # the maps that drove (None: none)
    learn_spelling: str | None = field(repr=False, compare=False, default=None)  # the learning rule, if any
    engine: str = field(repr=False, compare=False, default="pymunk")  # the robot's world: "pymunk" or "jax"
    robot: str = "khepera"
    robot_fingerprint: str = ""
    map_robot: str | None = None
    updates: int | None = None
    motion: dict = field(default_factory=dict)

    @classmethod
    def of(cls, rec, config, spec, maps=None, learn_spelling: str | None = None, engine: str = "pymunk") -> "Outcome":
        """The outcome of the run ``rec`` (:meth:`evaluation.scenario.RunRecord.outcome`); ``maps`` drove it,
        learning by the rule ``learn_spelling`` (None: frozen), in the world of ``engine``."""
        from evaluation.motion import KEYS

        out = rec.outcome()
        return cls(**{k: v for k, v in out.items() if k not in KEYS}, motion={k: out[k] for k in KEYS},
                   config=config, record=rec, spec=spec, spec_maps=maps, learn_spelling=learn_spelling, engine=engine)

    def __getattr__(self, name: str):
        motion = self.__dict__.get("motion", {})
        if name in motion:  # a motion measure, by its key
            return motion[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def learned(self):
        """With ``learn``: the map the run ended with, as one-trial :class:`~ekm.api.mapset.Maps` (save it with
        :meth:`save_map` and drive a later run with it); None for a frozen map."""
        rec = self.record
        if rec is None or rec.learned is None:
            return None
        import jax

        from ekm.api.mapset import Maps

        base = self.spec_maps
        meta = {k: v for k, v in base.meta.items() if k not in ("format", "version", "mapping", "neurons", "trials",
                                                               "ekm")}
        meta["learned"] = list(meta.get("learned", [])) + [{
            "from": rec.map_source, "trial": rec.trial, "world": rec.world.name, "architecture": rec.architecture,
            "seed": rec.seed, "robot": rec.robot.name, "robot_fingerprint": rec.robot.fingerprint,
            "updates": rec.updates, "rule": self.learn_spelling}]
        meta["robot"] = rec.robot.to_dict()
        stacked = jax.tree.map(lambda a: a[None], rec.learned)
        return Maps(ekm=stacked, cfg=base.cfg, meta=meta, arena=base.arena, curve=(), path=None,
                    source=f"learned in {rec.world.name} (seed {rec.seed})")

    def save_map(self, path) -> Path:
        """:attr:`learned` to a map file at ``path`` (atomically); refused for a run whose map did not learn."""
        learned = self.learned
        if learned is None:
            raise InputError("--save-map: the map did not learn during this run (give --learn)")
        return learned.save(path)

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        hidden = ("config", "record", "spec", "spec_maps", "learn_spelling", "engine", "motion")
        outcome = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in hidden}
        return {**outcome, **self.motion, "learn": self.learn_spelling, "engine": self.engine,
                "config": asdict(self.config), **provenance()}

    def plot(self, ax=None):
        """The run to scale on ``ax`` (a new figure sized to the arena if None): world, path coloured by
        time, robot outlines, plans and checkpoints, collisions and traps. Returns the axes."""
        from evaluation.scenario_plot import draw_run

        return draw_run(ax, self.record)

    def save_plot(self, path) -> Path:
        """:meth:`plot` to a PNG, SVG or PDF (by its suffix) at ``path`` (atomically); returns the path."""
        from ekm.api.checks import plot_path
        from evaluation.scenario_plot import save_run

        return save_run(self.record, plot_path(path, "--plot"))

    def save_animation(self, path, progress: bool = False) -> Path:
        """The run animated, to a GIF at ``path``; returns the path. ``progress``: a bar of the frames on stderr."""
        from ekm.api.checks import output_path
        from evaluation.scenario_plot import save_animation

        out = output_path(path, "--gif", ".gif")
        save_animation(self.record, out, progress=progress)
        return out


def run(world, architecture: str, *, maps=None, trial: int | None = None, sensors: str | None = None,
        recover: bool = True, seed: int = 0, time_limit: float | None = None, checkpoints: str = "visible",
        cell: float | None = None, robot=None, learn=None, progress: bool = False, engine: str = "pymunk") -> Outcome:
    """Drive the simulated robot from the world's start to its goal: the slippery-cell planner's
    checkpoints, reached by one architecture (thesis ch. 4.4–5, 6.2; docs/design.md §5).

    Parameters
    ----------
    world : str or World
        A named world, a world file (:func:`ekm.world`) or a loaded world.
    architecture : str
        ``"fusion"``, ``"fields"``, ``"samba"`` or ``"schema"``, optionally with parameters:
        ``"fields:form=thesis"``, ``"fusion:beta=0.6,sensors=long"``; without them each runs its best
        documented variant.
    maps : Maps, Map, or path, optional
        The indirect map the EKM architectures drive (default: the shipped map of the architecture's
        chart). A :class:`Map` (``maps[i]``) drives that trial.
    trial : int, optional
        Which trial of ``maps`` drives (default: ``seed % trials``).
    sensors : {"short", "long"}, optional
        IR ring, overriding the architecture's (short: 8 Khepera sensors, 5 cm; long: 12, 17.5 cm).
    recover : bool, default True
        When trapped, add the sensed obstacle to the planner's map and replan (thesis 7.1.1); False ends
        the run at the first trap, as the thesis's runs do.
    seed : int, default 0
        Noise seed of the run; the same seed gives the same run.
    time_limit : float, optional
        Simulated seconds before the run is given up; by default ten times the planned route's time at the
        robot's top speed, and at least 120 (:func:`evaluation.scenario.time_limit_for`).
    checkpoints : {"visible", "thesis"}, default "visible"
        The planner's checkpoint rule: consecutive checkpoints see each other with the robot's clearance
        (:mod:`planner.visibility`), or the greedy rule of thesis ch. 3.2.3 as written.
    cell : float, optional
        The planner's bitmap cell in metres (default 0.02), halved automatically where a narrow place
        holds no route.
    robot : str, RobotParams, optional
        The robot that drives: a named robot (``ekm robots``) or a robot file (default: the Khepera). A map
        trained on another robot drives it as it is (the outcome's ``map_robot`` says which).
    learn : str, bool or LearnParams, optional
        Let the architecture's map go on learning while it drives (thesis ch. 4.3): ``True`` or a rule,
        ``"error"``, ``"constant:eta=0.1,sigma=1"`` (:func:`robots.controllers.learner.parse_learning`);
        the map it ends with is ``outcome.learned`` (``save_map``). Default: the map is frozen.
    progress : bool, default False
        Show a progress bar in simulated seconds on stderr (pymunk only: the JAX engine runs the whole run as one
        batch).
    engine : {"pymunk", "jax"}, default "pymunk"
        The robot's world: pymunk (the reference) or the JAX engine (:mod:`evaluation.jaxrun`, a batch of one;
        docs/guide/jaxworld.md). The record is the same kind either way;
        the JAX run keeps no checkpoint, trap or IR-hit log, so its plot marks none.

    Returns
    -------
    Outcome
        Its ``to_dict()`` is ``ekm run --json`` for the same arguments.

    Examples
    --------
    ::

        out = ekm.run("concave-obstacle", architecture="fields", seed=1)
        out.reached, out.time_s
    """
    from ekm.api.comparing import ENGINES
    from ekm.api.mapset import Map, load
    from ekm.api.worlds import world as load_world
    from evaluation.scenario import run_architecture
    from robots.controllers.spec import parse_architecture

    choice(engine, ENGINES, "--engine", _PROG)
    if sensors is not None:
        choice(sensors, SENSORS, "--sensors", _PROG)
    config = scenario_config(_PROG, time_limit=time_limit, recover=recover, checkpoints=checkpoints, cell=cell)
    seed = whole(seed, "--seed", _PROG, strict=False)
    if isinstance(maps, Map):
        if trial is not None and trial != maps.trial:
            raise InputError(f"--trial {trial}: the map given is trial {maps.trial}")
        maps, trial = maps.maps, maps.trial
    if trial is not None:
        trial = whole(trial, "--trial", _PROG, strict=False)
    from robots.robotfile import load_robot

    w = load_world(world)
    robot = load_robot(robot)
    spec = parse_architecture(architecture)
    if sensors:
        spec = spec.with_params(sensors=sensors)
    learning = None
    if learn is not None and learn is not False:
        from robots.controllers.learner import parse_learning, spell_learning

        learning = parse_learning(learn)
        if not spec.uses_map:
            raise InputError(f"--learn: architecture {spec.name} drives no map, so it has nothing to learn")
    if not spec.uses_map and (maps is not None or trial is not None):
        raise InputError(f"--map/--trial: architecture {spec.name} drives no map")
    if spec.uses_map:
        maps = load(maps, chart=spec.default_chart)
        spec.check_map(maps.cfg, maps.source)
        if trial is not None and trial >= maps.trials:
            raise InputError(f"--trial {trial}: the map file holds trials 0..{maps.trials - 1}")
    from ekm import interrupts

    if engine == "jax":
        rec = _run_on_jax(w, spec, maps, seed=seed, trial=trial if spec.uses_map else None, config=config,
                          robot=robot, learn=learning)
        return Outcome.of(rec, config, spec, maps, None if learning is None else spell_learning(learning), engine)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=round(config.time_limit or _floor(), 1), unit="sim s", desc=f"{spec.label} in {w.name}",
                   dynamic_ncols=True, bar_format="{l_bar}{bar}| {n:.1f}/{total:.0f} sim s [{elapsed}]")

    def on_tick(t):
        interrupts.check()  # a Ctrl-C lost in a JAX callback stops the run at the next tick
        if bar is not None:
            bar.update(round(t, 3) - bar.n)

    try:
        rec = run_architecture(w, spec, maps, seed=seed, trial=trial if spec.uses_map else None, config=config,
                               on_tick=on_tick, source=maps.source if maps is not None else "", robot=robot,
                               learn=learning)
    finally:
        if bar is not None:
            bar.close()
    return Outcome.of(rec, config, spec, maps, None if learning is None else spell_learning(learning))


def _run_on_jax(world, spec, maps, *, seed: int, trial, config, robot, learn):
    """The :class:`~evaluation.scenario.RunRecord` of one run on the JAX engine (:func:`evaluation.jaxrun.run_scenarios`,
    a batch of one), the architecture built as :func:`evaluation.scenario.run_architecture` builds it."""
    from ekm import interrupts
    from evaluation.jaxrun import run_scenarios
    from evaluation.scenario import driven, driver

    d = driver(spec, maps, seed=seed, trial=trial, source=maps.source if maps is not None else "", robot=robot,
               learn=learn)
    return driven(run_scenarios([(world, seed)], d.controller, config, between=interrupts.check)[0], d)
