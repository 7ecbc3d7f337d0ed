"""Everything you can add, in Python: the catalogues :func:`architectures`, :func:`players` and :func:`families`
(``ekm architectures``, ``ekm players``, ``ekm families``; the robots are listed by :func:`ekm.robots`), and
:func:`register_architecture`, :func:`register_player`, :func:`register_family` and :func:`register_robot`, which
add your own beside the package's.

Each kind is one registry (:class:`robots.registry.Registry`): the package's own, then those of installed
packages — the entry-point groups ``ekm.architectures``, ``ekm.players``, ``ekm.families`` and ``ekm.robots``,
each entry point naming an :class:`Architecture`, a :class:`Player`, a :class:`Family` or a
:class:`~robots.params.RobotParams` — then those registered in this process.
Every ``register_*`` has one shape: the thing made already, or its name and its fields in their order. What you
register in a script goes to ``ekm.compare``'s and ``ekm.tournament``'s worker processes with their jobs, so
define its functions and parameter classes at the top level of a module (or of the script), where pickle finds
them. docs/guide/architectures.md and docs/guide/soccer.md have worked examples.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ekm.api.result import Result
from robots.controllers.spec import Architecture
from robots.generator import Family
from robots.soccer.roster import Player

__all__ = ["Architecture", "Architectures", "Families", "Family", "Player", "Players", "architectures", "families",
           "players", "register_architecture", "register_family", "register_player", "register_robot"]


@dataclass(frozen=True)
class Catalogue(Result):
    """The things of one kind: ``rows``, each ``{name, summary, origin, …, parameters}`` — ``origin`` "built in",
    "entry point" (an installed package's) or "added" (in this process); ``parameters``
    ``[{name, type, default, choices, help}]``. ``to_dict()`` is ``ekm <kinds> --json``."""

    rows: tuple
    key: ClassVar[str] = ""

    def _dict(self) -> dict:
        return {self.key: list(self.rows)}

    def names(self) -> list[str]:
        return [r["name"] for r in self.rows]


@dataclass(frozen=True)
class Architectures(Catalogue):
    """Every architecture the runner knows (``ekm architectures``); a row also has ``map``, the charts of the EKM
    it drives (None: it drives none), and ``encoding``, "continuous", "discrete" or None (Arkin §3.3)."""

    key: ClassVar[str] = "architectures"


@dataclass(frozen=True)
class Players(Catalogue):
    """Every soccer player :func:`ekm.match` and :func:`ekm.tournament` know (``ekm players``)."""

    key: ClassVar[str] = "players"


@dataclass(frozen=True)
class Families(Catalogue):
    """Every family of generated worlds (``ekm families``): ``FAMILY:SEED[:DIFFICULTY]`` spells one of its worlds
    everywhere a world is named. A family has no parameters but the seed and the difficulty."""

    key: ClassVar[str] = "families"


def _rows(registry, extra=lambda thing: {}) -> tuple:
    """One row per thing of ``registry``, in its order."""
    from robots.spelling import describe_fields

    return tuple({"name": name, "summary": thing.summary, "origin": registry.origin(name), **extra(thing),
                  "parameters": describe_fields(thing.params) if hasattr(thing, "params") else []}
                 for name, thing in registry.all().items())


def architectures() -> Architectures:
    """The built-in architectures, those of installed packages (entry-point group ``ekm.architectures``) and
    those added with :func:`register_architecture`, in that order."""
    from robots.controllers.spec import ARCHITECTURES

    return Architectures(_rows(ARCHITECTURES, lambda a: {"map": list(a.charts) or None, "encoding": a.encoding}))


def players() -> Players:
    """The soccer players :func:`ekm.match` and :func:`ekm.tournament` know, with their parameters, defaults and
    allowed values: the built-in ones, those of installed packages (``ekm.players``), those added with
    :func:`register_player`."""
    from robots.soccer.roster import PLAYERS

    return Players(_rows(PLAYERS))


def families() -> Families:
    """The families of generated worlds: the built-in ones, those of installed packages (``ekm.families``), those
    added with :func:`register_family`."""
    from robots.generator import FAMILIES

    return Families(_rows(FAMILIES))


def _register(registry, name, make):
    return registry.register(name if isinstance(name, registry.cls) else make())


def register_architecture(name, params: type | None = None, build=None, summary: str = "", *,
                          chart: str | None = None, charts=(), encoding: str | None = None):
    """Add an architecture under ``name``, for :func:`ekm.run`, :func:`ekm.compare` (and their commands in
    this process) and :func:`architectures`.

    Parameters
    ----------
    name : str or Architecture
        Lower-case letters, digits, ``-`` and ``_``; not a built-in name. Registering a name again
        replaces what was added under it. Or an :class:`Architecture` made already (what an entry point of
        the group ``ekm.architectures`` names), and nothing else.
    params : frozen dataclass type
        Its fields are the parameters (``NAME:k=v`` on the command line), each with a default; a field's
        ``metadata`` may give ``help`` (with the unit) and ``choices``.
    build : callable
        ``build(params, ekm, cfg, spec=..., robot=...)`` returns a
        :class:`~robots.controllers.base.Controller`; ``ekm`` and ``cfg`` are one trial's indirect map and its
        configuration when ``chart`` is given, else None.
    summary : str
        One line for ``ekm architectures``.
    chart : {"signed", "polar"}, optional
        The chart of the shipped map to drive when no map is given; None for an architecture without a map.
    charts : tuple of str, optional
        The charts of the maps it drives correctly (default: ``chart``).
    encoding : {"continuous", "discrete"}, optional
        How it encodes its response (Arkin §3.3), for ``ekm architectures`` and ``ekm compare --motion``.

    Returns
    -------
    Architecture
        What was registered.

    Examples
    --------
    ::

        ekm.register_architecture("wander", WanderParams, build_wander, "go to the checkpoint, turn from walls")
        ekm.compare(["concave-obstacle"], "wander,fields", trials=4)
    """
    from robots.controllers.spec import ARCHITECTURES

    return _register(ARCHITECTURES, name, lambda: Architecture(name, params, build, summary, chart, tuple(charts),
                                                               encoding))


def register_player(name, params: type | None = None, build=None, summary: str = ""):
    """Add a soccer player under ``name``, for :func:`ekm.match`, :func:`ekm.tournament` (and their commands in
    this process) and :func:`players`.

    Parameters
    ----------
    name : str or Player
        As :func:`register_architecture`'s; or a :class:`Player` made already (what an entry point of the group
        ``ekm.players`` names), and nothing else.
    params : frozen dataclass type
        Its fields are the parameters (``NAME:k=v``), each with a default, ``help`` and ``choices`` in their
        ``metadata``.
    build : callable
        ``build(params, field=..., robot=..., spec=...)`` returns a :class:`~robots.controllers.base.Controller`
        whose ``step(state, play)`` gets a :class:`robots.soccer.play.Play` — the game turned so that the player
        attacks the goal at x = ``field.length`` — and returns ``(state, (left, right) wheel speeds in m/s)``.
    summary : str
        One line for ``ekm players``.

    Returns
    -------
    Player
        What was registered.
    """
    from robots.soccer.roster import PLAYERS

    return _register(PLAYERS, name, lambda: Player(name, params, build, summary))


def register_family(name, layout=None, summary: str = ""):
    """Add a family of generated worlds under ``name``, for :func:`ekm.generate`, :func:`ekm.compare`'s ``suite``,
    every world named ``NAME:SEED[:DIFFICULTY]`` (in this process) and :func:`families`.

    Parameters
    ----------
    name : str or Family
        As :func:`register_architecture`'s; or a :class:`Family` made already (what an entry point of the group
        ``ekm.families`` names), and nothing else.
    layout : callable
        ``layout(rng, level)`` draws one world from a NumPy generator and a difficulty level in [0, 1] and
        returns a :class:`robots.generator.layout.Layout`, or raises :class:`robots.generator.layout.Retry` to be
        called again with the next sub-seed; :func:`robots.generator.build.build` turns, checks and keeps it.
    summary : str
        One line for ``ekm families``.

    Returns
    -------
    Family
        What was registered.
    """
    from robots.generator import FAMILIES

    return _register(FAMILIES, name, lambda: Family(name, layout, summary))


def register_robot(name, robot=None, summary: str = ""):
    """Add a robot under ``name``, for every ``robot=`` (``--robot NAME`` in this process) and :func:`ekm.robots`.

    Parameters
    ----------
    name : str or RobotParams
        As :func:`register_architecture`'s; or a :class:`~robots.params.RobotParams` made already, under its own
        name (what an entry point of the group ``ekm.robots`` names), and nothing else.
    robot : RobotParams, dict or path
        The robot: parameters, a robot-file document (keys left out are the Khepera's) or a robot file
        (:mod:`robots.robotfile`); checked key by key as a robot file is.
    summary : str
        One line for ``ekm robots`` (default the robot's own ``about``).

    Returns
    -------
    RobotParams
        What was registered.

    Examples
    --------
    ::

        ekm.register_robot("heavy", {"motor_tau": 0.08, "max_wheel_speed": 0.12}, "a slow, heavy Khepera")
        ekm.compare(["three-rooms"], "fields,samba", robot="heavy", learn=True)
    """
    from dataclasses import replace

    from robots.robotfile import ROBOTS, load_robot, parse_robot

    def make():
        if isinstance(robot, dict):
            made = parse_robot({**robot, "name": name}, f"robot {name}")
        elif robot is None:
            from ekm.errors import InputError

            raise InputError(f"register_robot: robot {name!r} needs its parameters (a RobotParams, a dict or a file)")
        else:
            made = load_robot(robot)
        return replace(made, name=name, about=summary or made.about)

    return _register(ROBOTS, name, make)
