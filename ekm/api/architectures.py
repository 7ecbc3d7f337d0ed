"""Architectures in Python: :func:`architectures` (``ekm architectures``) lists them, and
:func:`register_architecture` adds your own beside the built-in ones.

An architecture is a parameter dataclass and a ``build`` that returns a
:class:`~robots.controllers.base.Controller`: ``init()`` gives the state, ``step(state, obs)`` gives
``(state, (left, right) wheel speeds in m/s)`` from an :class:`~robots.controllers.base.Observation` — the
IR readings, the current checkpoint as (α, d) from the robot, the pose, the time. The runner calls it every
0.128 s; write the step with ``jax.numpy`` and it is compiled once. docs/guide/architectures.md has a
worked example.
"""

from __future__ import annotations

from dataclasses import dataclass

from ekm.api.result import Result
from robots.controllers.spec import Architecture

__all__ = ["Architecture", "Architectures", "architectures", "register_architecture"]


@dataclass(frozen=True)
class Architectures(Result):
    """Every architecture the runner knows: ``rows``, each ``{name, summary, origin, map, encoding, parameters}``
    (``origin``: "built in", "added" in this process or "entry point"; ``map``: the charts of the EKM it
    drives, or None; ``encoding``: "continuous", "discrete" or None (Arkin §3.3); ``parameters``: ``[{name, type, default, choices, help}]``). ``to_dict()`` is
    ``ekm architectures --json``."""

    rows: tuple

    def _dict(self) -> dict:
        return {"architectures": list(self.rows)}

    def names(self) -> list[str]:
        return [r["name"] for r in self.rows]


def architectures() -> Architectures:
    """The built-in architectures, those of installed packages (entry-point group ``ekm.architectures``) and
    those added with :func:`register_architecture`, in that order."""
    from robots.controllers import spec

    table = spec.registry()
    rows = []
    for name, arch in table.items():
        origin = "built in" if name in spec.ARCHITECTURES else ("added" if name in spec.added_here() else "entry point")
        rows.append({"name": name, "summary": arch.summary, "origin": origin,
                     "map": list(arch.charts) or None, "encoding": arch.encoding,
                     "parameters": spec.describe_parameters(name)})
    return Architectures(rows=tuple(rows))


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
        What was registered. ``ekm.compare``'s worker processes get it with their runs, so define
        ``params`` and ``build`` at the top level of a module (or of the script), where pickle finds them.

    Examples
    --------
    ::

        ekm.register_architecture("wander", WanderParams, build_wander, "go to the checkpoint, turn from walls")
        ekm.compare(["concave-obstacle"], "wander,fields", trials=4)
    """
    from robots.controllers.spec import Architecture, register

    if isinstance(name, Architecture):
        return register(name)
    return register(Architecture(name=name, params=params, build=build, summary=summary, default_chart=chart,
                                 charts=tuple(charts), encoding=encoding))
