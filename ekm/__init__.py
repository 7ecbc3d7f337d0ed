"""Extended Kohonen Maps for learned sensorimotor control of a Khepera-like robot (Low 2002).

Everything the ``ekm`` command line does, from Python (each command is a thin wrapper over one of these)::

    import ekm
    maps = ekm.load()                                   # the shipped indirect map, 5 trials
    outcome = ekm.run(ekm.world("concave-obstacle"), architecture="fields", maps=maps, seed=1)
    outcome.reached, outcome.time_s
    outcome.save_plot("run.png")

=====================================  ==========================  ==================================
function                               returns                     command line
=====================================  ==========================  ==================================
``train(mapping=, steps=, ...)``       :class:`Maps`               ``ekm train``
``resume(checkpoint)``                 :class:`Maps`               ``ekm train --resume``
``load(path=None)``, ``Maps.save``     :class:`Maps`               (map files)
``evaluate(maps, targets=, seed=)``    :class:`Metrics`            ``ekm evaluate``
``adapt(robots, maps=, steps=)``       :class:`AdaptationTable`    ``ekm adapt``
``world(name_or_path)``                ``World``                   (world files)
``worlds(check=None)``                 :class:`Worlds`             ``ekm worlds``
``generate(family, seed, ...)``        ``World``                   ``ekm worlds --generate``
``robot(name_or_path)``                ``RobotParams``             (robot files)
``robots(check=None)``                 :class:`Robots`             ``ekm robots``
``families()``                         :class:`Families`           ``ekm families``
``register_family(name, ...)``         (a family)                  (entry points: ``ekm.families``)
``register_robot(name, robot)``        ``RobotParams``             (entry points: ``ekm.robots``)
``plan(world, start, goal, ...)``      :class:`Plan`               ``ekm plan``
``run(world, architecture, ...)``      :class:`Outcome`            ``ekm run``
``compare(worlds, architectures)``     :class:`Table`              ``ekm compare``
``load_comparison(results)``           :class:`Table`              ``ekm compare --from``
``architectures()``                    :class:`Architectures`      ``ekm architectures``
``register_architecture(name, ...)``   (an architecture)           (entry points: ``ekm.architectures``)
``match(first, second, ...)``          :class:`MatchResult`        ``ekm match``
``tournament(players, ...)``           :class:`TournamentResult`   ``ekm tournament``
``players()``                          :class:`Players`            ``ekm players``
``register_player(name, ...)``         (a player)                  (entry points: ``ekm.players``)
``soccer_field(name_or_path)``         ``SoccerField``             (field files)
=====================================  ==========================  ==================================

Each result is a frozen dataclass whose ``to_dict()`` is the command's ``--json`` output, with
``plot()`` / ``save_plot(path)`` where a picture helps. Bad arguments raise :class:`InputError` with the
line the command line prints. ``import ekm`` stays light: these names are imported on first use, and
JAX and pymunk with them.
"""

__version__ = "0.1.0"

#: Public name -> the module of :mod:`ekm.api` (or :mod:`ekm.errors`) that holds it.
_EXPORTS = {
    "train": "ekm.api.training", "resume": "ekm.api.training",
    "load": "ekm.api.mapset", "Maps": "ekm.api.mapset", "Map": "ekm.api.mapset",
    "evaluate": "ekm.api.evaluation", "Metrics": "ekm.api.evaluation", "Evaluation": "ekm.api.evaluation",
    "world": "ekm.api.worlds", "worlds": "ekm.api.worlds", "Worlds": "ekm.api.worlds",
    "robot": "ekm.api.robots", "robots": "ekm.api.robots", "Robots": "ekm.api.robots",
    "generate": "ekm.api.worlds",
    "plan": "ekm.api.planning", "Plan": "ekm.api.planning",
    "run": "ekm.api.driving", "Outcome": "ekm.api.driving",
    "adapt": "ekm.api.adapting", "AdaptationTable": "ekm.api.adapting",
    "compare": "ekm.api.comparing", "Table": "ekm.api.comparing", "load_comparison": "ekm.api.comparing",
    "architectures": "ekm.api.catalogue", "Architectures": "ekm.api.catalogue",
    "register_architecture": "ekm.api.catalogue", "Architecture": "ekm.api.catalogue",
    "players": "ekm.api.catalogue", "Players": "ekm.api.catalogue", "register_player": "ekm.api.catalogue",
    "Player": "ekm.api.catalogue", "families": "ekm.api.catalogue", "Families": "ekm.api.catalogue",
    "register_family": "ekm.api.catalogue", "Family": "ekm.api.catalogue", "register_robot": "ekm.api.catalogue",
    "match": "ekm.api.soccer", "MatchResult": "ekm.api.soccer", "tournament": "ekm.api.soccer",
    "TournamentResult": "ekm.api.soccer", "soccer_field": "ekm.api.soccer",
    "InputError": "ekm.errors", "Interrupted": "ekm.errors",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'ekm' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # the next access is a plain attribute
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
